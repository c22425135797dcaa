// The programmable profile (geforce8800): programs, float targets, MRT, render-to-texture,
// depth compare, points, counters, errors, and the reference/fast agreement.
#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cstdio>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/error.h"
#include "core/profile.h"
#include "rasterizer/device.h"
#include "rasterizer/programmable_device.h"
#include "rasterizer/trace.h"
#include "texunit/format.h"
#include "texunit/program_fetch.h"

namespace rg::raster {
namespace {

using tex::TexelFormat;
using tex::TextureDesc;
using tex::TextureMemory;
using tex::TextureTarget;

const Profile& g80() { return profile(ProfileId::GeForce8800); }

// ---- programs used by the tests ---------------------------------------------------------

struct ScreenVertex {
    glm::vec4 position;  // clip space
    glm::vec4 attr;
};

struct PassVP {  // clip position as given, one varying
    static constexpr int kVaryings = 1;
    glm::vec4 operator()(const ScreenVertex& v, Varyings& out) const {
        out[0] = v.attr;
        return v.position;
    }
};

struct VaryingFP {  // writes varying 0 to target 0
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const { f.output(0, f.varying(0)); }
};

struct SampleFP {  // unit 0 at varying 0, implicit LOD
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const { f.output(0, f.sample(0, 0)); }
};

struct TwoTargets : VaryingFP {
    static constexpr uint32_t kTargets = 3;
};

struct Sneaky : VaryingFP {
    void operator()(FragmentContext& f) const { f.output(2, glm::vec4(1)); }
};

struct Mrt {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 3;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const {
        f.output(0, glm::vec4(1.5f, 0.25f, 3.0f, 1.0f));
        f.output(1, glm::vec4(0.125f));
    }
};

struct WritesDepth : VaryingFP {
    static constexpr bool kWritesDepth = true;
    void operator()(FragmentContext& f) const {
        f.output(0, glm::vec4(1));
        f.depth(0.1f);
    }
};

struct Shadow {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const {
        const glm::vec4 v = f.varying(0);
        f.output(0, glm::vec4(f.sampleCompare(0, v, 0.05f), f.sampleCompare(0, v, 0.2f), 0, 1));
    }
};

struct Splat {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const {
        const glm::vec2 pc = f.pointCoord();
        f.output(0, glm::vec4(pc.x, pc.y, 1.0f, 0.0f));
    }
};

// Window-space rectangle [x0, x1) × [y0, y1) of a w×h target as two clip-space triangles.
std::vector<ScreenVertex> rect(int w, int h, float x0, float y0, float x1, float y1, float z,
                               glm::vec4 a00, glm::vec4 a10, glm::vec4 a01, glm::vec4 a11) {
    auto clip = [&](float x, float y) {
        return glm::vec4(2.0f * x / float(w) - 1.0f, 1.0f - 2.0f * y / float(h), z, 1.0f);
    };
    ScreenVertex v00{clip(x0, y0), a00}, v10{clip(x1, y0), a10}, v01{clip(x0, y1), a01},
        v11{clip(x1, y1), a11};
    return {v00, v10, v01, v10, v11, v01};
}

struct Fixture {
    std::shared_ptr<TextureMemory> memory = std::make_shared<TextureMemory>(g80());
    std::shared_ptr<tex::Texture> target(int w, int h, TexelFormat f) {
        TextureDesc d;
        d.format = f;
        d.width = w;
        d.height = h;
        return memory->createRenderTarget(d);
    }
};

// ---- profile and errors -------------------------------------------------------------------

TEST(ProgrammableErrors, FixedFunctionProfilesHaveNoPrograms) {
    for (ProfileId id : {ProfileId::GeForce256, ProfileId::GeForce3, ProfileId::SgiOctaneMxe, ProfileId::SgiO2}) {
        try {
            ProgrammableDevice dev(profile(id));
            FAIL() << "profile " << profile(id).name << " accepted a programmable device";
        } catch (const UnsupportedFeature& e) {
            EXPECT_NE(std::string(e.what()).find(std::string(profile(id).name)), std::string::npos) << e.what();
        }
    }
    TextureMemory m(profile(ProfileId::GeForce256));
    TextureDesc d;
    d.format = TexelFormat::RGBA16F;
    d.width = d.height = 16;
    EXPECT_THROW(m.createRenderTarget(d), UnsupportedFeature);
}

TEST(ProgrammableErrors, UnboundUnitUnattachedTargetAndMismatches) {
    Fixture fx;
    ProgrammableDevice dev(g80());
    auto verts = rect(8, 8, 0, 0, 8, 8, 0.5f, {}, {}, {}, {});
    // No target at all.
    EXPECT_THROW(dev.draw(PassVP{}, VaryingFP{}, ProgramPrimitive::TriangleList,
                          std::span<const ScreenVertex>(verts)), InvalidState);
    auto rt = fx.target(8, 8, TexelFormat::RGBA8);
    ColorTarget ct{rt};
    dev.setRenderTargets({&ct, 1});
    // Unit 0 declared but unbound.
    try {
        dev.draw(PassVP{}, SampleFP{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(verts));
        FAIL();
    } catch (const InvalidState& e) {
        EXPECT_NE(std::string(e.what()).find("texture unit 0"), std::string::npos) << e.what();
    }
    // Sampling the target being written.
    dev.setTexture(0, rt);
    EXPECT_THROW(dev.draw(PassVP{}, SampleFP{}, ProgramPrimitive::TriangleList,
                          std::span<const ScreenVertex>(verts)), InvalidState);
    // A program writing target 1 with one target attached.
    try {
        dev.draw(PassVP{}, TwoTargets{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(verts));
        FAIL();
    } catch (const InvalidState& e) {
        EXPECT_NE(std::string(e.what()).find("render target 1"), std::string::npos) << e.what();
    }
    // A write to an undeclared target at run time.
    EXPECT_THROW(dev.draw(PassVP{}, Sneaky{}, ProgramPrimitive::TriangleList,
                          std::span<const ScreenVertex>(verts)), InvalidState);
    // Targets of different sizes; a plain texture as a target; an index past the end.
    auto other = fx.target(16, 8, TexelFormat::RGBA8);
    ColorTarget two[2] = {{rt}, {other}};
    EXPECT_THROW(dev.setRenderTargets(two), InvalidState);
    TextureDesc plain;
    plain.width = plain.height = 8;
    ColorTarget notRt{fx.memory->create(plain)};
    EXPECT_THROW(dev.setRenderTargets({&notRt, 1}), InvalidState);
    const uint32_t bad[3] = {0, 1, 99};
    EXPECT_THROW(dev.draw(PassVP{}, VaryingFP{}, ProgramPrimitive::TriangleList,
                          std::span<const ScreenVertex>(verts), bad), InvalidState);
}

// ---- interpolation and coverage -----------------------------------------------------------

TEST(ProgrammableRaster, AffineVaryingIsExactToAnUlpAndCoverageMatchesFixedFunction) {
    Fixture fx;
    const int W = 64, H = 64;  // powers of two: window ↔ clip conversions below are exact
    auto rt = fx.target(W, H, TexelFormat::RGBA32F);
    ProgrammableDevice dev(g80());
    ColorTarget ct{rt};
    dev.setRenderTargets({&ct, 1});
    dev.clearColor(0, glm::vec4(-1.0f));
    // Varying = window position, so each pixel must read its own centre.
    auto verts = rect(W, H, 0, 0, W, H, 0.5f, {0, 0, 0, 1}, {W, 0, 0, 1}, {0, H, 0, 1}, {W, H, 0, 1});
    dev.draw(PassVP{}, VaryingFP{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(verts));
    const glm::vec4* p = rt->renderDataF(0, 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            ASSERT_NEAR(p[y * W + x].x, x + 0.5f, 1e-4f) << x << "," << y;
            ASSERT_NEAR(p[y * W + x].y, y + 0.5f, 1e-4f) << x << "," << y;
        }
    EXPECT_EQ(dev.counters().fragmentInvocations, uint64_t(W * H));

    // Random triangles: the pixels covered are exactly the fixed-function pipeline's
    // (same snapping, edges and top-left rule).
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-0.3f, 1.3f);
    Device ff(g80(), W, H, DepthFormat::None);
    PipelineState st;
    st.cull = CullMode::None;
    st.depthTest = 0;
    ff.setState(st);
    auto rt8 = fx.target(W, H, TexelFormat::RGBA8);
    ColorTarget c8{rt8};
    dev.setRenderTargets({&c8, 1});
    for (int iter = 0; iter < 200; ++iter) {
        std::vector<ScreenVertex> tri(3);
        std::vector<Vertex> ffv(3);
        for (int i = 0; i < 3; ++i) {
            // On a 1/1024-pixel grid, so that clip → window reproduces x and y exactly.
            const float x = std::round(u(rng) * W * 1024.0f) / 1024.0f;
            const float y = std::round(u(rng) * H * 1024.0f) / 1024.0f;
            tri[size_t(i)] = {glm::vec4(2.0f * x / W - 1.0f, 1.0f - 2.0f * y / H, 0.5f, 1.0f), glm::vec4(1.0f)};
            ffv[size_t(i)].position = glm::vec4(x, y, 0.5f, 1.0f);
            ffv[size_t(i)].diffuse = Rgba8{255, 255, 255, 255};
        }
        dev.clearColor(0, glm::vec4(0.0f));
        dev.draw(PassVP{}, VaryingFP{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(tri));
        ff.clear(true, Rgba8{0, 0, 0, 0}, false, 1.0f);
        ff.draw(Primitive::TriangleList, VertexSpace::Pretransformed, ffv);
        const Rgba8* a = rt8->renderData8(0, 0);
        const auto b = ff.readPixels(0, 0, W, H);
        for (int i = 0; i < W * H; ++i)
            ASSERT_EQ(a[i].r != 0, b[size_t(i)].r != 0) << "triangle " << iter << " pixel " << i;
    }
}

// ---- float targets ------------------------------------------------------------------------

// The nearest binary16 by search: an oracle independent of the converter.
float nearestHalf(float v) {
    if (std::isnan(v)) return std::numeric_limits<float>::quiet_NaN();
    if (std::fabs(v) >= 65520.0f) return std::copysign(INFINITY, v);  // past max + ½ ulp
    float best = 0.0f;
    double bestErr = INFINITY;
    uint16_t bestBits = 0;
    // Bracket by the float's magnitude: check every half with the same sign.
    for (uint32_t h = 0; h < 0x7C00; ++h) {
        const uint16_t bits = uint16_t(h | (v < 0 ? 0x8000 : 0));
        const float c = tex::halfToFloat(bits);
        const double err = std::fabs(double(c) - double(v));
        if (err < bestErr || (err == bestErr && (h & 1) == 0 && (bestBits & 1) == 1)) {
            best = c;
            bestErr = err;
            bestBits = bits;
        }
    }
    return best;
}

TEST(ProgrammableFloatTargets, Rgba16fRoundsToNearestEven) {
    Fixture fx;
    auto rt = fx.target(4, 4, TexelFormat::RGBA16F);
    ProgrammableDevice dev(g80());
    ColorTarget ct{rt};
    dev.setRenderTargets({&ct, 1});
    std::mt19937 rng(3);
    std::vector<float> values = {0.0f, 1.0f, 1.0f + 1.0f / 2048.0f, 1.0f + 3.0f / 2048.0f,  // ties
                                 65504.0f, 65519.0f, 65520.0f, 1e-8f, 5.9604645e-08f, -2.5f};
    std::uniform_int_distribution<uint32_t> bitsDist(0, 0x477FFFFFu);
    for (int i = 0; i < 300; ++i) {
        uint32_t b = bitsDist(rng);
        float f;
        std::memcpy(&f, &b, 4);
        values.push_back(i & 1 ? -f : f);
    }
    for (float v : values) {
        dev.clearColor(0, glm::vec4(v));
        const float got = rt->renderDataF(0, 0)[0].x;
        const float want = nearestHalf(v);
        ASSERT_EQ(std::memcmp(&got, &want, 4) == 0 || (got == 0.0f && want == 0.0f), true)
            << "value " << v << " stored " << got << " nearest half " << want;
    }
    dev.clearColor(0, glm::vec4(std::nanf("")));
    EXPECT_TRUE(std::isnan(rt->renderDataF(0, 0)[0].x));
}

// Clears fill viewport ∩ scissor; a scissor of negative width or height is empty, and
// the clear writes nothing (it ran off the level before: found by the trace tests'
// corrupted scissor records).
TEST(ProgrammableClears, AScissorOfNegativeExtentClearsNothing) {
    Fixture fx;
    auto rt = fx.target(8, 8, TexelFormat::RGBA8);
    ProgrammableDevice dev(g80());
    ColorTarget ct{rt};
    dev.setRenderTargets({&ct, 1});
    dev.clearColor(0, glm::vec4(1.0f));
    for (const Rect r : {Rect{1, 1, -5, 3}, Rect{2, 6, 3, int32_t(0x80000006u)}, Rect{7, 0, -0x7fffffff, 8}}) {
        dev.setScissor(&r);
        dev.clearColor(0, glm::vec4(0.0f));
        const Rgba8* p = rt->renderData8(0, 0);
        EXPECT_TRUE(std::all_of(p, p + 64, [](Rgba8 c) { return c == Rgba8{255, 255, 255, 255}; }))
            << "scissor " << r.x << ", " << r.y << ", " << r.width << ", " << r.height;
    }
    const Rect inside{2, 3, 1, 1};
    dev.setScissor(&inside);
    dev.clearColor(0, glm::vec4(0.0f));
    EXPECT_EQ(rt->renderData8(0, 0)[3 * 8 + 2], (Rgba8{0, 0, 0, 0}));
    EXPECT_EQ(rt->renderData8(0, 0)[3 * 8 + 3], (Rgba8{255, 255, 255, 255}));
}

TEST(ProgrammableFloatTargets, AdditiveBlendAccumulatesUnclampedAndMrtWritesEachTarget) {
    Fixture fx;
    const int W = 16, H = 16;
    auto a = fx.target(W, H, TexelFormat::RGBA32F);
    auto b = fx.target(W, H, TexelFormat::R16F);
    ProgrammableDevice dev(g80());
    ColorTarget cts[2] = {{a}, {b}};
    dev.setRenderTargets(cts);
    ProgramState st;
    st.blend[0] = TargetBlend{1, BlendFactor::One, BlendFactor::One, BlendOp::Add, kWriteRGBA};
    st.blend[1] = TargetBlend{1, BlendFactor::One, BlendFactor::One, BlendOp::Add, kWriteRGBA};
    dev.setState(st);
    auto verts = rect(W, H, 0, 0, W, H, 0.5f, {}, {}, {}, {});
    for (int pass = 0; pass < 5; ++pass)
        dev.draw(PassVP{}, Mrt{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(verts));
    EXPECT_EQ(a->renderDataF(0, 0)[37], glm::vec4(7.5f, 1.25f, 15.0f, 5.0f));
    EXPECT_EQ(b->renderDataR(0, 0)[37], 0.625f);
}

// ---- render to texture, depth, depth compare ----------------------------------------------

TEST(ProgrammableRenderToTexture, SecondPassSamplesTheFirstWithoutACopy) {
    Fixture fx;
    const int W = 32, H = 32;
    auto first = fx.target(W, H, TexelFormat::RGBA16F);
    auto second = fx.target(W, H, TexelFormat::RGBA32F);
    ProgrammableDevice dev(g80());
    ColorTarget c1{first};
    dev.setRenderTargets({&c1, 1});
    auto verts = rect(W, H, 0, 0, W, H, 0.5f, {0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}, {1, 1, 0, 1});
    dev.draw(PassVP{}, VaryingFP{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(verts));
    ColorTarget c2{second};
    dev.setRenderTargets({&c2, 1});
    tex::SamplerState nearest;
    nearest.magFilter = nearest.minFilter = tex::FilterMode::Nearest;
    dev.setTexture(0, first, nearest);
    dev.draw(PassVP{}, SampleFP{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(verts));
    // Each pixel reads its own texel of the first pass (uv at the pixel centre).
    for (int i = 0; i < W * H; ++i) ASSERT_EQ(second->renderDataF(0, 0)[i], first->renderDataF(0, 0)[i]) << i;
    EXPECT_EQ(dev.counters().textureFetches, uint64_t(W * H));
    EXPECT_EQ(dev.counters().maxFetchesPerFragment, 1u);
}

TEST(ProgrammableDepth, EarlyAndLateDepthTestAndShadowCompare) {
    Fixture fx;
    const int W = 16, H = 16;
    auto rt = fx.target(W, H, TexelFormat::RGBA8);
    TextureDesc dd;
    dd.format = TexelFormat::Depth24;
    dd.width = W;
    dd.height = H;
    auto depth = fx.memory->createRenderTarget(dd);
    ProgrammableDevice dev(g80());
    ColorTarget ct{rt};
    dev.setRenderTargets({&ct, 1}, DepthTarget{depth});
    ProgramState st;
    st.depthTest = st.depthWrite = 1;
    st.depthFunc = CompareFunc::Less;
    dev.setState(st);
    dev.clearDepth(1.0f);
    // Left half at z = 0.25 first, then a full quad at z = 0.5: only the right half passes.
    auto left = rect(W, H, 0, 0, W / 2, H, 0.25f, {}, {}, {}, {});
    auto full = rect(W, H, 0, 0, W, H, 0.5f, {}, {}, {}, {});
    dev.draw(PassVP{}, VaryingFP{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(left));
    dev.beginFrame();
    dev.draw(PassVP{}, VaryingFP{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(full));
    EXPECT_EQ(dev.counters().fragmentsGenerated, uint64_t(W * H));
    EXPECT_EQ(dev.counters().fragmentsDepthFailed, uint64_t(W * H / 2));
    EXPECT_EQ(dev.counters().fragmentInvocations, uint64_t(W * H / 2));  // early test
    const float q25 = float(double(std::floor(0.25 * 16777215.0 + 0.5)) / 16777215.0);
    EXPECT_EQ(depth->renderDataR(0, 0)[3], q25);

    // A program writing depth runs for every pixel (late test).
    dev.beginFrame();
    dev.draw(PassVP{}, WritesDepth{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(full));
    EXPECT_EQ(dev.counters().fragmentInvocations, uint64_t(W * H));
    EXPECT_EQ(dev.counters().fragmentsDepthFailed, 0u);

    // The depth target as a shadow map: ref ≤ 0.1 passes, ref > 0.1 fails; LINEAR on a
    // step gives the percentage-closer fraction.
    auto rt2 = fx.target(W, H, TexelFormat::RGBA32F);
    ColorTarget c2{rt2};
    dev.setRenderTargets({&c2, 1});
    dev.setState(ProgramState{});
    tex::SamplerState cmp;
    cmp.magFilter = cmp.minFilter = tex::FilterMode::Nearest;
    cmp.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                   tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge};
    dev.setTexture(0, depth, cmp);
    auto uv = rect(W, H, 0, 0, W, H, 0.5f, {0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}, {1, 1, 0, 1});
    dev.draw(PassVP{}, Shadow{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(uv));
    EXPECT_EQ(rt2->renderDataF(0, 0)[5], glm::vec4(1, 0, 0, 1));
    // Percentage-closer: a depth step between texels 7 and 8 of a row, sampled LINEAR
    // halfway between the two texel centres → exactly half the weight passes.
    float* dp = depth->renderDataR(0, 0);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) dp[y * W + x] = x < 8 ? 0.0f : 1.0f;
    cmp.magFilter = cmp.minFilter = tex::FilterMode::Linear;
    uint32_t fetches = 0;
    const float pcf = tex::programFetchCompare(*depth, cmp, glm::vec4(8.0f / W, 0.5f, 0, 0), 0.5f,
                                               tex::programLambdaLod(cmp, 0.0f), Path::Fast, fetches);
    EXPECT_EQ(pcf, 0.5f);
    EXPECT_EQ(fetches, 4u);
}

// The fast path's stored depth, four lanes at a time (storedDepthQuad), against the rule
// of docs/hardware.md ("Depth rounding", "Depth24 storage") written out with branches:
// clamp to [0, 1] with NaN → 0; Depth24 k = floor(c·(2^24 − 1) + ½) in double, stored as
// float(k / (2^24 − 1)); Depth32F float(c). Values at
// the ends of the range, the midpoints between two 24-bit steps and their neighbours,
// and random ones.
TEST(ProgrammableDepth, QuadStoredDepthFollowsTheQuantisationRule) {
    constexpr double kMax = double((1u << 24) - 1u);
    auto oracle = [&](bool d24, double z) -> float {
        const double c = !(z > 0.0) ? 0.0 : (z >= 1.0 ? 1.0 : z);
        if (!d24) return float(c);
        const double k = std::floor(c * kMax + 0.5);
        return float(k / kMax);
    };
    std::vector<double> zs = {std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::infinity(),
                              -1.0, -0.0, 0.0, 1e-300, std::numeric_limits<double>::denorm_min(), 0.5 / kMax,
                              std::nextafter(0.5 / kMax, 0.0), std::nextafter(0.5 / kMax, 1.0), 0.25, 0.5,
                              std::nextafter(1.0, 0.0), 1.0, 1.5, std::numeric_limits<double>::infinity()};
    for (int k : {1, 2, 1000, 4194303, 8388607, 16777213}) {  // halfway between steps k and k + 1
        const double mid = (double(k) + 0.5) / kMax;
        zs.insert(zs.end(), {mid, std::nextafter(mid, 0.0), std::nextafter(mid, 1.0)});
    }
    std::mt19937 rng(20261128);
    std::uniform_real_distribution<double> u(-0.25, 1.25);
    for (int i = 0; i < 4000; ++i) zs.push_back(u(rng));
    while (zs.size() % 4) zs.push_back(0.75);
    int checked = 0;
    for (bool d24 : {true, false})
        for (size_t i = 0; i < zs.size(); i += 4) {
            const double z[4] = {zs[i], zs[i + 1], zs[i + 2], zs[i + 3]};
            float out[4];
            raster::detail::storedDepthQuad(d24, z, out);
            for (int p = 0; p < 4; ++p) {
                const float want = oracle(d24, z[p]);
                ASSERT_EQ(std::bit_cast<uint32_t>(out[p]), std::bit_cast<uint32_t>(want))
                    << (d24 ? "Depth24" : "Depth32F") << " z = " << z[p];
                // The per-fragment path (shadeFragment) stores the same bits.
                ASSERT_EQ(std::bit_cast<uint32_t>(raster::detail::storedDepth(d24, z[p])), std::bit_cast<uint32_t>(want));
                ++checked;
            }
        }
    EXPECT_EQ(checked, int(2 * zs.size()));
    // Every 24-bit value: z = k/(2^24 − 1) quantises to k (|z·(2^24 − 1) − k| is far below
    // ½), and storedDepthQuad keeps float(k/(2^24 − 1)), the division's bits, which its
    // product by 1/(2^24 − 1) must give.
    for (uint32_t k = 0; k < (1u << 24); k += 4) {
        double z[4];
        for (int p = 0; p < 4; ++p) z[p] = double(k + uint32_t(p)) / kMax;
        float out[4];
        raster::detail::storedDepthQuad(true, z, out);
        for (int p = 0; p < 4; ++p) {
            const float want = float(double(k + uint32_t(p)) / kMax);
            if (std::bit_cast<uint32_t>(out[p]) != std::bit_cast<uint32_t>(want))
                FAIL() << "Depth24 step " << k + uint32_t(p) << ": " << out[p] << " against " << want;
        }
    }
}

// ---- points ---------------------------------------------------------------------------------

TEST(ProgrammablePoints, SquareOfPointSizeWithPointCoordinates) {
    Fixture fx;
    const int W = 16, H = 16;
    auto rt = fx.target(W, H, TexelFormat::RGBA32F);
    ProgrammableDevice dev(g80());
    ColorTarget ct{rt};
    dev.setRenderTargets({&ct, 1});
    dev.clearColor(0, glm::vec4(-1));
    ProgramState st;
    st.pointSize = 4.0f;
    st.blend[0] = TargetBlend{1, BlendFactor::One, BlendFactor::One, BlendOp::Add, kWriteRGBA};
    dev.setState(st);
    // Centre on the pixel corner (8, 8): covers pixels 6..9 in x and y.
    ScreenVertex p{glm::vec4(0.0f, 0.0f, 0.5f, 1.0f), glm::vec4(0)};
    dev.draw(PassVP{}, Splat{}, ProgramPrimitive::PointList, std::span<const ScreenVertex>(&p, 1));
    int covered = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const glm::vec4 v = rt->renderDataF(0, 0)[y * W + x];
            const bool in = x >= 6 && x <= 9 && y >= 6 && y <= 9;
            EXPECT_EQ(v.z, in ? 0.0f : -1.0f) << x << "," << y;  // −1 + 1 inside
            if (in) {
                ++covered;
                EXPECT_NEAR(v.x, -1.0f + (x - 6 + 0.5f) / 4.0f, 1e-5f);
                EXPECT_NEAR(v.y, -1.0f + (y - 6 + 0.5f) / 4.0f, 1e-5f);
            }
        }
    EXPECT_EQ(covered, 16);
}

// ---- the binary search of Davis & Wyman (tir): tests/programmable/test_binary_search.cpp
// checks the benchmark's search program against the workload's scalar reference exactly.

// ---- reference and fast paths, thread counts -------------------------------------------------

// n draws in sequence: a function's arguments are evaluated in an unspecified order (GCC
// and Clang differ), so random values are never drawn inside one call's argument list.
template <class Rng>
std::array<float, 12> draws(Rng& rng, std::uniform_real_distribution<float>& u) {
    std::array<float, 12> r;
    for (float& x : r) x = u(rng);
    return r;
}

struct RandomVertex {
    glm::vec4 position;
    glm::vec4 a, b;
};
struct RandomVP {
    static constexpr int kVaryings = 2;
    glm::vec4 operator()(const RandomVertex& v, Varyings& out) const {
        out[0] = v.a;
        out[1] = v.b;
        return v.position;
    }
};
// Samples a float cube map and a mipmapped RGBA8 2D texture (implicit and explicit LOD),
// discards some fragments, writes depth for some, blends into two targets.
struct RandomFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 3;
    static constexpr uint32_t kUnits = 7;
    static constexpr bool kWritesDepth = true;
    void operator()(FragmentContext& f) const {
        const glm::vec4 a = f.varying(0), b = f.varying(1);
        // Unit 2: a point-sampled float texture (the fast path's inline fetch).
        const glm::vec4 n = f.sampleLevel(2, a * 3.0f - b, 0.0f);
        if (n.x > 0.9f) {
            f.discard();
            return;
        }
        if (a.w > 0.8f) {
            f.discard();
            return;
        }
        const glm::vec4 t0 = f.sample(0, 0);
        const glm::vec4 t1 = f.sample(1, 1);
        const glm::vec4 t2 = f.sampleGrad(1, b * 2.0f, f.ddx(1) * 2.0f, f.ddy(1) * 2.0f);
        const glm::vec4 t3 = f.sampleLevel(0, a + b, b.z * 4.0f);
        f.output(0, t0 * t1 + t3);
        f.output(1, t2 - a + n);
        if (b.w > 0.5f) f.depth(b.w - 0.5f);
        else f.depth(f.fragCoord().z);
    }
};

std::string hashTargets(const std::vector<std::shared_ptr<tex::Texture>>& ts, int w, int h) {
    std::vector<uint8_t> bytes;
    for (const auto& t : ts) {
        const uint8_t* p = t->singleChannel() ? reinterpret_cast<const uint8_t*>(t->renderDataR(0, 0))
                           : t->isFloat()     ? reinterpret_cast<const uint8_t*>(t->renderDataF(0, 0))
                                              : reinterpret_cast<const uint8_t*>(t->renderData8(0, 0));
        const size_t n = size_t(w) * size_t(h) * (t->singleChannel() ? 4 : t->isFloat() ? sizeof(glm::vec4) : 4);
        bytes.insert(bytes.end(), p, p + n);
    }
    return sha256Hex(bytes.data(), bytes.size());
}

TEST(ProgrammablePathsAgree, RandomDrawsGiveTheSameBytesOnBothPathsAndAnyThreadCount) {
    const int W = 150, H = 110;
    std::mt19937 rng(2024);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Fixture fx;
    // Textures: a 32² RGBA32F cube map (LINEAR) and a 64² RGBA8 2D texture with mips.
    TextureDesc cd;
    cd.target = TextureTarget::CubeMap;
    cd.format = TexelFormat::RGBA32F;
    cd.width = cd.height = 32;
    auto cube = fx.memory->create(cd);
    for (int face = 0; face < 6; ++face) {
        std::vector<uint8_t> b(32 * 32 * 16);
        for (size_t i = 0; i < b.size() / 4; ++i) {
            const float v = u(rng) * 4.0f - 1.0f;
            std::memcpy(&b[i * 4], &v, 4);
        }
        fx.memory->upload(*cube, 0, face, b);
    }
    TextureDesc td;
    td.format = TexelFormat::RGBA8;
    td.width = td.height = 64;
    td.levels = 7;
    auto tex2d = fx.memory->create(td);
    for (int l = 0; l < 7; ++l) {
        const int n = 64 >> l;
        std::vector<uint8_t> b(size_t(n) * n * 4);
        for (auto& x : b) x = uint8_t(rng());
        fx.memory->upload(*tex2d, l, 0, b);
    }
    TextureDesc nd;  // 24×16 R32F, point-sampled, WRAP in s and CLAMP_TO_EDGE in t
    nd.format = TexelFormat::R32F;
    nd.width = 24;
    nd.height = 16;
    auto nearestTex = fx.memory->create(nd);
    {
        std::vector<uint8_t> b(24 * 16 * 4);
        for (size_t i = 0; i < b.size() / 4; ++i) {
            const float v = (i % 7 == 0) ? -0.0f : u(rng);
            std::memcpy(&b[i * 4], &v, 4);
        }
        fx.memory->upload(*nearestTex, 0, 0, b);
    }
    tex::SamplerState s2;
    s2.magFilter = s2.minFilter = tex::FilterMode::Nearest;
    s2.address[1] = tex::AddressMode::ClampToEdge;
    tex::SamplerState s0;  // cube: LINEAR, no mips
    tex::SamplerState s1;
    s1.mipFilter = tex::MipMode::Linear;
    s1.address = {tex::AddressMode::Mirror, tex::AddressMode::Border, tex::AddressMode::Wrap,
                  tex::AddressMode::Wrap};
    s1.borderColor = Rgba8{10, 200, 30, 255};

    for (int scene = 0; scene < 12; ++scene) {
        std::vector<RandomVertex> verts;
        const int tris = 6 + int(rng() % 40);
        for (int i = 0; i < 3 * tris; ++i) {
            RandomVertex v;
            const auto r = draws(rng, u);
            const float w = 0.3f + 2.0f * r[0];
            v.position = glm::vec4((r[1] * 2.6f - 1.3f) * w, (r[2] * 2.6f - 1.3f) * w,
                                   (r[3] * 1.2f - 0.1f) * w, w);
            if (rng() % 23 == 0) v.position.x = std::nanf("");
            v.a = glm::vec4(r[4] * 2 - 1, r[5] * 2 - 1, r[6] * 2 - 1, r[7]);
            v.b = glm::vec4(r[8] * 3 - 1, r[9] * 3 - 1, r[10], r[11]);
            verts.push_back(v);
        }
        ProgramState st;
        st.cull = CullMode(rng() % 3);
        st.depthTest = uint8_t(rng() & 1);
        st.depthWrite = 1;
        st.depthFunc = CompareFunc(rng() % 8);
        // Destination factors exclude BOTH* (source factors only; setState refuses them).
        st.blend[0] = TargetBlend{uint8_t(rng() & 1), BlendFactor(rng() % 13), BlendFactor(rng() % 11),
                                  BlendOp(rng() % 5), uint8_t(rng() % 16)};
        st.blend[1] = TargetBlend{uint8_t(rng() & 1), BlendFactor(rng() % 13), BlendFactor(rng() % 11),
                                  BlendOp(rng() % 5), kWriteRGBA};
        const TexelFormat f0 = (scene & 1) ? TexelFormat::RGBA8 : TexelFormat::RGBA16F;
        std::string expect;
        for (int run = 0; run < 5; ++run) {
            const Path path = run == 0 ? Path::Reference : Path::Fast;
            const int threads = run == 0 ? 1 : std::array<int, 4>{1, 2, 3, 8}[size_t(run - 1)];
            auto t0 = fx.target(W, H, f0);
            auto t1 = fx.target(W, H, TexelFormat::RGBA32F);
            TextureDesc dd;
            dd.format = (scene & 2) ? TexelFormat::Depth24 : TexelFormat::Depth32F;
            dd.width = W;
            dd.height = H;
            auto depth = fx.memory->createRenderTarget(dd);
            ProgrammableDevice dev(g80(), DeviceOptions{path, threads});
            ColorTarget cts[2] = {{t0}, {t1}};
            dev.setRenderTargets(cts, DepthTarget{depth});
            dev.setState(st);
            dev.clearColor(0, glm::vec4(0.25f, 0.5f, 0.75f, 0.5f));
            dev.clearColor(1, glm::vec4(0.0f));
            dev.clearDepth(0.75f);
            dev.setTexture(0, cube, s0);
            dev.setTexture(1, tex2d, s1);
            dev.setTexture(2, nearestTex, s2);
            dev.draw(RandomVP{}, RandomFP{}, ProgramPrimitive::TriangleList, std::span<const RandomVertex>(verts));
            const std::string hash = hashTargets({t0, t1, depth}, W, H);
            if (run == 0) {
                expect = hash;
                EXPECT_GT(dev.counters().fragmentInvocations, 0u);
            } else {
                ASSERT_EQ(hash, expect) << "scene " << scene << " fast path, " << threads << " threads";
            }
        }
    }
}

}  // namespace
}  // namespace rg::raster

namespace rg::raster {
namespace {

// One algorithm written twice: per pixel (FragmentContext) and per quad (QuadContext).
// Point-sampled RGBA32F (unit 0) and R32F (unit 1) textures, a filtered cube map (unit 2),
// a data-dependent loop, discard and a masked write.
struct TwinScalarFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 3;
    static constexpr uint32_t kUnits = 7;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const {
        const glm::vec4 a = f.varying(0), b = f.varying(1);
        if (a.w > 0.8f) {
            f.discard();
            return;
        }
        glm::vec4 acc = f.sampleLevel(0, a, 0.0f);
        float t = 0.0f;
        for (int i = 0; i < 6 && t < 2.0f; ++i) {  // a data-dependent number of steps
            const float h = f.sampleLevel(1, glm::vec4(b.x + t, b.y - t, 0, 0), 0.0f).x;
            t = t + std::max(h, 0.125f);
        }
        const glm::vec4 e = f.sampleLevel(2, b, 0.0f) + f.sample(2, 1);
        f.output(0, acc * t + e);
        if (b.z > 0.5f) f.output(1, glm::vec4(t, std::min(a.x, b.x), a.y / b.w, 1.0f));
    }
};

struct TwinQuadFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 3;
    static constexpr uint32_t kUnits = 7;
    static constexpr bool kWritesDepth = false;
    void operator()(QuadContext& q) const {
        const Vec4x4 a = q.varying(0), b = q.varying(1);
        q.discard(a.w > Float4(0.8f));
        Vec4x4 acc = q.sampleLevel(0, a, Float4(0.0f));
        Float4 t(0.0f);
        Mask4 going = q.active();
        for (int i = 0; i < 6; ++i) {
            going = going & (t < Float4(2.0f));
            if (!going.any()) break;
            const Float4 h =
                q.sampleLevel(1, Vec4x4(b.x + t, b.y - t, Float4(0.0f), Float4(0.0f)), Float4(0.0f), going).x;
            t = select(going, t + max(h, Float4(0.125f)), t);
        }
        const Vec4x4 e = q.sampleLevel(2, b, Float4(0.0f)) + q.sample(2, 1);
        q.output(0, acc * t + e);
        q.output(1, Vec4x4(t, min(a.x, b.x), a.y / b.w, Float4(1.0f)), b.z > Float4(0.5f));
    }
};

// The twin tests' textures: random float texels in [−0.25, 1.25) in every face, with every
// `zeroEvery`-th float −0 (the sign of zero must survive every path).
template <class Rng>
auto randomFloatTexture(Fixture& fx, Rng& rng, std::uniform_real_distribution<float>& u, TexelFormat f,
                        TextureTarget target, int w, int h, size_t zeroEvery) {
    TextureDesc d;
    d.format = f;
    d.target = target;
    d.width = w;
    d.height = h;
    auto t = fx.memory->create(d);
    for (int face = 0; face < t->faces(); ++face) {
        std::vector<uint8_t> b(size_t(w) * h * formatInfo(f).bytesPerTexel);
        for (size_t i = 0; i < b.size() / 4; ++i) {
            const float v = (i % zeroEvery == 0) ? -0.0f : u(rng) * 1.5f - 0.25f;
            std::memcpy(&b[i * 4], &v, 4);
        }
        fx.memory->upload(*t, 0, face, b);
    }
    return t;
}

// The twin tests' vertices from one vertex's draws: inside the view volume, window depth ½
// or (randomDepth) spread over it.
RandomVertex twinVertex(const std::array<float, 12>& r, bool randomDepth) {
    RandomVertex v;
    const float w = 0.5f + r[0];
    v.position = glm::vec4((r[1] * 2.4f - 1.2f) * w, (r[2] * 2.4f - 1.2f) * w,
                           randomDepth ? (r[11] * 1.8f - 0.9f) * w : 0.5f * w, w);
    v.a = glm::vec4(r[3] * 2 - 1, r[4] * 2 - 1, r[5] * 2 - 1, r[6]);
    v.b = glm::vec4(r[7] * 3 - 1, r[8] * 3 - 1, r[9], 0.5f + r[10]);
    return v;
}

TEST(ProgrammablePathsAgree, QuadProgramEqualsItsScalarTwinOnBothPaths) {
    const int W = 90, H = 70;
    std::mt19937 rng(77);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Fixture fx;
    auto makeTex = [&](TexelFormat f, TextureTarget target, int w, int h) {
        return randomFloatTexture(fx, rng, u, f, target, w, h, 11);
    };
    auto rgba = makeTex(TexelFormat::RGBA32F, TextureTarget::Texture2D, 32, 16);
    auto red = makeTex(TexelFormat::R32F, TextureTarget::Texture2D, 24, 32);  // non-power-of-two WRAP in s
    auto cube = makeTex(TexelFormat::RGBA32F, TextureTarget::CubeMap, 8, 8);
    tex::SamplerState point;
    point.magFilter = point.minFilter = tex::FilterMode::Nearest;
    point.address[1] = tex::AddressMode::ClampToEdge;
    std::vector<RandomVertex> verts;
    for (int i = 0; i < 3 * 30; ++i) {
        verts.push_back(twinVertex(draws(rng, u), false));
    }
    ProgramState st;
    st.blend[1] = TargetBlend{1, BlendFactor::One, BlendFactor::One, BlendOp::Add, kWriteRGBA};
    auto render = [&](bool quad, Path path, int threads, ProgramCounters& counters) {
        auto t0 = fx.target(W, H, TexelFormat::RGBA16F);
        auto t1 = fx.target(W, H, TexelFormat::RGBA32F);
        ProgrammableDevice dev(g80(), DeviceOptions{path, threads});
        ColorTarget cts[2] = {{t0}, {t1}};
        dev.setRenderTargets(cts);
        dev.setState(st);
        dev.setTexture(0, rgba, point);
        dev.setTexture(1, red, point);
        dev.setTexture(2, cube, tex::SamplerState{});
        if (quad)
            dev.draw(RandomVP{}, TwinQuadFP{}, ProgramPrimitive::TriangleList, std::span<const RandomVertex>(verts));
        else
            dev.draw(RandomVP{}, TwinScalarFP{}, ProgramPrimitive::TriangleList, std::span<const RandomVertex>(verts));
        counters = dev.counters();
        return hashTargets({t0, t1}, W, H);
    };
    ProgramCounters ref, c;
    const std::string want = render(false, Path::Reference, 1, ref);
    // Pinned like the golden traces: the bytes must not move with the compiler or build type
    // (tests/compilers.sh); a change of the emulated arithmetic updates it and says why.
    EXPECT_EQ(want, "5f7be720b53d46c4d922f514f1e5c139ef60531a9a11da5114f161266951784d")
        << "reproduce: build/bin/test_programmable --gtest_filter='*Twin*'";
    EXPECT_GT(ref.fragmentsDiscarded, 0u);
    EXPECT_GT(ref.fragmentsWritten, 0u);
    for (bool quad : {false, true})
        for (Path path : {Path::Reference, Path::Fast})
            for (int threads : {1, 3}) {
                EXPECT_EQ(render(quad, path, threads, c), want)
                    << (quad ? "quad" : "scalar") << " program, " << (path == Path::Fast ? "fast" : "reference")
                    << " path, " << threads << " threads";
                EXPECT_EQ(c.fragmentInvocations, ref.fragmentInvocations);
                EXPECT_EQ(c.textureFetches, ref.textureFetches);
                EXPECT_EQ(c.maxFetchesPerFragment, ref.maxFetchesPerFragment);
                EXPECT_EQ(c.fragmentsDiscarded, ref.fragmentsDiscarded);
            }
}

// The quad twin written for any context: the fast path runs it on groups of quads
// (QuadGroupContext, interleaved), the reference path quad by quad.
struct TwinGroupFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 3;
    static constexpr uint32_t kUnits = 7;
    static constexpr bool kWritesDepth = false;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V4 = typename Q::Vec4;
        const V4 a = q.varying(0), b = q.varying(1);
        q.discard(a.w > F(0.8f));
        V4 acc = q.sampleLevel(0, a, F(0.0f));
        F t(0.0f);
        auto going = q.active();
        for (int i = 0; i < 6; ++i) {
            going = going & (t < F(2.0f));
            if (!going.any()) break;
            const F h = q.sampleLevel(1, V4(b.x + t, b.y - t, F(0.0f), F(0.0f)), F(0.0f), going).x;
            t = select(going, t + max(h, F(0.125f)), t);
        }
        const V4 e = q.sampleLevel(2, b, F(0.0f)) + q.sample(2, 1);
        q.output(0, acc * t + e);
        q.output(1, V4(t, min(a.x, b.x), a.y / b.w, F(1.0f)), b.z > F(0.5f));
    }
};

static_assert(detail::kIsGroupProgram<TwinGroupFP> && !detail::kIsGroupProgram<TwinQuadFP>);

// Group programs against the scalar twin on the reference path, with an early depth test
// and depth writes between overlapping triangles, on power-of-two WRAP (the interleaved
// fetch), non-power-of-two WRAP and a filtered cube map (quad by quad), any thread count.
// Under RETROGLASS_NO_AVX2 (the ctest ...WithoutAvx2) the SSE2 group kernel runs.
TEST(ProgrammablePathsAgree, GroupProgramEqualsItsScalarTwinWithDepth) {
    const int W = 97, H = 66;
    std::mt19937 rng(4242);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Fixture fx;
    auto makeTex = [&](TexelFormat f, TextureTarget target, int w, int h) {
        return randomFloatTexture(fx, rng, u, f, target, w, h, 13);
    };
    auto rgba = makeTex(TexelFormat::RGBA32F, TextureTarget::Texture2D, 16, 32);
    auto red = makeTex(TexelFormat::R32F, TextureTarget::Texture2D, 20, 8);
    auto redPow2 = makeTex(TexelFormat::R32F, TextureTarget::Texture2D, 32, 8);
    auto cube = makeTex(TexelFormat::RGBA32F, TextureTarget::CubeMap, 8, 8);
    tex::SamplerState point;
    point.magFilter = point.minFilter = tex::FilterMode::Nearest;
    tex::SamplerState pointClamp = point;
    pointClamp.address[0] = tex::AddressMode::ClampToEdge;
    std::vector<RandomVertex> verts;
    for (int i = 0; i < 3 * 40; ++i) {
        verts.push_back(twinVertex(draws(rng, u), true));
    }
    ProgramState st;
    st.depthTest = 1;
    st.depthWrite = 1;
    st.depthFunc = CompareFunc::Less;
    st.blend[1] = TargetBlend{1, BlendFactor::One, BlendFactor::One, BlendOp::Add, kWriteRGBA};
    for (int variant = 0; variant < 2; ++variant) {
        auto render = [&](bool group, Path path, int threads, ProgramCounters& counters) {
            auto t0 = fx.target(W, H, TexelFormat::RGBA8);
            auto t1 = fx.target(W, H, TexelFormat::RGBA32F);
            TextureDesc dd;
            dd.format = TexelFormat::Depth32F;
            dd.width = W;
            dd.height = H;
            auto depth = fx.memory->createRenderTarget(dd);
            ProgrammableDevice dev(g80(), DeviceOptions{path, threads});
            ColorTarget cts[2] = {{t0}, {t1}};
            dev.setRenderTargets(cts, DepthTarget{depth});
            dev.setState(st);
            dev.clearDepth(1.0f);
            dev.setTexture(0, rgba, variant ? pointClamp : point);
            dev.setTexture(1, variant ? redPow2 : red, variant ? point : pointClamp);
            dev.setTexture(2, cube, tex::SamplerState{});
            dev.beginFrame();
            if (group)
                dev.draw(RandomVP{}, TwinGroupFP{}, ProgramPrimitive::TriangleList, std::span<const RandomVertex>(verts));
            else
                dev.draw(RandomVP{}, TwinScalarFP{}, ProgramPrimitive::TriangleList, std::span<const RandomVertex>(verts));
            counters = dev.counters();
            return hashTargets({t0, t1, depth}, W, H);
        };
        ProgramCounters ref, c;
        const std::string want = render(false, Path::Reference, 1, ref);
        EXPECT_GT(ref.fragmentsDepthFailed, 0u);
        EXPECT_GT(ref.fragmentsDiscarded, 0u);
        for (Path path : {Path::Reference, Path::Fast})
            for (int threads : {1, 3}) {
                EXPECT_EQ(render(true, path, threads, c), want)
                    << "variant " << variant << ", " << (path == Path::Fast ? "fast" : "reference") << " path, "
                    << threads << " threads; reproduce: build/bin/test_programmable --gtest_filter='*GroupProgram*'";
                EXPECT_EQ(c.fragmentsGenerated, ref.fragmentsGenerated);
                EXPECT_EQ(c.fragmentsDepthFailed, ref.fragmentsDepthFailed);
                EXPECT_EQ(c.fragmentInvocations, ref.fragmentInvocations);
                EXPECT_EQ(c.fragmentsWritten, ref.fragmentsWritten);
                EXPECT_EQ(c.textureFetches, ref.textureFetches);
                EXPECT_EQ(c.maxFetchesPerFragment, ref.maxFetchesPerFragment);
                EXPECT_EQ(c.fragmentsDiscarded, ref.fragmentsDiscarded);
            }
    }
}

// A program whose lanes never read one another (kLaneIndependent, programmable_device.h):
// the fast path may fill a quad with the pixels of several triangles. The same body twice,
// declared and not; each writes what a fused lane could get wrong — the varyings, 1/w
// (fragCoord.w), window z (fragCoord.z, and the depth test and writes) — and counts, on
// the group contexts, the calls and their live lanes.
struct FusionCounts {
    std::atomic<uint64_t> calls{0}, lanes{0}, mostLanes{0};
};
// kQuads: the AVX2 kernel's group width the program asks for (kWideQuads).
template <bool kFuse, int kQuads = 8>
struct FusionFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 3;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    static constexpr bool kLaneIndependent = kFuse;
    static constexpr int kWideQuads = kQuads;
    FusionCounts* counts = nullptr;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V4 = typename Q::Vec4;
        if constexpr (requires { Q::kQuads; }) {
            const uint64_t n = uint64_t(std::popcount(q.active().bits()));
            counts->calls.fetch_add(1, std::memory_order_relaxed);
            counts->lanes.fetch_add(n, std::memory_order_relaxed);
            uint64_t most = counts->mostLanes.load(std::memory_order_relaxed);
            while (n > most && !counts->mostLanes.compare_exchange_weak(most, n, std::memory_order_relaxed)) {
            }
        }
        const V4 a = q.varying(0), b = q.varying(1), fc = q.fragCoord();
        q.discard(a.w > F(0.9f));
        const V4 c = q.sampleLevel(0, V4(a.x, a.y, b.x, F(0.0f)), F(0.0f));
        q.output(0, V4(a.x + c.x, b.y * c.w, fc.z, fc.w));
        q.output(1, V4(c.y, b.z, a.z, F(1.0f)));
    }
};

// Meshes like the chess pieces' at 600²: a jittered grid of cells about 1.4 pixels wide, two
// triangles a cell sharing their vertices (so a quad's pixels are covered by several
// triangles, each pixel once), in perspective, with a second such mesh crossing the first in
// depth (pixels covered twice: the later quad must wait for the pending one), depth test
// and writes on. Fused or not, on either kernel and any thread count, the bytes and the
// counters are the reference path's; fused, a call shades more live lanes.
TEST(ProgrammablePathsAgree, LaneIndependentProgramsFuseQuadsOfTinyTriangles) {
    const int W = 83, H = 61;
    std::mt19937 rng(777);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Fixture fx;
    auto cube = randomFloatTexture(fx, rng, u, TexelFormat::RGBA32F, TextureTarget::CubeMap, 8, 8, 13);
    tex::SamplerState point;
    point.magFilter = point.minFilter = tex::FilterMode::Nearest;
    std::vector<RandomVertex> verts;
    auto mesh = [&](float z0, float z1, float x0, float x1, float y0, float y1, int n, int m) {
        std::vector<RandomVertex> grid;
        for (int j = 0; j <= m; ++j)
            for (int i = 0; i <= n; ++i) {
                const float px = x0 + (x1 - x0) * (float(i) + (i > 0 && i < n ? 0.3f * (u(rng) - 0.5f) : 0.0f)) / float(n);
                const float py = y0 + (y1 - y0) * (float(j) + (j > 0 && j < m ? 0.3f * (u(rng) - 0.5f) : 0.0f)) / float(m);
                const float w = 0.7f + 0.6f * float(i) / float(n);  // perspective: 1/w varies
                const float z = z0 + (z1 - z0) * float(j) / float(m) + 0.05f * (u(rng) - 0.5f);
                RandomVertex v;
                v.position = glm::vec4(px * w, py * w, z * w, w);
                v.a = glm::vec4(u(rng) * 2 - 1, u(rng) * 2 - 1, u(rng), u(rng));
                v.b = glm::vec4(u(rng) * 2 - 1, u(rng), u(rng), 1.0f);
                grid.push_back(v);
            }
        auto at = [&](int i, int j) { return grid[size_t(j * (n + 1) + i)]; };
        for (int j = 0; j < m; ++j)
            for (int i = 0; i < n; ++i) {
                const bool flip = (i + j) % 3 == 0;  // both diagonals
                const RandomVertex p00 = at(i, j), p10 = at(i + 1, j), p01 = at(i, j + 1), p11 = at(i + 1, j + 1);
                for (const RandomVertex& v : flip ? std::array{p00, p10, p11, p00, p11, p01}
                                                   : std::array{p00, p10, p01, p10, p11, p01})
                    verts.push_back(v);
            }
    };
    mesh(-0.4f, 0.4f, -0.9f, 0.7f, -0.85f, 0.75f, 40, 30);
    mesh(0.5f, -0.5f, -0.5f, 0.95f, -0.6f, 0.9f, 35, 35);
    ProgramState st;
    st.depthTest = 1;
    st.depthWrite = 1;
    st.depthFunc = CompareFunc::Less;
    st.blend[1] = TargetBlend{1, BlendFactor::One, BlendFactor::One, BlendOp::Add, kWriteRGBA};
    // quads: the program's kWideQuads (8, the default, or 4 or 2).
    auto render = [&](bool fuse, Path path, int threads, ProgramCounters& counters, FusionCounts& fcount,
                      int quads = 8) {
        auto t0 = fx.target(W, H, TexelFormat::RGBA32F);
        auto t1 = fx.target(W, H, TexelFormat::RGBA8);
        TextureDesc dd;
        dd.format = TexelFormat::Depth24;
        dd.width = W;
        dd.height = H;
        auto depth = fx.memory->createRenderTarget(dd);
        ProgrammableDevice dev(g80(), DeviceOptions{path, threads});
        ColorTarget cts[2] = {{t0}, {t1}};
        dev.setRenderTargets(cts, DepthTarget{depth});
        dev.setState(st);
        dev.clearDepth(1.0f);
        dev.setTexture(0, cube, point);
        dev.beginFrame();
        const std::span<const RandomVertex> v(verts);
        if (fuse && quads == 4)
            dev.draw(RandomVP{}, FusionFP<true, 4>{&fcount}, ProgramPrimitive::TriangleList, v);
        else if (fuse && quads == 2)
            dev.draw(RandomVP{}, FusionFP<true, 2>{&fcount}, ProgramPrimitive::TriangleList, v);
        else if (fuse)
            dev.draw(RandomVP{}, FusionFP<true>{&fcount}, ProgramPrimitive::TriangleList, v);
        else
            dev.draw(RandomVP{}, FusionFP<false>{&fcount}, ProgramPrimitive::TriangleList, v);
        counters = dev.counters();
        return hashTargets({t0, t1, depth}, W, H);
    };
    ProgramCounters ref, c;
    FusionCounts none, plain, fused;
    const std::string want = render(false, Path::Reference, 1, ref, none);
    EXPECT_GT(ref.fragmentsDepthFailed, 100u) << "the second mesh must cross the first";
    EXPECT_GT(ref.fragmentsDiscarded, 0u);
    EXPECT_GT(ref.fragmentsWritten, 2000u);
    for (bool fuse : {false, true})
        for (int threads : {1, 3}) {
            FusionCounts& fc = threads == 1 ? (fuse ? fused : plain) : none;
            EXPECT_EQ(render(fuse, Path::Fast, threads, c, fc), want)
                << (fuse ? "fused" : "not fused") << ", " << threads
                << " threads; reproduce: build/bin/test_programmable --gtest_filter='*FuseQuads*'";
            EXPECT_EQ(c.fragmentsGenerated, ref.fragmentsGenerated);
            EXPECT_EQ(c.fragmentsDepthFailed, ref.fragmentsDepthFailed);
            EXPECT_EQ(c.fragmentInvocations, ref.fragmentInvocations);
            EXPECT_EQ(c.fragmentsWritten, ref.fragmentsWritten);
            EXPECT_EQ(c.textureFetches, ref.textureFetches);
            EXPECT_EQ(c.maxFetchesPerFragment, ref.maxFetchesPerFragment);
            EXPECT_EQ(c.fragmentsDiscarded, ref.fragmentsDiscarded);
        }
    // Fusion happened: the same live lanes in about a third of the calls. Unfused, a quad of
    // this mesh holds one triangle's part of it (8.9 of a call's 32 lanes on the AVX2 kernel,
    // 4.5 of 16 on SSE2); fused, the pool fills it (27.9 and 14.1).
    ASSERT_GT(plain.calls.load(), 0u);
    ASSERT_GT(fused.calls.load(), 0u);
    EXPECT_EQ(fused.lanes.load(), plain.lanes.load());
    const double plainFill = double(plain.lanes.load()) / double(plain.calls.load());
    const double fusedFill = double(fused.lanes.load()) / double(fused.calls.load());
    EXPECT_GT(fusedFill, 2.5 * plainFill) << "lanes per call: fused " << fusedFill << ", not fused " << plainFill;
    std::printf("lanes per call: fused %.2f, not fused %.2f\n", fusedFill, plainFill);

    // A program's own group width (kWideQuads): the same bytes and counters, and on the AVX2
    // kernel calls of at most 4·kWideQuads lanes, some of them full (SSE2 runs four quads
    // whatever the program asks).
    for (int quads : {4, 2}) {
        FusionCounts narrow;
        EXPECT_EQ(render(true, Path::Fast, 1, c, narrow, quads), want) << "kWideQuads " << quads;
        EXPECT_EQ(c.fragmentInvocations, ref.fragmentInvocations);
        EXPECT_EQ(c.fragmentsWritten, ref.fragmentsWritten);
        EXPECT_EQ(c.textureFetches, ref.textureFetches);
        EXPECT_EQ(c.fragmentsDiscarded, ref.fragmentsDiscarded);
        EXPECT_EQ(narrow.lanes.load(), plain.lanes.load());
        EXPECT_EQ(narrow.mostLanes.load(), uint64_t(detail::programAvx2() ? 4 * quads : 16)) << "kWideQuads " << quads;
    }
    if (detail::programAvx2()) {
        EXPECT_EQ(fused.mostLanes.load(), 32u);
    }
}

// Fetch counts around a discard: a point-sampled fetch of every live lane, a discard that
// depends on it, a second unmasked fetch and a masked third. The wide group kernel counts
// its unmasked fetches once per call and adds them to the lanes live at the time (before a
// discard changes them), so each lane's count must still be what the scalar twin counts:
// 1 for a discarded fragment, 2 or 3 for the others.
struct FetchDiscardScalarFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const {
        const glm::vec4 a = f.varying(0), b = f.varying(1);
        const float h = f.sampleLevel(0, a, 0.0f).x;
        if (h > 0.6f) {
            f.discard();
            return;
        }
        const float g = f.sampleLevel(0, b, 0.0f).x;
        float k = 0.0f;
        if (b.z > 0.5f) k = f.sampleLevel(0, a + b, 0.0f).x;
        f.output(0, glm::vec4(h, g, k, 1.0f));
    }
};

struct FetchDiscardGroupFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V4 = typename Q::Vec4;
        const V4 a = q.varying(0), b = q.varying(1);
        const F h = q.sampleLevel(0, a, F(0.0f)).x;
        q.discard(h > F(0.6f));
        const F g = q.sampleLevel(0, b, F(0.0f)).x;
        const auto third = b.z > F(0.5f);
        const F k = select(third, q.sampleLevel(0, a + b, F(0.0f), third).x, F(0.0f));
        q.output(0, V4(h, g, k, F(1.0f)));
    }
};

static_assert(detail::kIsGroupProgram<FetchDiscardGroupFP>);

TEST(ProgrammablePathsAgree, GroupFetchCountsAroundADiscardEqualTheScalarTwin) {
    const int W = 83, H = 61;
    std::mt19937 rng(777);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    Fixture fx;
    auto red = randomFloatTexture(fx, rng, u, TexelFormat::R32F, TextureTarget::Texture2D, 32, 16, 11);
    tex::SamplerState point;
    point.magFilter = point.minFilter = tex::FilterMode::Nearest;
    std::vector<RandomVertex> verts;
    for (int i = 0; i < 3 * 24; ++i) verts.push_back(twinVertex(draws(rng, u), false));
    auto render = [&](bool group, Path path, int threads, ProgramCounters& counters) {
        auto t0 = fx.target(W, H, TexelFormat::RGBA8);
        ProgrammableDevice dev(g80(), DeviceOptions{path, threads});
        ColorTarget ct{t0};
        dev.setRenderTargets({&ct, 1});
        dev.setTexture(0, red, point);
        dev.beginFrame();
        if (group)
            dev.draw(RandomVP{}, FetchDiscardGroupFP{}, ProgramPrimitive::TriangleList,
                     std::span<const RandomVertex>(verts));
        else
            dev.draw(RandomVP{}, FetchDiscardScalarFP{}, ProgramPrimitive::TriangleList,
                     std::span<const RandomVertex>(verts));
        counters = dev.counters();
        return hashTargets({t0}, W, H);
    };
    ProgramCounters ref, c;
    const std::string want = render(false, Path::Reference, 1, ref);
    ASSERT_GT(ref.fragmentsDiscarded, 100u);
    ASSERT_GT(ref.fragmentInvocations, ref.fragmentsDiscarded + 100u);
    for (Path path : {Path::Reference, Path::Fast})
        for (int threads : {1, 2}) {
            EXPECT_EQ(render(true, path, threads, c), want)
                << (path == Path::Fast ? "fast" : "reference") << " path, " << threads << " threads";
            EXPECT_EQ(c.textureFetches, ref.textureFetches);
            EXPECT_EQ(c.maxFetchesPerFragment, ref.maxFetchesPerFragment);
            EXPECT_EQ(c.fragmentsDiscarded, ref.fragmentsDiscarded);
            EXPECT_EQ(c.fragmentsWritten, ref.fragmentsWritten);
        }
}

// The RGBA8 conversion of whole quads (the AVX2 kernel converts two at a time) at the values
// where rounding decides: each pixel writes its own texel of a 64×64 R32F texture in all
// four channels, the texels a few ulps around (k + ½)/255 and 0.5/255, where x·255 + ½ sits
// at or next to an integer, and NaN, ±∞, −0 and values outside [0, 1] — against the scalar
// twin on the reference path.
struct TexelColourScalarFP {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const {
        const glm::vec4 c = f.fragCoord() * (1.0f / 64.0f);
        f.output(0, glm::vec4(f.sampleLevel(0, c, 0.0f).x));
    }
};

struct TexelColourGroupFP {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V4 = typename Q::Vec4;
        const V4 fc = q.fragCoord();
        const F s = F(1.0f / 64.0f);
        const F v = q.sampleLevel(0, V4(fc.x * s, fc.y * s, fc.z * s, fc.w * s), F(0.0f)).x;
        q.output(0, V4(v, v, v, v));
    }
};

TEST(ProgrammablePathsAgree, GroupRgba8ConversionAtRoundingEdgesEqualsTheScalarTwin) {
    const int S = 64;
    Fixture fx;
    TextureDesc d;
    d.format = TexelFormat::R32F;
    d.width = d.height = S;
    auto tex = fx.memory->create(d);
    std::vector<uint8_t> bytes(size_t(S) * S * 4);
    for (int i = 0; i < S * S; ++i) {
        float v = i < 256 ? 0.5f / 255.0f : (float(i % 256) + 0.5f) / 255.0f;  // ties, then near ties
        for (int step = 0, ulps = (i / 7) % 9 - 4; step < std::abs(ulps); ++step)
            v = std::nextafter(v, ulps < 0 ? 0.0f : 2.0f);
        if (i >= S * S - 64) {  // and what the clamp decides: NaN → 0, ±∞, −0, out of [0, 1]
            const float special[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                                     -std::numeric_limits<float>::infinity(), -0.0f, -1.0f, 2.0f, 1.0000001f, 0.0f};
            v = special[i % 8];
        }
        std::memcpy(&bytes[size_t(i) * 4], &v, 4);
    }
    fx.memory->upload(*tex, 0, 0, bytes);
    tex::SamplerState point;
    point.magFilter = point.minFilter = tex::FilterMode::Nearest;
    auto verts = rect(S, S, 0, 0, S, S, 0.5f, {}, {}, {}, {});
    auto render = [&](bool group, Path path, int threads) {
        auto t0 = fx.target(S, S, TexelFormat::RGBA8);
        ProgrammableDevice dev(g80(), DeviceOptions{path, threads});
        ColorTarget ct{t0};
        dev.setRenderTargets({&ct, 1});
        dev.setTexture(0, tex, point);
        if (group)
            dev.draw(PassVP{}, TexelColourGroupFP{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(verts));
        else
            dev.draw(PassVP{}, TexelColourScalarFP{}, ProgramPrimitive::TriangleList, std::span<const ScreenVertex>(verts));
        return hashTargets({t0}, S, S);
    };
    const std::string want = render(false, Path::Reference, 1);
    for (Path path : {Path::Reference, Path::Fast})
        for (int threads : {1, 2})
            EXPECT_EQ(render(true, path, threads), want)
                << (path == Path::Fast ? "fast" : "reference") << " path, " << threads << " threads";
}

}  // namespace
}  // namespace rg::raster
