// `retroglass view hybrid`: the demo draws every lens object with its layer passes and
// alpha clears on the viewer's device, τ and the layer count live.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "core/profile.h"
#include "hybrid_demo.h"
#include "rasterizer/device.h"

namespace rg::hybrid {
namespace {

HybridDemoSettings tiny() {
    HybridDemoSettings s;
    s.width = 96;
    s.height = 72;
    s.teapotLevel = 6;
    s.emSize = 16;
    s.clusterWidth = 24;
    s.clusterHeight = 18;
    return s;
}

// Pixels of the frame that a lens object drew (depth written) with a colour above black,
// on the left and right halves (the teapot is left of the cup from sample 40).
int litPixels(const raster::Device& d, int x0, int x1) {
    const auto& fb = d.framebuffer();
    int n = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = x0; x < x1; ++x) {
            const Rgba8 c = fb.pixel(x, y);
            n += fb.depth()[size_t(y) * size_t(fb.width()) + size_t(x)] < fb.depthMax() &&
                 c.r + c.g + c.b > 30;
        }
    return n;
}

TEST(HybridDemo, DrawsEveryLensObjectWithItsPassesAndTauAndLayersAreLive) {
    HybridDemo demo(viewer::DemoOptions{}, tiny());
    raster::Device device(profileByName(demo.defaultProfile()), demo.frameSize().first,
                          demo.frameSize().second, raster::DepthFormat::D24);
    const ray::Camera cam = demo.rig().start;
    demo.render(device, cam);
    int clears = 0, teapotPasses = 0;
    for (const raster::PassRecord& p : device.passes()) {
        clears += p.label.rfind("alpha clear", 0) == 0;
        teapotPasses += p.label.rfind("teapot ", 0) == 0;
    }
    EXPECT_EQ(teapotPasses, 6) << "on sample 40: 2 terms × 3 layers";
    EXPECT_EQ(clears, 1);
    const int w = device.framebuffer().width();
    EXPECT_GT(litPixels(device, 0, w), 300) << "the lens objects are drawn";
    // The teapot covers the upper half of the frame, the cup the lower.
    int upper = 0;
    for (int y = 0; y < device.framebuffer().height() / 2; ++y)
        for (int x = 0; x < w; ++x) {
            const Rgba8 c = device.framebuffer().pixel(x, y);
            upper += c.r + c.g + c.b > 30;
        }
    EXPECT_GT(upper, 200) << "the teapot (upper half) is drawn";
    // Between samples 40 and 41: 4n passes, three clears for the teapot, one for the cup.
    ray::Camera between = cam;
    {
        const glm::vec3 c = cam.target, d = cam.eye - c;
        const float a = glm::radians(4.0f);
        between.eye = c + glm::vec3(d.x * std::cos(a) - d.z * std::sin(a), d.y,
                                    d.x * std::sin(a) + d.z * std::cos(a));
    }
    viewer::FrameNotes notes = demo.render(device, between);
    clears = teapotPasses = 0;
    for (const raster::PassRecord& p : device.passes()) {
        clears += p.label.rfind("alpha clear", 0) == 0;
        teapotPasses += p.label.rfind("teapot ", 0) == 0;
    }
    EXPECT_EQ(teapotPasses, 12) << notes[0].second;
    EXPECT_EQ(clears, 4);
    int upperBetween = 0;
    for (int y = 0; y < device.framebuffer().height() / 2; ++y)
        for (int x = 0; x < w; ++x) {
            const Rgba8 c = device.framebuffer().pixel(x, y);
            upperBetween += c.r + c.g + c.b > 30;
        }
    EXPECT_GT(upperBetween, 200) << "the teapot is drawn between samples too";
    auto& params = demo.params();
    viewer::findParam(params, "tau").value = 12;
    viewer::FrameNotes coarse = demo.render(device, cam);
    viewer::findParam(params, "tau").value = 2;
    viewer::FrameNotes fine = demo.render(device, cam);
    ASSERT_FALSE(fine.empty());
    EXPECT_NE(coarse[1].second, fine[1].second) << "τ changes the tessellation";
    viewer::findParam(params, "layers").value = 1;
    demo.render(device, cam);
    teapotPasses = 0;
    for (const raster::PassRecord& p : device.passes()) teapotPasses += p.label.rfind("teapot ", 0) == 0;
    EXPECT_EQ(teapotPasses, 2) << "one layer, two terms";
}

}  // namespace
}  // namespace rg::hybrid
