// The per-fragment operations: blend factors and operations, depth compare and
// quantization, alpha test, write mask, specular add (docs/hardware.md, "Blending",
// "Depth", "Alpha test"). Oracles are one-line double-precision definitions written here
// independently of rasterizer/include/rasterizer/fragment_ops.h.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "raster_test_util.h"
#include "rasterizer/fragment_ops.h"

namespace rg::testing {
namespace {

using namespace rg::raster;

// round(x · f) for x in 0..255 and f in [0, 1] given as k/255, halves up.
uint32_t product(uint32_t x, double f) { return uint32_t(std::floor(double(x) * f + 0.5)); }

// The factor of `f` for channel c as the Direct3D 7 documentation defines it, in [0, 1].
double factorDefinition(BlendFactor f, int c, const double s[4], const double d[4]) {
    switch (f) {
        case BlendFactor::Zero: return 0;
        case BlendFactor::One: return 1;
        case BlendFactor::SrcColor: return s[c];
        case BlendFactor::InvSrcColor: return 1 - s[c];
        case BlendFactor::SrcAlpha: return s[3];
        case BlendFactor::InvSrcAlpha: return 1 - s[3];
        case BlendFactor::DestAlpha: return d[3];
        case BlendFactor::InvDestAlpha: return 1 - d[3];
        case BlendFactor::DestColor: return d[c];
        case BlendFactor::InvDestColor: return 1 - d[c];
        case BlendFactor::SrcAlphaSat: return c == 3 ? 1.0 : std::min(s[3], 1 - d[3]);
        case BlendFactor::BothSrcAlpha: return s[3];
        case BlendFactor::BothInvSrcAlpha: return 1 - s[3];
    }
    return -1;
}

// Source and destination colours built from the pair (u, v) so that every channel and
// both alphas sweep all 256 values over the 65,536 pairs.
void colours(uint32_t u, uint32_t v, Rgba8& s, Rgba8& d) {
    s = Rgba8{uint8_t(u), uint8_t(v), uint8_t(u ^ v), uint8_t(v)};
    d = Rgba8{uint8_t(v), uint8_t(u), uint8_t(255 - u), uint8_t(u)};
}

constexpr BlendFactor kAllFactors[] = {
    BlendFactor::Zero,        BlendFactor::One,          BlendFactor::SrcColor,
    BlendFactor::InvSrcColor, BlendFactor::SrcAlpha,     BlendFactor::InvSrcAlpha,
    BlendFactor::DestAlpha,   BlendFactor::InvDestAlpha, BlendFactor::DestColor,
    BlendFactor::InvDestColor, BlendFactor::SrcAlphaSat, BlendFactor::BothSrcAlpha,
    BlendFactor::BothInvSrcAlpha};

// Each source factor with destination ZERO, and each destination factor with source
// ZERO: the result is exactly the rounded product, for all 65,536 colour pairs.
TEST(BlendFactors, EachFactorProductIsExactRoundingForAll65536Pairs) {
    for (BlendFactor f : kAllFactors)
        for (int asSource = 0; asSource < 2; ++asSource) {
            bool both = f == BlendFactor::BothSrcAlpha || f == BlendFactor::BothInvSrcAlpha;
            if (!asSource && both) continue;  // source-only factors
            for (uint32_t u = 0; u < 256; ++u)
                for (uint32_t v = 0; v < 256; ++v) {
                    Rgba8 s, d;
                    colours(u, v, s, d);
                    const double sd[4] = {s.r / 255.0, s.g / 255.0, s.b / 255.0, s.a / 255.0};
                    const double dd[4] = {d.r / 255.0, d.g / 255.0, d.b / 255.0, d.a / 255.0};
                    Rgba8 out = asSource ? blendPixel(f, BlendFactor::Zero, BlendOp::Add, s, d)
                                         : blendPixel(BlendFactor::Zero, f, BlendOp::Add, s, d);
                    for (int c = 0; c < 4; ++c) {
                        double fs = asSource ? factorDefinition(f, c, sd, dd) : 0.0;
                        double fd = asSource ? 0.0 : factorDefinition(f, c, sd, dd);
                        // BOTH* as source also set the destination factor.
                        if (f == BlendFactor::BothSrcAlpha) fd = 1 - sd[3];
                        if (f == BlendFactor::BothInvSrcAlpha) fd = sd[3];
                        uint32_t expected = std::min<uint32_t>(
                            255, product(channel(s, c), fs) + product(channel(d, c), fd));
                        ASSERT_EQ(channel(out, c), expected)
                            << "factor " << int(f) << (asSource ? " as source" : " as dest")
                            << " channel " << c << " u=" << u << " v=" << v;
                    }
                }
        }
}

// ADD saturates, SUBTRACT and REVSUBTRACT clamp at 0, MIN and MAX ignore the factors.
TEST(BlendOps, EachOperationMatchesItsDefinitionForAll65536Pairs) {
    for (uint32_t u = 0; u < 256; ++u)
        for (uint32_t v = 0; v < 256; ++v) {
            Rgba8 s, d;
            colours(u, v, s, d);
            const BlendFactor fs = BlendFactor::SrcAlpha, fd = BlendFactor::InvDestColor;
            for (int c = 0; c < 4; ++c) {
                uint32_t sc = channel(s, c), dc = channel(d, c);
                int64_t a = product(sc, s.a / 255.0), b = product(dc, 1 - dc / 255.0);
                ASSERT_EQ(channel(blendPixel(fs, fd, BlendOp::Add, s, d), c),
                          uint32_t(std::min<int64_t>(255, a + b)));
                ASSERT_EQ(channel(blendPixel(fs, fd, BlendOp::Subtract, s, d), c),
                          uint32_t(std::max<int64_t>(0, a - b)));
                ASSERT_EQ(channel(blendPixel(fs, fd, BlendOp::RevSubtract, s, d), c),
                          uint32_t(std::max<int64_t>(0, b - a)));
                ASSERT_EQ(channel(blendPixel(fs, fd, BlendOp::Min, s, d), c), std::min(sc, dc));
                ASSERT_EQ(channel(blendPixel(fs, fd, BlendOp::Max, s, d), c), std::max(sc, dc));
            }
        }
}

// Hand-computed: src (200,100,50,128) over dst (10,20,30,40) with SRCALPHA/INVSRCALPHA:
// r = round(200·128/255) + round(10·127/255) = 100 + 5, and so on.
TEST(BlendFactors, SrcAlphaOverInvSrcAlphaThroughThePipeline) {
    for (Path path : {Path::Reference, Path::Fast})
        for (int both = 0; both < 2; ++both) {
            Device dev(geforce256(), 8, 8, DepthFormat::None, {path, 2});
            PipelineState s = plainState();
            s.blend = 1;
            s.srcBlend = both ? BlendFactor::BothSrcAlpha : BlendFactor::SrcAlpha;
            s.dstBlend = both ? BlendFactor::One : BlendFactor::InvSrcAlpha;  // One: overridden
            dev.setState(s);
            dev.clear(true, {10, 20, 30, 40}, false, 0);
            Rgba8 c{200, 100, 50, 128};
            std::vector<Vertex> q = {tv(0, 0, 0.5f, 1, c), tv(8, 0, 0.5f, 1, c),
                                     tv(8, 8, 0.5f, 1, c), tv(0, 8, 0.5f, 1, c)};
            dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
            EXPECT_EQ(dev.framebuffer().pixel(3, 4), (Rgba8{105, 60, 40, 84})) << pathName(path);
            EXPECT_EQ(dev.counters().blendOps, 64u);
        }
}

TEST(BlendOps, ProfileWithoutTheFeatureRefusesTheOperation) {
    Profile p = geforce256();
    p.featureMask &= ~(uint64_t{1} << uint32_t(Feature::BlendSubtract));
    p.featureMask &= ~(uint64_t{1} << uint32_t(Feature::BlendMinMax));
    Device dev(p, 8, 8, DepthFormat::None);
    std::vector<Vertex> tri = {tv(0, 0), tv(8, 0), tv(0, 8)};
    for (BlendOp op : {BlendOp::Subtract, BlendOp::RevSubtract, BlendOp::Min, BlendOp::Max}) {
        PipelineState s = plainState();
        s.blend = 1;
        s.blendOp = op;
        dev.setState(s);
        EXPECT_THROW(dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri),
                     UnsupportedFeature);
    }
    PipelineState s = plainState();
    s.blend = 1;
    dev.setState(s);
    EXPECT_NO_THROW(dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri));
}

// ---- depth -----------------------------------------------------------------------------
TEST(DepthQuantize, RoundsHalfUpOnTheBuffersScale) {
    EXPECT_EQ(quantizeDepth(0.5, 65535), 32768u);
    EXPECT_EQ(quantizeDepth(0.5, 16777215), 8388608u);
    EXPECT_EQ(quantizeDepth(0.0, 65535), 0u);
    EXPECT_EQ(quantizeDepth(1.0, 65535), 65535u);
    EXPECT_EQ(quantizeDepth(-0.25, 65535), 0u);
    EXPECT_EQ(quantizeDepth(7.0, 65535), 65535u);
    EXPECT_EQ(quantizeDepth(std::nan(""), 65535), 0u);
    for (uint32_t k = 0; k <= 65535; ++k)
        ASSERT_EQ(quantizeDepth(double(k) / 65535.0, 65535), k) << "k=" << k;
}

// Clear depth to 0.5, draw at 0.25, 0.5 and 0.75: each function passes exactly where
// its definition says, for 16- and 24-bit buffers, and the write mask keeps the buffer.
TEST(DepthCompare, EveryFunctionAgainstEveryOrder) {
    const CompareFunc funcs[] = {CompareFunc::Never,   CompareFunc::Less,
                                 CompareFunc::Equal,   CompareFunc::LessEqual,
                                 CompareFunc::Greater, CompareFunc::NotEqual,
                                 CompareFunc::GreaterEqual, CompareFunc::Always};
    for (Path path : {Path::Reference, Path::Fast})
        for (DepthFormat fmt : {DepthFormat::D16, DepthFormat::D24})
            for (CompareFunc f : funcs)
                for (float z : {0.25f, 0.5f, 0.75f})
                    for (int write = 0; write < 2; ++write) {
                        Device dev(geforce256(), 8, 8, fmt, {path, 2});
                        PipelineState s = plainState();
                        s.depthTest = 1;
                        s.depthWrite = uint8_t(write);
                        s.depthFunc = f;
                        dev.setState(s);
                        dev.clear(true, {0, 0, 0, 0}, true, 0.5f);
                        std::vector<Vertex> q = {tv(0, 0, z), tv(8, 0, z), tv(8, 8, z), tv(0, 8, z)};
                        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
                        const uint32_t m = dev.framebuffer().depthMax();
                        const uint32_t zq = uint32_t(std::floor(double(z) * m + 0.5));
                        const uint32_t half = uint32_t(std::floor(0.5 * m + 0.5));
                        bool pass = f == CompareFunc::Always ||
                                    (f == CompareFunc::Less && zq < half) ||
                                    (f == CompareFunc::Equal && zq == half) ||
                                    (f == CompareFunc::LessEqual && zq <= half) ||
                                    (f == CompareFunc::Greater && zq > half) ||
                                    (f == CompareFunc::NotEqual && zq != half) ||
                                    (f == CompareFunc::GreaterEqual && zq >= half);
                        const auto& fb = dev.framebuffer();
                        EXPECT_EQ(fb.pixel(5, 2).r, pass ? 255 : 0)
                            << "func " << int(f) << " z " << z << " " << pathName(path);
                        EXPECT_EQ(fb.depth()[2 * 8 + 5], pass && write ? zq : half);
                        EXPECT_EQ(dev.counters().fragmentsWritten, pass ? 64u : 0u);
                    }
}

TEST(DepthFormats, ProfileWithoutD24RefusesIt) {
    Profile p = geforce256();
    p.featureMask &= ~(uint64_t{1} << uint32_t(Feature::Depth24));
    EXPECT_THROW(Device(p, 8, 8, DepthFormat::D24), UnsupportedFeature);
    EXPECT_NO_THROW(Device(p, 8, 8, DepthFormat::D16));
}

// ---- alpha test ----------------------------------------------------------------------
TEST(AlphaTest, EveryFunctionAtEveryReferenceForAll65536Pairs) {
    for (int f = 0; f < 8; ++f)
        for (uint32_t a = 0; a < 256; ++a)
            for (uint32_t ref = 0; ref < 256; ++ref) {
                bool expected[8] = {false, a < ref, a == ref, a <= ref,
                                    a > ref, a != ref, a >= ref, true};
                ASSERT_EQ(comparePasses(CompareFunc(f), a, ref), expected[f])
                    << "func " << f << " alpha " << a << " ref " << ref;
            }
}

TEST(AlphaTest, ThroughThePipelineTheFragmentAlphaIsCompared) {
    for (Path path : {Path::Reference, Path::Fast})
        for (int f = 0; f < 8; ++f)
            for (uint8_t alpha : {uint8_t(99), uint8_t(100), uint8_t(101)}) {
                Device dev(geforce256(), 4, 4, DepthFormat::None, {path, 2});
                PipelineState s = plainState();
                s.alphaTest = 1;
                s.alphaFunc = CompareFunc(f);
                s.alphaRef = 100;
                dev.setState(s);
                Rgba8 c{9, 9, 9, alpha};
                std::vector<Vertex> q = {tv(0, 0, 0.5f, 1, c), tv(4, 0, 0.5f, 1, c),
                                         tv(4, 4, 0.5f, 1, c), tv(0, 4, 0.5f, 1, c)};
                dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
                bool pass = comparePasses(CompareFunc(f), alpha, 100);
                EXPECT_EQ(dev.framebuffer().pixel(1, 1).a, pass ? alpha : 0);
                EXPECT_EQ(dev.counters().fragmentsGenerated, 16u);
                EXPECT_EQ(dev.counters().fragmentsWritten, pass ? 16u : 0u);
            }
}

// ---- write mask and specular -----------------------------------------------------------
TEST(ColorWriteMask, OnlyEnabledChannelsChange) {
    for (Path path : {Path::Reference, Path::Fast})
        for (uint8_t mask = 0; mask < 16; ++mask) {
            Device dev(geforce256(), 4, 4, DepthFormat::None, {path, 2});
            PipelineState s = plainState();
            s.colorWriteMask = mask;
            dev.setState(s);
            dev.clear(true, {1, 2, 3, 4}, false, 0);
            Rgba8 c{200, 201, 202, 203};
            std::vector<Vertex> q = {tv(0, 0, 0.5f, 1, c), tv(4, 0, 0.5f, 1, c),
                                     tv(4, 4, 0.5f, 1, c), tv(0, 4, 0.5f, 1, c)};
            dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
            Rgba8 p = dev.framebuffer().pixel(2, 2);
            EXPECT_EQ(p.r, (mask & kWriteR) ? 200 : 1);
            EXPECT_EQ(p.g, (mask & kWriteG) ? 201 : 2);
            EXPECT_EQ(p.b, (mask & kWriteB) ? 202 : 3);
            EXPECT_EQ(p.a, (mask & kWriteA) ? 203 : 4);
        }
}

TEST(SpecularAdd, AddsSaturatedRgbAfterTheStagesAndKeepsAlpha) {
    EXPECT_EQ(addSpecular({100, 100, 100, 50}, {200, 10, 0, 77}), (Rgba8{255, 110, 100, 50}));
    for (Path path : {Path::Reference, Path::Fast})
        for (int enable = 0; enable < 2; ++enable) {
            Device dev(geforce256(), 4, 4, DepthFormat::None, {path, 2});
            PipelineState s = plainState();
            s.specularEnable = uint8_t(enable);
            dev.setState(s);
            Rgba8 d{100, 100, 100, 50}, sp{200, 10, 0, 77};
            std::vector<Vertex> q = {tv(0, 0, 0.5f, 1, d, sp), tv(4, 0, 0.5f, 1, d, sp),
                                     tv(4, 4, 0.5f, 1, d, sp), tv(0, 4, 0.5f, 1, d, sp)};
            dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, q);
            EXPECT_EQ(dev.framebuffer().pixel(2, 1),
                      enable ? (Rgba8{255, 110, 100, 50}) : (Rgba8{100, 100, 100, 50}));
        }
}

}  // namespace
}  // namespace rg::testing
