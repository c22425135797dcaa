// Sampling: addressing at texel centres and edges, level of detail, level choice, 4D
// quadrilinear filtering, and the fast filter against the reference tap list
// (docs/hardware.md, "Level of detail", "Filtering").
#include <gtest/gtest.h>

#include <cmath>

#include "tex_test_util.h"
#include "texunit/cube_mapping.h"
#include "texunit/sampler.h"

namespace rg::tex {
namespace {

using testing::makeRgba8;
using testing::Rng;

constexpr uint8_t kT[4] = {10, 50, 90, 200};
constexpr uint8_t kBorder = 255;
constexpr int32_t kMagnify = -(1 << 20);

struct AddressFixture {
    TextureMemory mem{profile(ProfileId::GeForce256)};
    std::shared_ptr<Texture> tex = makeRgba8(
        mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 4, 2, 1, 1, 1},
        [](int, int, int x, int, int, int) { return Rgba8{kT[x], 0, 0, 255}; });
    uint8_t sample(AddressMode m, FilterMode f, float s) {
        SamplerState st;
        st.address = {m, AddressMode::ClampToEdge, m, m};
        st.magFilter = st.minFilter = f;
        st.borderColor = {kBorder, 0, 0, 0};
        TapList taps;
        // t at a row centre so only s matters.
        gatherTaps(*tex, st, glm::vec4(s, 0.25f, 0, 0), kMagnify, taps);
        return resolveTaps(*tex, st, taps).r;
    }
};

constexpr uint8_t avg(int a, int b) { return uint8_t((a + b + 1) >> 1); }  // weights ½, ½, half up

TEST(SamplerAddressing, TexelCentresAreExactUnderEveryMode) {
    AddressFixture fx;
    for (AddressMode m : {AddressMode::Wrap, AddressMode::Mirror, AddressMode::Clamp,
                          AddressMode::ClampToEdge, AddressMode::Border})
        for (FilterMode f : {FilterMode::Nearest, FilterMode::Linear})
            for (int i = 0; i < 4; ++i)
                EXPECT_EQ(fx.sample(m, f, (i + 0.5f) / 4.0f), kT[i])
                    << "mode " << int(m) << " filter " << int(f) << " texel " << i;
}

TEST(SamplerAddressing, EdgesAndOutsideLinear) {
    AddressFixture fx;
    const auto L = FilterMode::Linear;
    // s = 0: u − ½ = −½, taps −1 and 0 with weights ½, ½.
    EXPECT_EQ(fx.sample(AddressMode::Wrap, L, 0.0f), avg(kT[3], kT[0]));
    EXPECT_EQ(fx.sample(AddressMode::Mirror, L, 0.0f), kT[0]);
    EXPECT_EQ(fx.sample(AddressMode::ClampToEdge, L, 0.0f), kT[0]);
    EXPECT_EQ(fx.sample(AddressMode::Clamp, L, 0.0f), avg(kBorder, kT[0]));
    EXPECT_EQ(fx.sample(AddressMode::Border, L, 0.0f), avg(kBorder, kT[0]));
    // s = 1: taps 3 and 4.
    EXPECT_EQ(fx.sample(AddressMode::Wrap, L, 1.0f), avg(kT[3], kT[0]));
    EXPECT_EQ(fx.sample(AddressMode::Mirror, L, 1.0f), kT[3]);
    EXPECT_EQ(fx.sample(AddressMode::ClampToEdge, L, 1.0f), kT[3]);
    EXPECT_EQ(fx.sample(AddressMode::Clamp, L, 1.0f), avg(kT[3], kBorder));
    EXPECT_EQ(fx.sample(AddressMode::Border, L, 1.0f), avg(kT[3], kBorder));
    // s = 1.25: taps 4 and 5 (weights ½, ½).
    EXPECT_EQ(fx.sample(AddressMode::Wrap, L, 1.25f), avg(kT[0], kT[1]));
    EXPECT_EQ(fx.sample(AddressMode::Mirror, L, 1.25f), avg(kT[3], kT[2]));
    EXPECT_EQ(fx.sample(AddressMode::ClampToEdge, L, 1.25f), kT[3]);
    EXPECT_EQ(fx.sample(AddressMode::Clamp, L, 1.25f), avg(kT[3], kBorder));  // s clamped to 1
    EXPECT_EQ(fx.sample(AddressMode::Border, L, 1.25f), kBorder);
    // A quarter of the way: s = 0.1875 → u − ½ = 0.25: ¾·T0 + ¼·T1 = 20 exactly.
    EXPECT_EQ(fx.sample(AddressMode::Wrap, L, 0.1875f), 20);
    // Mirror repeats with period 2: s = −0.125 → u − ½ = −1, tap −1 → texel 0.
    EXPECT_EQ(fx.sample(AddressMode::Mirror, L, -0.125f), kT[0]);
}

TEST(SamplerAddressing, EdgesAndOutsideNearest) {
    AddressFixture fx;
    const auto N = FilterMode::Nearest;
    for (AddressMode m : {AddressMode::Wrap, AddressMode::Mirror, AddressMode::Clamp,
                          AddressMode::ClampToEdge, AddressMode::Border})
        EXPECT_EQ(fx.sample(m, N, 0.0f), kT[0]) << int(m);
    // s = 1: ⌊u⌋ = 4.
    EXPECT_EQ(fx.sample(AddressMode::Wrap, N, 1.0f), kT[0]);
    EXPECT_EQ(fx.sample(AddressMode::Mirror, N, 1.0f), kT[3]);
    EXPECT_EQ(fx.sample(AddressMode::ClampToEdge, N, 1.0f), kT[3]);
    EXPECT_EQ(fx.sample(AddressMode::Clamp, N, 1.0f), kT[3]);  // GL 1.2: u = n → n − 1
    EXPECT_EQ(fx.sample(AddressMode::Border, N, 1.0f), kBorder);
    // Just below 0: ⌊u⌋ = −1.
    EXPECT_EQ(fx.sample(AddressMode::Wrap, N, -0.01f), kT[3]);
    EXPECT_EQ(fx.sample(AddressMode::Mirror, N, -0.01f), kT[0]);
    EXPECT_EQ(fx.sample(AddressMode::ClampToEdge, N, -0.01f), kT[0]);
    EXPECT_EQ(fx.sample(AddressMode::Clamp, N, -0.01f), kT[0]);
    EXPECT_EQ(fx.sample(AddressMode::Border, N, -0.01f), kBorder);
    // The texel edge between 1 and 2 (s = 0.5) belongs to texel 2.
    EXPECT_EQ(fx.sample(AddressMode::Wrap, N, 0.5f), kT[2]);
}

TEST(SamplerAddressing, NonPowerOfTwoWrapAndMirror) {
    // geforce8800 takes a 3-texel row: WRAP and MIRROR need a true remainder there.
    TextureMemory mem(profile(ProfileId::GeForce8800));
    const uint8_t v[3] = {10, 50, 90};
    auto t = makeRgba8(mem, {TextureTarget::Texture1D, TexelFormat::RGBA8, 3, 1, 1, 1, 1},
                       [&](int, int, int x, int, int, int) { return Rgba8{v[x], 0, 0, 255}; });
    auto at = [&](AddressMode m, float s) {
        SamplerState st;
        st.address[0] = m;
        st.magFilter = st.minFilter = FilterMode::Nearest;
        TapList taps;
        gatherTaps(*t, st, glm::vec4(s, 0, 0, 0), kMagnify, taps);
        EXPECT_EQ(sampleFast(*t, st, glm::vec4(s, 0, 0, 0), kMagnify), resolveTaps(*t, st, taps));
        return resolveTaps(*t, st, taps).r;
    };
    EXPECT_EQ(at(AddressMode::Wrap, -0.1f), 90);    // ⌊−0.3⌋ = −1 → 2
    EXPECT_EQ(at(AddressMode::Mirror, -0.1f), 10);  // −1 → 0
    EXPECT_EQ(at(AddressMode::Wrap, 1.5f), 50);     // 4 → 1
    EXPECT_EQ(at(AddressMode::Mirror, 1.5f), 50);   // 4 → 6 − 1 − 4 = 1
    EXPECT_EQ(at(AddressMode::Wrap, 2.2f), 10);     // 6 → 0
    EXPECT_EQ(at(AddressMode::Mirror, 2.2f), 10);   // 6 → 0
    EXPECT_EQ(at(AddressMode::Mirror, -0.5f), 50);  // ⌊−1.5⌋ = −2 → 4 → 6 − 1 − 4 = 1
    EXPECT_EQ(at(AddressMode::Wrap, -0.5f), 50);    // −2 → 1
}

TEST(SamplerLod, Log2ApproximationIsExactAtPowersOfTwoAndAtMost0p087Low) {
    EXPECT_EQ(log2Fixed(1.0f), 0);
    EXPECT_EQ(log2Fixed(2.0f), 256);
    EXPECT_EQ(log2Fixed(0.5f), -256);
    EXPECT_EQ(log2Fixed(1024.0f), 2560);
    EXPECT_EQ(log2Fixed(3.0f), 384);  // 1 + (1.5 − 1) = 1.5 against log2 3 = 1.585
    Rng rng(1);
    for (int i = 0; i < 100000; ++i) {
        float x = std::exp2(rng.uniform(-20, 20));
        double err = std::log2(double(x)) - log2Fixed(x) / 256.0;
        ASSERT_GE(err, -1e-9) << x;
        ASSERT_LT(err, 0.0861 + 1.0 / 256.0) << x;
    }
}

TEST(SamplerLod, LambdaAtKnownDerivatives) {
    const std::array<int, 4> size{64, 64, 1, 1};
    auto quad = [](float dsdx, float dtdx, float dsdy, float dtdy) {
        const glm::vec4 p0(0.25f, 0.5f, 0, 0);  // dyadic: the differences are exact
        return std::array<glm::vec4, 4>{p0, p0 + glm::vec4(dsdx, dtdx, 0, 0),
                                        p0 + glm::vec4(dsdy, dtdy, 0, 0),
                                        p0 + glm::vec4(dsdx + dsdy, dtdx + dtdy, 0, 0)};
    };
    EXPECT_EQ(quadLambda(quad(1 / 64.f, 0, 0, 1 / 64.f), size, 2), 0);      // one texel per pixel
    EXPECT_EQ(quadLambda(quad(2 / 64.f, 0, 0, 1 / 64.f), size, 2), 256);    // 2 texels in x
    EXPECT_EQ(quadLambda(quad(0, 0, 0, 4 / 64.f), size, 2), 512);           // 4 texels in y
    EXPECT_EQ(quadLambda(quad(0, 8 / 64.f, 0, 0), size, 2), 768);           // t along x counts
    // ρ = 3: ρ² = 9 → log2approx 3.125 → λ = 1.5625 = 400/256.
    EXPECT_EQ(quadLambda(quad(3 / 64.f, 0, 0, 1 / 64.f), size, 2), 400);
    // ρ = 5 from (3, 4) along x: ρ² = 25 → 4 + 0.5625 → λ = 2.28125 = 584/256.
    EXPECT_EQ(quadLambda(quad(3 / 64.f, 4 / 64.f, 0, 0), size, 2), 584);
    // Half a texel per pixel: magnification, λ = −1.
    EXPECT_EQ(quadLambda(quad(0.5f / 64.f, 0, 0, 0.5f / 64.f), size, 2), -256);
}

struct MipFixture {
    TextureMemory mem{profile(ProfileId::GeForce256)};
    std::shared_ptr<Texture> tex = makeRgba8(
        mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 64, 64, 1, 1, 7},
        [](int l, int, int, int, int, int) { return Rgba8{uint8_t(l * 30), 0, 0, 255}; });
};

TEST(SamplerLod, NearestMipRoundsHalfIntegerDown) {
    MipFixture fx;
    SamplerState s;
    s.minFilter = FilterMode::Nearest;
    s.magFilter = FilterMode::Nearest;
    s.mipFilter = MipMode::Nearest;
    EXPECT_EQ(chooseLevels(*fx.tex, s, 384).level0, 1);  // λ = 1.5 → level 1
    EXPECT_EQ(chooseLevels(*fx.tex, s, 385).level0, 2);  // just above → level 2
    EXPECT_EQ(chooseLevels(*fx.tex, s, 128).level0, 0);  // λ = 0.5 → level 0
    EXPECT_EQ(chooseLevels(*fx.tex, s, 129).level0, 1);
    EXPECT_EQ(chooseLevels(*fx.tex, s, 100 * 256).level0, 6);  // the last level
    // The same through bias: λ = 1 at derivatives of 2 texels, bias +0.5 → level 1.
    s.lodBias = 0.5f;
    EXPECT_EQ(biasAndClampLambda(256, s), 384);
}

TEST(SamplerLod, LinearMipWeightsAndClamps) {
    MipFixture fx;
    SamplerState s;
    s.mipFilter = MipMode::Linear;
    LevelChoice c = chooseLevels(*fx.tex, s, 400);  // λ = 1.5625
    EXPECT_TRUE(c.blend);
    EXPECT_EQ(c.level0, 1);
    EXPECT_EQ(c.level1, 2);
    EXPECT_EQ(c.frac, 144);
    // 30·(112/256) + 60·(144/256) = 46.875 → 47.
    TapList taps;
    gatherTaps(*fx.tex, s, glm::vec4(0.3f, 0.3f, 0, 0), 400, taps);
    EXPECT_EQ(taps.count, 8);
    EXPECT_EQ(taps.weightBits, 24);
    EXPECT_EQ(resolveTaps(*fx.tex, s, taps).r, 47);
    // Level clamps: MAX_LEVEL 2 stops at level 2, BASE_LEVEL 3 starts at level 3.
    s.maxLevel = 2;
    EXPECT_EQ(chooseLevels(*fx.tex, s, 5 * 256).level0, 2);
    EXPECT_FALSE(chooseLevels(*fx.tex, s, 5 * 256).blend);
    s.maxLevel = 1000;
    s.baseLevel = 3;
    EXPECT_EQ(chooseLevels(*fx.tex, s, -100).level0, 3);
    EXPECT_EQ(chooseLevels(*fx.tex, s, 256).level0, 4);  // λ counts from the base level
    // Out of range (pinned, docs/hardware.md): a MAX_LEVEL past the 7 levels is the last,
    // one below the base is the base; a negative BASE_LEVEL is 0, one past the last the last.
    EXPECT_EQ(chooseLevels(*fx.tex, s, 100 * 256).level0, 6);
    s.maxLevel = 1;
    EXPECT_EQ(chooseLevels(*fx.tex, s, 100 * 256).level0, 3);
    s.maxLevel = 1000;
    s.baseLevel = -5;
    EXPECT_EQ(chooseLevels(*fx.tex, s, -100).level0, 0);
    s.baseLevel = 9;
    EXPECT_EQ(chooseLevels(*fx.tex, s, -100).level0, 6);
    EXPECT_EQ(chooseLevels(*fx.tex, s, 3 * 256).level0, 6);
    s.baseLevel = 3;
    // MIN_LOD / MAX_LOD clamp λ after the bias.
    SamplerState c2;
    c2.minLod = 1.0f;
    c2.maxLod = 2.5f;
    EXPECT_EQ(biasAndClampLambda(0, c2), 256);
    EXPECT_EQ(biasAndClampLambda(1000, c2), 640);
    // Magnification switch-over c = ½ for LINEAR mag with NEAREST_MIPMAP_*.
    SamplerState m;
    m.magFilter = FilterMode::Linear;
    m.minFilter = FilterMode::Nearest;
    m.mipFilter = MipMode::Nearest;
    EXPECT_EQ(chooseLevels(*fx.tex, m, 128).filter, FilterMode::Linear);
    EXPECT_EQ(chooseLevels(*fx.tex, m, 129).filter, FilterMode::Nearest);
}

TEST(Sampler4D, QuadrilinearAtAKnownPoint) {
    TextureMemory mem(profile(ProfileId::SgiOctaneMxe));
    auto t = makeRgba8(mem, {TextureTarget::Texture4D, TexelFormat::RGBA8, 4, 4, 4, 4, 1},
                       [](int, int, int x, int y, int z, int w) {
                           return Rgba8{uint8_t(3 * x + 5 * y + 7 * z + 11 * w), uint8_t(x * 60),
                                        uint8_t(w * 60), 255};
                       });
    SamplerState s;
    s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge,
                 AddressMode::ClampToEdge};
    // u − ½ = (1.25, 2.5, 0.75, 1.0): a linear function is reproduced exactly:
    // 3·1.25 + 5·2.5 + 7·0.75 + 11·1 = 32.5, which rounds half up to 33.
    TapList taps;
    gatherTaps(*t, s, glm::vec4(0.4375f, 0.75f, 0.3125f, 0.375f), kMagnify, taps);
    EXPECT_EQ(taps.count, 16);
    EXPECT_EQ(taps.weightBits, 32);
    uint64_t sum = 0;
    for (int i = 0; i < taps.count; ++i) sum += taps.taps[size_t(i)].weight;
    EXPECT_EQ(sum, uint64_t(1) << 32);
    Rgba8 c = resolveTaps(*t, s, taps);
    EXPECT_EQ(c.r, 33);
    EXPECT_EQ(c.g, 75);  // 60·1.25
    EXPECT_EQ(c.b, 60);  // 60·1.0
    // At a 4D texel centre the texel itself comes back.
    gatherTaps(*t, s, glm::vec4(2.5f / 4, 0.5f / 4, 3.5f / 4, 1.5f / 4), kMagnify, taps);
    EXPECT_EQ(resolveTaps(*t, s, taps).r, 3 * 2 + 5 * 0 + 7 * 3 + 11 * 1);
    // Q wraps like S, T, R: q = 1.375 is q = 0.375.
    s.address[3] = AddressMode::Wrap;
    gatherTaps(*t, s, glm::vec4(2.5f / 4, 0.5f / 4, 3.5f / 4, 1.375f), kMagnify, taps);
    EXPECT_EQ(resolveTaps(*t, s, taps).r, 3 * 2 + 5 * 0 + 7 * 3 + 11 * 1);
}

TEST(SamplerCube, FacesFilterClampToEdgeWhateverTheSamplerSays) {
    TextureMemory mem(profile(ProfileId::GeForce256));
    auto cube = makeRgba8(mem, {TextureTarget::CubeMap, TexelFormat::RGBA8, 8, 8, 1, 1, 1},
                          [](int, int f, int x, int, int, int) { return Rgba8{uint8_t(f * 20 + x * 10), 0, 0, 255}; });
    SamplerState s;  // WRAP on every axis: ignored on cube faces
    for (int f = 0; f < 6; ++f) {
        TapList taps;
        // s = 0 with LINEAR: WRAP would mix texel 7 in (f·20 + 35); the edge gives f·20.
        gatherTaps(*cube, s, glm::vec4(0.0f, 0.5f, float(f), 0), kMagnify, taps);
        EXPECT_EQ(resolveTaps(*cube, s, taps).r, f * 20) << "face " << f;
        for (int i = 0; i < taps.count; ++i) EXPECT_EQ(taps.taps[size_t(i)].face, f);
        EXPECT_EQ(sampleFast(*cube, s, glm::vec4(1.0f, 0.5f, float(f), 0), kMagnify).r, f * 20 + 70);
    }
}

TEST(Sampler4D, MipmappedQuadrilinearHas32TapsOf40Bits) {
    TextureMemory mem(profile(ProfileId::SgiOctaneMxe));
    auto t = makeRgba8(mem, {TextureTarget::Texture4D, TexelFormat::RGBA8, 4, 4, 4, 4, 3},
                       [](int l, int, int, int, int, int) { return Rgba8{uint8_t(100 * l), 0, 0, 255}; });
    SamplerState s;
    s.mipFilter = MipMode::Linear;
    TapList taps;
    gatherTaps(*t, s, glm::vec4(0.3f, 0.6f, 0.2f, 0.9f), 64, taps);  // λ = ¼ between levels 0, 1
    EXPECT_EQ(taps.count, 32);
    EXPECT_EQ(taps.weightBits, 40);
    uint64_t sum = 0;
    for (int i = 0; i < taps.count; ++i) sum += taps.taps[size_t(i)].weight;
    EXPECT_EQ(sum, uint64_t(1) << 40);
    EXPECT_EQ(resolveTaps(*t, s, taps).r, 25);  // 0·¾ + 100·¼
}

TEST(Sampler3D, TrilinearReproducesALinearFunction) {
    TextureMemory mem(profile(ProfileId::SgiOctaneMxe));
    auto t = makeRgba8(mem, {TextureTarget::Texture3D, TexelFormat::RGBA8, 8, 4, 2, 1, 1},
                       [](int, int, int x, int y, int z, int) {
                           return Rgba8{uint8_t(10 * x + 20 * y + 40 * z), 0, 0, 255};
                       });
    SamplerState s;
    s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge,
                 AddressMode::ClampToEdge};
    // u − ½ = (2.25, 1.5, 0.75): 22.5 + 30 + 30 = 82.5 → 83 (half up).
    TapList taps;
    gatherTaps(*t, s, glm::vec4(2.75f / 8, 2.0f / 4, 1.25f / 2, 0), kMagnify, taps);
    EXPECT_EQ(taps.count, 8);
    EXPECT_EQ(resolveTaps(*t, s, taps).r, 83);
}

TEST(SamplerFastPath, MatchesReferenceUnderRandomStates) {
    TextureMemory mem(profile(ProfileId::GeForce8800));
    Rng rng(2024);
    int samples = 0;
    for (int texI = 0; texI < 60; ++texI) {
        const int kind = int(rng.below(3));
        TextureDesc d;
        d.target = kind == 0 ? TextureTarget::Texture1D
                   : kind == 1 ? TextureTarget::Texture2D
                               : TextureTarget::CubeMap;
        d.width = 1 << rng.below(6);
        d.height = kind == 0 ? 1 : (kind == 2 ? d.width : 1 << rng.below(6));
        d.levels = 1 + int(rng.below(uint32_t(fullChainLevels(d))));
        const uint32_t seed = rng.next();
        auto t = makeRgba8(mem, d, [&](int l, int f, int x, int y, int, int) {
            uint32_t h = testing::hash32(seed ^ uint32_t(l * 7919 + f * 104729 + x * 31 + y * 1031));
            return Rgba8{uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
        });
        for (int k = 0; k < 4000; ++k) {
            SamplerState s;
            for (auto& a : s.address) a = AddressMode(rng.below(5));
            s.magFilter = FilterMode(rng.below(2));
            s.minFilter = FilterMode(rng.below(2));
            s.mipFilter = MipMode(rng.below(3));
            s.baseLevel = int(rng.below(3));
            s.maxLevel = int(rng.below(8));
            s.borderColor = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()),
                             uint8_t(rng.next())};
            glm::vec4 c;
            if (d.target == TextureTarget::CubeMap) {
                CubeCoord cc = selectCubeFace({rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)});
                c = glm::vec4(cc.s, cc.t, float(int(cc.face)), 0);
            } else {
                c = glm::vec4(rng.uniform(-2, 3), rng.uniform(-2, 3), 0, 0);
            }
            int32_t lambda = int32_t(rng.below(8 * 256)) - 2 * 256;
            TapList taps;
            gatherTaps(*t, s, c, lambda, taps);
            ASSERT_EQ(sampleFast(*t, s, c, lambda), resolveTaps(*t, s, taps))
                << "texture " << texI << " sample " << k << " (seed 2024)";
            ++samples;
        }
    }
    EXPECT_EQ(samples, 240000);
}

TEST(SamplerFloat, FloatTexturesFilterInFloatAndConvertOnce) {
    TextureMemory mem(profile(ProfileId::GeForce8800));
    auto t = mem.create({TextureTarget::Texture2D, TexelFormat::R32F, 2, 1, 1, 1, 1});
    float v[2] = {0.25f, 0.75f};
    mem.upload(*t, 0, 0, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(v), 8));
    SamplerState s;
    s.address[0] = AddressMode::ClampToEdge;
    TapList taps;
    gatherTaps(*t, s, glm::vec4(0.5f, 0.5f, 0, 0), kMagnify, taps);  // halfway: 0.5
    EXPECT_EQ(resolveTaps(*t, s, taps), (Rgba8{128, 0, 0, 255}));
    EXPECT_EQ(sampleFast(*t, s, glm::vec4(0.5f, 0.5f, 0, 0), kMagnify), (Rgba8{128, 0, 0, 255}));
    EXPECT_EQ(resolveTapsFloat(*t, s, taps), glm::vec4(0.5f, 0.0f, 0.0f, 1.0f));  // unrounded
    // Values outside [0, 1] survive in float and clamp only on the way to 8 bits.
    float big[2] = {4.0f, -2.0f};
    mem.upload(*t, 0, 0, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(big), 8));
    gatherTaps(*t, s, glm::vec4(0.5f, 0.5f, 0, 0), kMagnify, taps);
    EXPECT_EQ(resolveTapsFloat(*t, s, taps).x, 1.0f);
    EXPECT_EQ(resolveTaps(*t, s, taps).r, 255);
}

}  // namespace
}  // namespace rg::tex
