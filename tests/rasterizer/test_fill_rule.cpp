// Setup and rasterization: the top-left fill rule, snapping to the profile's subpixel
// bits and culling (docs/hardware.md, "Setup and rasterization").
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "raster_test_util.h"

namespace rg::testing {
namespace {

using namespace rg::raster;

// Additive blending of (1, 0, 0, 0) per triangle: a pixel's red is how often it was hit.
PipelineState countingState() {
    PipelineState s = plainState();
    s.blend = 1;
    s.srcBlend = BlendFactor::One;
    s.dstBlend = BlendFactor::One;
    return s;
}

int64_t snapBits(float x, int bits) {
    return int64_t(std::floor(double(x) * double(1 << bits) + 0.5));
}

class FillRule : public ::testing::TestWithParam<Path> {};

// Two triangles sharing a diagonal cover a rectangle: every pixel whose centre lies in
// [left, right) × [top, bottom) of the snapped rectangle once, no other pixel, whichever
// diagonal and winding is used.
TEST_P(FillRule, RectangleFromTwoTrianglesHasNoGapsAndNoDoubleHits) {
    std::mt19937 rng(1234);
    std::uniform_real_distribution<float> coord(0.0f, 40.0f);
    for (int iter = 0; iter < 400; ++iter) {
        // 4 subpixel bits (GeForce 256) and 8 (GeForce 8800) on alternate pairs.
        const Profile& prof = profile((iter & 4) ? ProfileId::GeForce8800 : ProfileId::GeForce256);
        const int bits = prof.subpixelBits;
        Device dev(prof, 48, 44, DepthFormat::None, {GetParam(), 2});
        dev.setState(countingState());
        float x0 = coord(rng), x1 = coord(rng), y0 = coord(rng), y1 = coord(rng);
        if (x0 > x1) std::swap(x0, x1);
        if (y0 > y1) std::swap(y0, y1);
        const Rgba8 one{1, 0, 0, 0};
        Vertex a = tv(x0, y0, 0.5f, 1, one), b = tv(x1, y0, 0.5f, 1, one),
               c = tv(x1, y1, 0.5f, 1, one), d = tv(x0, y1, 0.5f, 1, one);
        std::vector<Vertex> tris = (iter & 1) ? std::vector<Vertex>{a, b, c, a, c, d}
                                              : std::vector<Vertex>{a, b, d, b, c, d};
        if (iter & 2) std::swap(tris[1], tris[2]);  // the other winding
        dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tris);
        int expected = 0;
        const int64_t one_ = int64_t{1} << bits, half = one_ / 2;
        for (int y = 0; y < 44; ++y)
            for (int x = 0; x < 48; ++x) {
                int64_t sx = x * one_ + half, sy = y * one_ + half;
                bool in = sx >= snapBits(x0, bits) && sx < snapBits(x1, bits) &&
                          sy >= snapBits(y0, bits) && sy < snapBits(y1, bits);
                expected += in;
                ASSERT_EQ(dev.framebuffer().pixel(x, y).r, in ? 1 : 0)
                    << "pixel (" << x << ", " << y << ") rect " << x0 << "," << y0 << " " << x1
                    << "," << y1 << " iteration " << iter << " (seed 1234, " << prof.name << ")";
            }
        EXPECT_EQ(dev.counters().fragmentsGenerated, uint64_t(expected));
    }
}

// Two triangulations of the same convex polygon (a fan from its centre, a fan from a
// corner) cover the same pixels, each once.
TEST_P(FillRule, TriangulationsOfAPolygonCoverTheSamePixelsOnce) {
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int iter = 0; iter < 100; ++iter) {
        Device dev(geforce256(), 64, 64, DepthFormat::None, {GetParam(), 3});
        dev.setState(countingState());
        const int n = 3 + iter % 9;
        const float cx = 20 + 24 * u(rng), cy = 20 + 24 * u(rng), r = 2 + 18 * u(rng);
        const float phase = 6.2831853f * u(rng);
        std::vector<Vertex> ring;
        for (int k = 0; k < n; ++k) {
            float ang = phase + 6.2831853f * float(k) / float(n);
            ring.push_back(tv(cx + r * std::cos(ang), cy + r * std::sin(ang)));
        }
        std::vector<Vertex> centreFan = {tv(cx, cy, 0.5f, 1, {1, 0, 0, 0})};
        for (int k = 0; k <= n; ++k) {
            Vertex v = ring[k % n];
            v.diffuse = {1, 0, 0, 0};
            centreFan.push_back(v);
        }
        std::vector<Vertex> cornerFan;
        for (int k = 0; k < n; ++k) {
            Vertex v = ring[k];
            v.diffuse = {0, 1, 0, 0};
            cornerFan.push_back(v);
        }
        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, centreFan);
        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, cornerFan);
        const Framebuffer& fb = dev.framebuffer();
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                Rgba8 p = fb.pixel(x, y);
                ASSERT_LE(p.r, 1) << "double hit at (" << x << ", " << y << ") iteration " << iter;
                ASSERT_EQ(p.r, p.g) << "the two triangulations differ at (" << x << ", " << y
                                    << ") iteration " << iter << " (seed 99)";
            }
    }
}

// Pixel centres exactly on an edge: the hypotenuse of (0,0) (4,0) (0,4) is a right edge
// and excludes its centres; the other half of the square, whose hypotenuse is a left
// edge, takes them. 6 + 10 = 16 pixels.
TEST_P(FillRule, CentresOnAnEdgeBelongToTheTopLeftTriangle) {
    Device dev(geforce256(), 8, 8, DepthFormat::None, {GetParam(), 2});
    dev.setState(countingState());
    std::vector<Vertex> lower = {tv(0, 0, 0.5f, 1, {1, 0, 0, 0}), tv(4, 0, 0.5f, 1, {1, 0, 0, 0}),
                                 tv(0, 4, 0.5f, 1, {1, 0, 0, 0})};
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, lower);
    EXPECT_EQ(dev.counters().fragmentsGenerated, 6u);
    EXPECT_EQ(dev.framebuffer().pixel(1, 2).r, 0) << "centre (1.5, 2.5) lies on the right edge";
    std::vector<Vertex> upper = {tv(4, 4, 0.5f, 1, {1, 0, 0, 0}), tv(0, 4, 0.5f, 1, {1, 0, 0, 0}),
                                 tv(4, 0, 0.5f, 1, {1, 0, 0, 0})};
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, upper);
    EXPECT_EQ(dev.counters().fragmentsGenerated, 16u);
    EXPECT_EQ(dev.framebuffer().pixel(1, 2).r, 1);
    EXPECT_EQ(countIf(dev.framebuffer(), [](Rgba8 p) { return p.r == 1; }), 16);
}

TEST_P(FillRule, IntegerSquareCoversExactlyItsPixels) {
    Device dev(geforce256(), 32, 32, DepthFormat::None, {GetParam(), 2});
    dev.setState(plainState());
    std::vector<Vertex> q = {tv(3, 5), tv(13, 5), tv(13, 15), tv(3, 15)};
    dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
    EXPECT_EQ(dev.counters().fragmentsGenerated, 100u);
    EXPECT_EQ(countIf(dev.framebuffer(), [](Rgba8 p) { return p.r == 255; }), 100);
    EXPECT_EQ(dev.framebuffer().pixel(3, 5).r, 255);
    EXPECT_EQ(dev.framebuffer().pixel(13, 5).r, 0);
    EXPECT_EQ(dev.framebuffer().pixel(3, 15).r, 0);
}

INSTANTIATE_TEST_SUITE_P(RasterFillRule, FillRule,
                         ::testing::Values(Path::Reference, Path::Fast),
                         [](const auto& info) { return std::string(pathName(info.param)); });

// Snapping follows Profile::subpixelBits: a left edge at x = 10.52 snaps to 10.5 with 4
// bits (the GeForce 256 takes column 10, whose centre is on the edge) and to 10.51953
// with 8 bits (the GeForce 8800 does not).
TEST(RasterSubpixelSnap, EdgePositionFollowsTheProfilesSubpixelBits) {
    for (ProfileId id : {ProfileId::GeForce256, ProfileId::GeForce8800}) {
        Device dev(profile(id), 32, 8, DepthFormat::None, {Path::Reference, 1});
        dev.setState(plainState());
        std::vector<Vertex> q = {tv(10.52f, 0), tv(20, 0), tv(20, 8), tv(10.52f, 8)};
        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
        int expected = id == ProfileId::GeForce256 ? 255 : 0;
        EXPECT_EQ(dev.framebuffer().pixel(10, 3).r, expected) << profile(id).name;
        EXPECT_EQ(dev.framebuffer().pixel(11, 3).r, 255) << profile(id).name;
    }
}

// D3DCULL: CW culls triangles clockwise on screen (y down), CCW the others.
TEST(RasterCull, WindingSelectsWhatIsCulled) {
    const std::vector<Vertex> cw = {tv(0, 0), tv(8, 0), tv(0, 8)};
    const std::vector<Vertex> ccw = {tv(0, 0), tv(0, 8), tv(8, 0)};
    for (Path path : {Path::Reference, Path::Fast})
        for (CullMode mode : {CullMode::None, CullMode::CW, CullMode::CCW}) {
            Device dev(geforce256(), 16, 16, DepthFormat::None, {path, 2});
            PipelineState s = plainState();
            s.cull = mode;
            dev.setState(s);
            dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, cw);
            dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, ccw);
            uint64_t culled = mode == CullMode::None ? 0 : 1;
            EXPECT_EQ(dev.counters().trianglesCulled, culled) << int(mode);
            EXPECT_EQ(dev.counters().trianglesDrawn, 2 - culled) << int(mode);
            // 8·9/2 − 8 centres on the diagonal (excluded, right edge) = 28 per triangle
            EXPECT_EQ(dev.counters().fragmentsGenerated, (2 - culled) * 28) << int(mode);
        }
}

}  // namespace
}  // namespace rg::testing
