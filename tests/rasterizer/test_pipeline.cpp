// The pipeline end to end: clipping and the guard band, interpolation, flat shading,
// viewport and scissor, clears and pixel transfer, passes and counters, refused input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "raster_test_util.h"

namespace rg::testing {
namespace {

using namespace rg::raster;

Vertex ov(float x, float y, float z, Rgba8 c = {255, 255, 255, 255}) {
    Vertex v;
    v.position = {x, y, z, 1.0f};
    v.diffuse = c;
    return v;
}


class PipelinePaths : public ::testing::TestWithParam<Path> {
  protected:
    DeviceOptions opts() const { return {GetParam(), 2}; }
};

// ---- clipping --------------------------------------------------------------------------
// Identity transforms: clip = (x, y, z, 1). A full-screen quad whose z runs from −1 at
// the left to +1 at the right crosses the near plane z = 0 at window x = W/2.
TEST_P(PipelinePaths, ClippingNearPlaneKeepsTheFrontHalf) {
    Device dev(geforce256(), 32, 16, DepthFormat::None, opts());
    dev.setState(plainState());
    std::vector<Vertex> q = {ov(-1, 1, -1), ov(1, 1, 1), ov(1, -1, 1), ov(-1, -1, -1)};
    dev.draw(Primitive::TriangleFan, VertexSpace::Untransformed, q);
    EXPECT_EQ(dev.counters().trianglesClipped, 2u);
    EXPECT_EQ(dev.counters().trianglesDrawn, 2u);
    EXPECT_EQ(dev.counters().fragmentsGenerated, 16u * 16u);
    EXPECT_EQ(dev.framebuffer().pixel(15, 8).r, 0);
    EXPECT_EQ(dev.framebuffer().pixel(16, 8).r, 255);
}

// The near plane exactly at z = 0: a quad with z = ½(x − x_b) crosses it at ndc x_b, placed
// 0.05 pixel right of column 127's centre on a 256-wide target, so column 127 is outside
// and column 128 inside. A plane shifted by a thousandth of w (0.26 pixel here) flips
// column 127.
TEST_P(PipelinePaths, ClippingNearPlaneIsExactlyZZero) {
    Device dev(geforce256(), 256, 8, DepthFormat::None, opts());
    dev.setState(plainState());
    const float xb = -0.5f / 128.0f + 0.05f / 128.0f;
    auto z = [&](float x) { return 0.5f * (x - xb); };
    std::vector<Vertex> q = {ov(-1, 1, z(-1)), ov(1, 1, z(1)), ov(1, -1, z(1)), ov(-1, -1, z(-1))};
    dev.draw(Primitive::TriangleFan, VertexSpace::Untransformed, q);
    for (int y = 0; y < 8; ++y) {
        EXPECT_EQ(dev.framebuffer().pixel(127, y).r, 0) << "row " << y;
        EXPECT_EQ(dev.framebuffer().pixel(128, y).r, 255) << "row " << y;
    }
    EXPECT_EQ(dev.counters().fragmentsGenerated, 128u * 8u);
}

TEST_P(PipelinePaths, ClippingBehindTheEyeIsCulled) {
    Device dev(geforce256(), 32, 16, DepthFormat::None, opts());
    dev.setState(plainState());
    dev.setTransforms(glm::mat4(1.0f), glm::mat4(1.0f),
                      glm::perspectiveLH_ZO(1.0f, 2.0f, 0.1f, 100.0f));
    std::vector<Vertex> tri = {ov(-1, -1, -2), ov(1, -1, -2), ov(0, 1, -3)};
    dev.draw(Primitive::TriangleList, VertexSpace::Untransformed, tri);
    EXPECT_EQ(dev.counters().trianglesCulled, 1u);
    EXPECT_EQ(dev.counters().fragmentsGenerated, 0u);
    // The same triangle in front of the eye is drawn.
    std::vector<Vertex> front = {ov(-1, -1, 2), ov(1, -1, 2), ov(0, 1, 3)};
    dev.draw(Primitive::TriangleList, VertexSpace::Untransformed, front);
    EXPECT_EQ(dev.counters().trianglesDrawn, 1u);
    EXPECT_GT(dev.counters().fragmentsGenerated, 0u);
}

// Far outside the ±16384 pixel guard band: clipped, and still covers every pixel.
TEST_P(PipelinePaths, ClippingGuardBandForHugeTriangles) {
    for (VertexSpace space : {VertexSpace::Untransformed, VertexSpace::Pretransformed}) {
        Device dev(geforce256(), 40, 24, DepthFormat::None, opts());
        dev.setState(plainState());
        float big = space == VertexSpace::Untransformed ? 1e4f : 1e6f;
        std::vector<Vertex> tri = {ov(-big, -big, 0.5f), ov(big * 3, -big, 0.5f),
                                   ov(-big, big * 3, 0.5f)};
        dev.draw(Primitive::TriangleList, space, tri);
        EXPECT_EQ(dev.counters().trianglesClipped, 1u);
        EXPECT_EQ(dev.counters().fragmentsGenerated, 40u * 24u);
        EXPECT_EQ(countIf(dev.framebuffer(), [](Rgba8 p) { return p.g == 255; }), 40 * 24);
    }
}

TEST_P(PipelinePaths, ClippingDropsNanAndInfVerticesAndCountsThem) {
    Device dev(geforce256(), 16, 16, DepthFormat::None, opts());
    dev.setState(plainState());
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<Vertex> tris = {tv(0, 0), tv(nan, 0), tv(0, 8),   tv(0, 0), tv(8, 0), tv(0, inf),
                                tv(0, 0, 0.5f, 0), tv(8, 0), tv(0, 8),  // RHW 0: w infinite
                                tv(0, 0), tv(8, 0), tv(0, 8)};
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tris);
    std::vector<Vertex> obj = {ov(0, 0, 0.5f), ov(inf, 0, 0.5f), ov(0, 1, 0.5f)};
    dev.draw(Primitive::TriangleList, VertexSpace::Untransformed, obj);
    EXPECT_EQ(dev.counters().trianglesSubmitted, 5u);
    EXPECT_EQ(dev.counters().trianglesInvalid, 4u);
    EXPECT_EQ(dev.counters().trianglesDrawn, 1u);
}

// ---- interpolation ---------------------------------------------------------------------
// Red 255 at the vertex with RHW 1/4, 0 at the two with RHW 1: perspective-correct
// red = 255·b1/4 / (b0 + b1/4 + b2) from the screen barycentrics; linear red = 255·b1.
TEST_P(PipelinePaths, InterpolationPerspectiveCorrectAndLinearColours) {
    for (int persp = 0; persp < 2; ++persp) {
        Device dev(geforce256(), 64, 64, DepthFormat::None, opts());
        PipelineState s = plainState();
        s.perspectiveColor = uint8_t(persp);
        dev.setState(s);
        std::vector<Vertex> tri = {tv(0, 0, 0.5f, 1.0f, {0, 0, 0, 255}),
                                   tv(64, 0, 0.5f, 0.25f, {255, 0, 0, 255}),
                                   tv(0, 64, 0.5f, 1.0f, {0, 0, 0, 255})};
        dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
        int checked = 0;
        for (int y = 0; y < 64; y += 5)
            for (int x = 0; x + y < 63; x += 3) {
                double b1 = (x + 0.5) / 64.0, b2 = (y + 0.5) / 64.0, b0 = 1 - b1 - b2;
                double expected = persp ? 255.0 * b1 * 0.25 / (b0 + b1 * 0.25 + b2) : 255.0 * b1;
                EXPECT_NEAR(dev.framebuffer().pixel(x, y).r, expected, 0.5 + 1e-3)
                    << "pixel (" << x << ", " << y << ") perspective " << persp;
                ++checked;
            }
        EXPECT_GT(checked, 100);
    }
}

// D3D7 flat shading takes the first vertex of each list or strip triangle and the second
// of each fan triangle.
TEST_P(PipelinePaths, FlatShadingUsesTheProvokingVertex) {
    const Rgba8 c0{10, 0, 0, 255}, c1{20, 0, 0, 255}, c2{30, 0, 0, 255}, c3{40, 0, 0, 255};
    struct Case {
        Primitive prim;
        uint8_t first, second;
    } cases[] = {{Primitive::TriangleStrip, 10, 20}, {Primitive::TriangleFan, 20, 30}};
    for (const Case& c : cases) {
        Device dev(geforce256(), 16, 16, DepthFormat::None, opts());
        PipelineState s = plainState();
        s.shade = ShadeMode::Flat;
        dev.setState(s);
        // Strip: triangles (0,1,2) upper-left and (1,2,3) lower-right of a square.
        // Fan: (0,1,2) and (0,2,3) for the square's corners in order.
        std::vector<Vertex> v =
            c.prim == Primitive::TriangleStrip
                ? std::vector<Vertex>{tv(0, 0, .5f, 1, c0), tv(16, 0, .5f, 1, c1),
                                      tv(0, 16, .5f, 1, c2), tv(16, 16, .5f, 1, c3)}
                : std::vector<Vertex>{tv(0, 0, .5f, 1, c0), tv(16, 0, .5f, 1, c1),
                                      tv(16, 16, .5f, 1, c2), tv(0, 16, .5f, 1, c3)};
        dev.draw(c.prim, VertexSpace::Pretransformed, v);
        const Framebuffer& fb = dev.framebuffer();
        if (c.prim == Primitive::TriangleStrip) {
            EXPECT_EQ(fb.pixel(2, 2).r, c.first);
            EXPECT_EQ(fb.pixel(13, 13).r, c.second);
        } else {
            EXPECT_EQ(fb.pixel(13, 2).r, c.first);
            EXPECT_EQ(fb.pixel(2, 13).r, c.second);
        }
    }
}

// ---- viewport, scissor, clears ---------------------------------------------------------
TEST_P(PipelinePaths, ViewportMapsClipSpaceOntoItsRectangle) {
    Device dev(geforce256(), 32, 32, DepthFormat::None, opts());
    dev.setState(plainState());
    dev.setViewport({8, 4, 16, 8, 0.0f, 1.0f});
    std::vector<Vertex> q = {ov(-1, 1, .5f), ov(1, 1, .5f), ov(1, -1, .5f), ov(-1, -1, .5f)};
    dev.draw(Primitive::TriangleFan, VertexSpace::Untransformed, q);
    EXPECT_EQ(dev.counters().fragmentsGenerated, 128u);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x)
            ASSERT_EQ(dev.framebuffer().pixel(x, y).r, (x >= 8 && x < 24 && y >= 4 && y < 12) ? 255 : 0)
                << x << "," << y;
}

TEST_P(PipelinePaths, ScissorLimitsDrawsAndClears) {
    Device dev(geforce256(), 16, 16, DepthFormat::D16, opts());
    PipelineState s = plainState();
    s.scissorTest = 1;
    dev.setState(s);
    dev.setScissor({2, 3, 5, 7});
    dev.clear(true, {1, 1, 1, 1}, true, 0.25f);
    EXPECT_EQ(countIf(dev.framebuffer(), [](Rgba8 p) { return p.r == 1; }), 35);
    EXPECT_EQ(dev.framebuffer().depth()[3 * 16 + 2], 16384u);  // floor(0.25·65535 + ½)
    EXPECT_EQ(dev.framebuffer().depth()[0], 65535u);
    std::vector<Vertex> q = {tv(0, 0), tv(16, 0), tv(16, 16), tv(0, 16)};
    dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
    EXPECT_EQ(dev.counters().fragmentsGenerated, 35u);
    EXPECT_EQ(countIf(dev.framebuffer(), [](Rgba8 p) { return p.r == 255; }), 35);
}

// Pinned in docs/hardware.md: an untransformed vertex's w is ignored (the object position
// is (x, y, z, 1)), so w = 0, NaN or 7 draws what w = 1 draws.
TEST_P(PipelinePaths, UntransformedPositionWIsIgnored) {
    std::string expected;
    for (float w : {1.0f, 0.0f, std::numeric_limits<float>::quiet_NaN(), 7.0f}) {
        Device dev(geforce256(), 16, 16, DepthFormat::None, opts());
        dev.setState(plainState());
        std::vector<Vertex> tri = {ov(-0.9f, 0.8f, 0.5f, {255, 0, 0, 255}), ov(0.7f, 0.6f, 0.5f, {0, 255, 0, 255}),
                                   ov(-0.2f, -0.9f, 0.5f, {0, 0, 255, 255})};
        for (Vertex& v : tri) v.position.w = w;
        dev.draw(Primitive::TriangleList, VertexSpace::Untransformed, tri);
        EXPECT_EQ(dev.counters().trianglesDrawn, 1u) << "w = " << w;
        const std::string h = frameHash(dev.framebuffer());
        if (expected.empty()) expected = h;
        EXPECT_EQ(h, expected) << "w = " << w;
    }
}

// Pinned: depthWrite with the depth test off writes nothing (D3DRS_ZENABLE = FALSE).
TEST_P(PipelinePaths, DepthWriteWithTheTestOffWritesNothing) {
    Device dev(geforce256(), 8, 8, DepthFormat::D16, opts());
    PipelineState s = plainState();
    s.depthTest = 0;
    s.depthWrite = 1;
    dev.setState(s);
    dev.clear(false, {}, true, 0.75f);
    std::vector<Vertex> q = {tv(0, 0), tv(8, 0), tv(8, 8), tv(0, 8)};  // z = 0.5
    dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
    EXPECT_EQ(countIf(dev.framebuffer(), [](Rgba8 p) { return p.r == 255; }), 64);  // drawn
    for (uint32_t z : dev.framebuffer().depth()) ASSERT_EQ(z, 49151u);  // floor(0.75·65535 + ½): untouched
    s.depthTest = 1;
    dev.setState(s);
    dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
    EXPECT_EQ(dev.framebuffer().depth()[0], 32768u);  // with the test on it writes
}

INSTANTIATE_TEST_SUITE_P(Pipeline, PipelinePaths, ::testing::Values(Path::Reference, Path::Fast),
                         [](const auto& info) { return std::string(pathName(info.param)); });

// ---- pixel transfer --------------------------------------------------------------------
TEST(PixelTransfer, DrawCopyAndReadBackRoundTrip) {
    Device dev(geforce256(), 16, 8, DepthFormat::None);
    std::vector<Rgba8> img(6 * 4);
    for (size_t i = 0; i < img.size(); ++i) img[i] = Rgba8{uint8_t(i), uint8_t(2 * i), 7, 255};
    dev.drawPixels(1, 2, 6, 4, img);
    EXPECT_EQ(dev.readPixels(1, 2, 6, 4), img);
    EXPECT_EQ(dev.counters().bytesReadBack, 6u * 4u * 4u);
    dev.copyPixels(1, 2, 6, 4, 3, 3);  // overlapping: copies as if through a temporary
    EXPECT_EQ(dev.readPixels(3, 3, 6, 4), img);
    EXPECT_EQ(dev.counters().bytesReadBack, 2u * 6u * 4u * 4u);
    dev.drawPixels(14, 6, 6, 4, img);  // clipped at the target's edge, no crash
    EXPECT_EQ(dev.framebuffer().pixel(15, 7), img[1 * 6 + 1]);
    EXPECT_THROW(dev.readPixels(12, 0, 6, 4), InvalidState);
    EXPECT_THROW(dev.copyPixels(12, 0, 6, 4, 0, 0), InvalidState);  // a source past the target
}

// Pixel transfers take no per-fragment state (docs/trace-format.md, "Pixel transfers"): a
// viewport and scissor elsewhere, every channel masked, an alpha test and a depth test
// that would fail, a blend that would zero the colour, leave drawPixels and copyPixels
// writing every pixel as given.
TEST(PixelTransfer, NoPerFragmentStateApplies) {
    Device dev(geforce256(), 16, 8, DepthFormat::D16);
    PipelineState s = plainState();
    s.colorWriteMask = 0;
    s.alphaTest = 1;
    s.alphaFunc = CompareFunc::Never;
    s.depthTest = 1;
    s.depthFunc = CompareFunc::Never;
    s.blend = 1;
    s.srcBlend = BlendFactor::Zero;
    s.dstBlend = BlendFactor::Zero;
    s.scissorTest = 1;
    dev.setState(s);
    dev.setViewport({12, 6, 2, 2, 0.0f, 1.0f});
    dev.setScissor({0, 0, 1, 1});
    std::vector<Rgba8> img(6 * 4);
    for (size_t i = 0; i < img.size(); ++i) img[i] = Rgba8{uint8_t(i + 1), uint8_t(2 * i), 7, uint8_t(9 * i)};
    dev.drawPixels(1, 2, 6, 4, img);
    EXPECT_EQ(dev.readPixels(1, 2, 6, 4), img);
    dev.copyPixels(1, 2, 6, 4, 9, 0);
    EXPECT_EQ(dev.readPixels(9, 0, 6, 4), img);
}

// ---- frames, passes, counters ----------------------------------------------------------
TEST(Passes, ObserverSeesEachPassOnce) {
    Device dev(geforce256(), 8, 8, DepthFormat::None);
    std::vector<std::string> seen;
    dev.setPassObserver([&](const PassRecord& p, const Framebuffer&) {
        seen.push_back(p.label + ":" + std::to_string(p.drawCalls));
    });
    dev.setState(plainState());
    std::vector<Vertex> tri = {tv(0, 0), tv(8, 0), tv(0, 8)};
    dev.beginFrame();
    dev.beginPass("base");
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
    dev.beginPass("reflection");
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
    dev.endFrame();
    EXPECT_EQ(seen, (std::vector<std::string>{"base:1", "reflection:2"}));
    EXPECT_EQ(dev.counters().passes, 2u);
    EXPECT_EQ(dev.counters().drawCalls, 3u);
    dev.beginFrame();
    EXPECT_EQ(dev.counters().drawCalls, 0u);
    EXPECT_TRUE(dev.passes().empty());
}

// The instrumentation hook sees every rasterized quad once, with the written pixels.
TEST(FragmentObserver, SeesEveryQuadAndTheWrittenPixels) {
    for (Path path : {Path::Reference, Path::Fast}) {
        Device dev(geforce256(), 16, 16, DepthFormat::D16, {path, 2});
        PipelineState s = plainState();
        s.depthTest = 1;
        s.depthFunc = CompareFunc::Less;
        dev.setState(s);
        dev.clear(true, {}, true, 0.5f);
        uint64_t quads = 0, written = 0;
        dev.setFragmentObserver([&](const tex::FragmentQuad& q, uint8_t passed) {
            ++quads;
            EXPECT_EQ(passed & ~q.coverage, 0);
            written += uint64_t(__builtin_popcount(passed));
        });
        // Left half in front of the cleared depth, right half behind it.
        std::vector<Vertex> a = {tv(0, 0, 0.25f), tv(8, 0, 0.25f), tv(8, 16, 0.25f), tv(0, 16, 0.25f)};
        std::vector<Vertex> b = {tv(8, 0, 0.75f), tv(16, 0, 0.75f), tv(16, 16, 0.75f), tv(8, 16, 0.75f)};
        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, a);
        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, b);
        EXPECT_EQ(written, 128u);
        EXPECT_EQ(written, dev.counters().fragmentsWritten);
        EXPECT_GE(quads, 64u);  // 2 × 32 quads, plus quads split between two triangles
        dev.setFragmentObserver({});
        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, a);
        EXPECT_EQ(written, 128u);
    }
}

// ---- refused input ---------------------------------------------------------------------
TEST(BadInput, ImpossibleStateIsRefusedWithItsName) {
    EXPECT_THROW(Device(geforce256(), 0, 8, DepthFormat::None), InvalidState);
    EXPECT_THROW(Device(geforce256(), 4096, 8, DepthFormat::None), InvalidState);
    EXPECT_NO_THROW(Device(profile(ProfileId::GeForce8800), 4096, 8, DepthFormat::None));
    Device dev(geforce256(), 16, 16, DepthFormat::D16);
    EXPECT_THROW(dev.setViewport({0, 0, 0, 8, 0, 1}), InvalidState);
    EXPECT_THROW(dev.setViewport({8, 8, 16, 16, 0, 1}), InvalidState);
    EXPECT_THROW(dev.setViewport({0, 0, 8, 8, 0, 2}), InvalidState);
    EXPECT_THROW(dev.setScissor({0, 0, -1, 8}), InvalidState);
    std::vector<Vertex> tri = {tv(0, 0), tv(8, 0), tv(0, 8)};
    auto expectRefused = [&](PipelineState s, const std::string& name) {
        dev.setState(s);
        try {
            dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
            ADD_FAILURE() << "state accepted: " << name;
        } catch (const InvalidState& e) {
            EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
        }
    };
    PipelineState s = plainState();
    s.srcBlend = BlendFactor(13);
    expectRefused(s, "source blend factor");
    s = plainState();
    s.depthFunc = CompareFunc(8);
    expectRefused(s, "depth function");
    s = plainState();
    s.cull = CullMode(3);
    expectRefused(s, "cull mode");
    s = plainState();
    s.colorWriteMask = 16;
    expectRefused(s, "write mask");
    s = plainState();
    s.blend = 1;
    s.dstBlend = BlendFactor::BothSrcAlpha;
    expectRefused(s, "BOTHSRCALPHA");
    dev.setState(plainState());
    std::vector<uint32_t> badIndex = {0, 1, 7};
    EXPECT_THROW(dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri, badIndex),
                 InvalidState);
    EXPECT_THROW(dev.clear(false, {}, true, 2.0f), InvalidState);
    EXPECT_EQ(dev.counters().fragmentsGenerated, 0u);
}

// Rectangles near the int32 limits: nothing overflows, nothing outside is touched.
TEST(BadInput, ExtremeRectanglesDoNotOverflow) {
    const int big = std::numeric_limits<int>::max();
    for (Path path : {Path::Reference, Path::Fast}) {
        Device dev(geforce256(), 16, 16, DepthFormat::D16, {path, 2});
        PipelineState s = plainState();
        s.scissorTest = 1;
        dev.setState(s);
        dev.setScissor({big - 5, big - 5, big, big});
        dev.clear(true, {9, 9, 9, 9}, true, 0.0f);
        std::vector<Vertex> q = {tv(0, 0), tv(16, 0), tv(16, 16), tv(0, 16)};
        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
        EXPECT_EQ(dev.counters().fragmentsGenerated, 0u);
        dev.setScissor({-1000, -1000, big, big});  // right edge −1000 + big
        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
        EXPECT_EQ(dev.counters().fragmentsGenerated, 256u);
        std::vector<Rgba8> px(4, Rgba8{1, 2, 3, 4});
        dev.drawPixels(big - 1, big - 1, 2, 2, px);
        dev.drawPixels(-big, -big, 2, 2, px);
        EXPECT_EQ(countIf(dev.framebuffer(), [](Rgba8 p) { return p.r == 255; }), 256);
    }
}

// ---- golden frame ----------------------------------------------------------------------
TEST(Sha256, KnownVectors) {
    EXPECT_EQ(sha256Hex("", 0), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    EXPECT_EQ(sha256Hex("abc", 3), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    const char* fox = "The quick brown fox jumps over the lazy dog";
    EXPECT_EQ(sha256Hex(fox, 43), "d7a8fbb307d7809469ca9abcb0082e4f8d5651e46d3cdb762d02d0bf37c9e592");
}

// Gouraud, perspective-correct, depth-tested and blended triangles on a GeForce 256:
// the bytes of colour and depth are pinned (any change to docs/hardware.md's arithmetic
// must update this hash deliberately).
TEST(GoldenFrame, GouraudDepthBlendFrameHash) {
    for (Path path : {Path::Reference, Path::Fast}) {
        Device dev(geforce256(), 32, 24, DepthFormat::D24, {path, 2});
        PipelineState s;
        s.cull = CullMode::None;
        s.blend = 1;
        s.srcBlend = BlendFactor::SrcAlpha;
        s.dstBlend = BlendFactor::InvSrcAlpha;
        dev.setState(s);
        dev.clear(true, {20, 40, 60, 255}, true, 1.0f);
        std::vector<Vertex> tris = {
            tv(1.3f, 2.7f, 0.2f, 1.0f, {255, 0, 0, 200}), tv(30.1f, 5.5f, 0.6f, 0.5f, {0, 255, 0, 100}),
            tv(7.9f, 22.2f, 0.9f, 0.25f, {0, 0, 255, 255}),
            tv(31.0f, 23.0f, 0.1f, 1.0f, {255, 255, 0, 128}), tv(0.5f, 12.25f, 0.8f, 2.0f, {0, 255, 255, 60}),
            tv(20.0f, 0.0f, 0.4f, 1.0f, {255, 0, 255, 255})};
        dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tris);
        EXPECT_EQ(frameHash(dev.framebuffer()), "5c3c8a532b64cf2d6e9e1df4f9e9cfce474f9689065e2cf642cf33d14436f7aa/"
                  "6da0c54b1a97fbc21b0e1c3d4b4b27839d844e2329acd49ae7b7a82d2d910a6c") << pathName(path);
    }
}

}  // namespace
}  // namespace rg::testing
