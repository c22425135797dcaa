// Fragment-program texture fetches: the fast path (no tap list) against the reference
// (gatherTaps + resolveTapsFloat), bit for bit, over random textures, samplers and λ.
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>

#include "core/cpu.h"
#include "core/profile.h"
#include "texunit/program_fetch.h"
#include "texunit/program_fetch_quad.h"

namespace rg::tex {
namespace {

// A 64², 7-level 2D texture of a 4-byte format whose level l holds the texel `bytes(l)`
// everywhere.
template <class Bytes>
std::shared_ptr<Texture> uniformLevels(TextureMemory& memory, TexelFormat format, Bytes&& bytes) {
    TextureDesc d;
    d.format = format;
    d.width = d.height = 64;
    d.levels = 7;
    auto t = memory.create(d);
    for (int l = 0; l < 7; ++l) {
        const int n = 64 >> l;
        const std::array<uint8_t, 4> texel = bytes(l);
        std::vector<uint8_t> b(static_cast<size_t>(n) * n * 4);
        for (size_t i = 0; i < b.size(); i += 4) std::memcpy(&b[i], texel.data(), 4);
        memory.upload(*t, l, 0, b);
    }
    return t;
}

TEST(ProgramFetch, FastPathMatchesTheTapListBitForBit) {
    std::mt19937 rng(99);
    std::uniform_real_distribution<float> u(-1.5f, 2.5f);
    TextureMemory memory(profile(ProfileId::GeForce8800));
    const TexelFormat formats[] = {TexelFormat::RGBA8, TexelFormat::L8, TexelFormat::R16F,
                                   TexelFormat::RGBA16F, TexelFormat::R32F, TexelFormat::RGBA32F};
    int compared = 0;
    for (int tcase = 0; tcase < 60; ++tcase) {
        TextureDesc d;
        const int kind = int(rng() % 3);  // 1D, 2D, cube
        d.target = kind == 0 ? TextureTarget::Texture1D : kind == 1 ? TextureTarget::Texture2D
                                                                     : TextureTarget::CubeMap;
        d.format = formats[rng() % 6];
        d.width = 1 << (1 + rng() % 6);
        d.height = kind == 0 ? 1 : kind == 2 ? d.width : (1 << (rng() % 6));
        if (kind == 1 && rng() % 3 == 0) d.width += 3;  // non-power-of-two (geforce8800 has them)
        d.levels = 1 + int(rng() % fullChainLevels(d));
        auto t = memory.create(d);
        for (int l = 0; l < d.levels; ++l)
            for (int f = 0; f < t->faces(); ++f) {
                const auto& s = t->levelSize(l);
                std::vector<uint8_t> b(size_t(s[0]) * s[1] * formatInfo(d.format).bytesPerTexel);
                if (formatInfo(d.format).isFloat && (d.format == TexelFormat::R32F || d.format == TexelFormat::RGBA32F)) {
                    for (size_t i = 0; i < b.size() / 4; ++i) {
                        const float v = u(rng);
                        std::memcpy(&b[i * 4], &v, 4);
                    }
                } else if (d.format == TexelFormat::R16F || d.format == TexelFormat::RGBA16F) {
                    for (size_t i = 0; i < b.size() / 2; ++i) {
                        const uint16_t h = uint16_t(rng() & 0x7BFF);  // finite halves, both signs below
                        std::memcpy(&b[i * 2], &h, 2);
                    }
                } else {
                    for (auto& x : b) x = uint8_t(rng());
                }
                memory.upload(*t, l, f, b);
            }
        for (int scase = 0; scase < 40; ++scase) {
            SamplerState s;
            for (auto& a : s.address) a = AddressMode(rng() % 5);
            s.magFilter = FilterMode(rng() % 2);
            s.minFilter = FilterMode(rng() % 2);
            s.mipFilter = MipMode(rng() % 3);
            s.lodBias = float(int(rng() % 9) - 4) * 0.37f;
            s.borderColor = Rgba8{uint8_t(rng()), uint8_t(rng()), uint8_t(rng()), uint8_t(rng())};
            for (int k = 0; k < 50; ++k) {
                const glm::vec4 c(u(rng), u(rng), u(rng), 1.0f);
                const glm::vec4 dx(u(rng) * 0.1f, u(rng) * 0.1f, u(rng) * 0.1f, 0.0f);
                const glm::vec4 dy(u(rng) * 0.1f, u(rng) * 0.1f, u(rng) * 0.1f, 0.0f);
                const int32_t lambda = (k & 1) ? programLambdaGrad(*t, s, c, dx, dy)
                                               : programLambdaLod(s, u(rng) * 4.0f);
                uint32_t fr = 0, ff = 0;
                const glm::vec4 ref = programFetch(*t, s, c, lambda, Path::Reference, fr);
                const glm::vec4 fast = programFetch(*t, s, c, lambda, Path::Fast, ff);
                ASSERT_EQ(std::memcmp(&ref, &fast, sizeof ref), 0)
                    << "texture case " << tcase << " sampler case " << scase << " sample " << k;
                ASSERT_EQ(fr, ff);
                ++compared;
            }
        }
    }
    EXPECT_EQ(compared, 60 * 40 * 50);
}

TEST(ProgramFetch, LodOfKnownGradientsSelectsTheExpectedLevel) {
    TextureMemory memory(profile(ProfileId::GeForce8800));
    auto t = uniformLevels(memory, TexelFormat::R32F, [](int l) {
        const float v = float(l);  // each level holds its own number
        std::array<uint8_t, 4> b;
        std::memcpy(b.data(), &v, 4);
        return b;
    });
    SamplerState s;
    s.magFilter = s.minFilter = FilterMode::Nearest;
    s.mipFilter = MipMode::Nearest;
    uint32_t f = 0;
    // A gradient of 2^k texels per pixel selects level k.
    for (int k = 0; k < 7; ++k) {
        const glm::vec4 g(float(1 << k) / 64.0f, 0, 0, 0);
        const int32_t lambda = programLambdaGrad(*t, s, glm::vec4(0.3f, 0.6f, 0, 0), g, glm::vec4(0));
        EXPECT_EQ(programFetch(*t, s, glm::vec4(0.3f, 0.6f, 0, 0), lambda, Path::Fast, f).x, float(k)) << k;
        EXPECT_EQ(programFetch(*t, s, glm::vec4(0.3f, 0.6f, 0, 0), programLambdaLod(s, float(k)), Path::Fast, f).x,
                  float(k));
    }
    // LINEAR between levels (trilinear with bilinear levels): at λ = k + f the levels k and
    // k + 1 weigh 1 − f and f (OpenGL 2.1 §3.8.8, f in kLodFracBits fixed point), so a
    // texture whose level l holds l everywhere reads k + f — exact for f a multiple of 1/8.
    s.magFilter = s.minFilter = FilterMode::Linear;
    s.mipFilter = MipMode::Linear;
    for (int k = 0; k < 6; ++k)
        for (int e = 1; e < 8; ++e) {
            const float lod = float(k) + float(e) / 8.0f;
            for (Path path : {Path::Fast, Path::Reference}) {
                uint32_t n = 0;
                EXPECT_EQ(programFetch(*t, s, glm::vec4(0.3f, 0.6f, 0, 0), programLambdaLod(s, lod), path, n).x, lod)
                    << "λ " << lod << (path == Path::Fast ? ", fast" : ", reference");
                EXPECT_EQ(n, 8u) << "two levels of four taps";
            }
        }
}

// The quad fetch of 8-bit 2D textures (program_fetch_quad.h) against the tap list lane by
// lane: random RGBA8 and L8 textures (power-of-two and not, partial chains), samplers of
// every address mode and mip filter — where quadFetch8Applies refuses one, the quad is not
// compared, and the refusals are counted so that both kinds occur — random lane masks,
// and coordinates that wrap, clamp, or are NaN or infinite.
// programFetchQuad8 turns a byte v into texelAsFloat's v/255 (a float division) as
// v·(1/255) in double rounded to float. Every byte: the same bits.
TEST(ProgramFetch, Unorm8ProductEqualsDivision) {
    const double inv255 = 1.0 / 255.0;
    for (int v = 0; v < 256; ++v) {
        volatile float byte = float(v);  // no folding: the divisions run as the fetch's would
        const float division = byte / 255.0f;
        const float product = float(double(byte) * inv255);
        ASSERT_EQ(std::bit_cast<uint32_t>(product), std::bit_cast<uint32_t>(division)) << "v = " << v;
    }
}

TEST(ProgramFetch, QuadFetchOf8BitTexturesMatchesTheTapListBitForBit) {
    if (!avx2Enabled()) GTEST_SKIP() << "programFetchQuad8 needs AVX2, which this CPU lacks or RETROGLASS_NO_AVX2 turns off";
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-2.5f, 3.5f);
    TextureMemory memory(profile(ProfileId::GeForce8800));
    int compared = 0, refused = 0, blended = 0;
    for (int tcase = 0; tcase < 40; ++tcase) {
        TextureDesc d;
        d.format = rng() % 2 ? TexelFormat::RGBA8 : TexelFormat::L8;
        d.width = 1 << (rng() % 8);
        d.height = 1 << (rng() % 8);
        if (rng() % 4 == 0) d.width += 5;  // non-power-of-two: WRAP is refused on that axis
        d.levels = rng() % 2 ? fullChainLevels(d) : 1 + int(rng() % fullChainLevels(d));
        auto t = memory.create(d);
        for (int l = 0; l < d.levels; ++l) {
            const auto& sz = t->levelSize(l);
            std::vector<uint8_t> b(static_cast<size_t>(sz[0]) * sz[1] * formatInfo(d.format).bytesPerTexel);
            for (auto& x : b) x = uint8_t(rng());
            memory.upload(*t, l, 0, b);
        }
        for (int scase = 0; scase < 40; ++scase) {
            SamplerState s;
            // Mostly the modes the quad fetch takes, sometimes any.
            for (auto& a : s.address)
                a = rng() % 4 == 0 ? AddressMode(rng() % 5) : (rng() % 2 ? AddressMode::Wrap : AddressMode::ClampToEdge);
            s.magFilter = rng() % 5 == 0 ? FilterMode::Nearest : FilterMode::Linear;
            s.minFilter = rng() % 5 == 0 ? FilterMode::Nearest : FilterMode::Linear;
            s.mipFilter = rng() % 2 ? MipMode::Linear : MipMode(rng() % 3);
            s.lodBias = float(int(rng() % 9) - 4) * 0.37f;
            s.baseLevel = int(rng() % 3);
            if (rng() % 4 == 0) s.maxLevel = 1 + int(rng() % 6);
            if (!quadFetch8Applies(*t, s)) {
                ++refused;
                continue;
            }
            for (int k = 0; k < 30; ++k) {
                std::array<glm::vec4, 4> q;
                const glm::vec4 c0(u(rng), u(rng), 0.0f, 1.0f);
                // Pixel steps of 2^−3 to 2^7 texels: λ from magnification to past the chain's end.
                const float step = std::exp2(float(int(rng() % 11)) - 3.0f) / float(std::max(d.width, d.height));
                for (int i = 0; i < 4; ++i)
                    q[size_t(i)] = c0 + glm::vec4(float(i & 1) * step * u(rng), float(i >> 1) * step * u(rng), 0, 0);
                if (k % 10 == 3) q[1].x = std::numeric_limits<float>::quiet_NaN();
                if (k % 10 == 5) q[2].y = std::numeric_limits<float>::infinity();
                if (k % 10 == 7) q[3].x = -3.0e9f;
                const int32_t lambda = programLambdaQuad(*t, s, q);
                const uint32_t lanes = rng() % 16;
                std::array<glm::vec4, 4> out;
                std::array<uint32_t, 4> ff{1, 2, 3, 4};
                programFetchQuad8(*t, s, q, lambda, lanes, out, ff);
                for (int i = 0; i < 4; ++i) {
                    uint32_t fr = 0;
                    const glm::vec4 ref = (lanes >> i) & 1u ? programFetch(*t, s, q[size_t(i)], lambda, Path::Reference, fr)
                                                            : glm::vec4(0.0f);
                    ASSERT_EQ(std::memcmp(&ref, &out[size_t(i)], sizeof ref), 0)
                        << "texture case " << tcase << " sampler case " << scase << " quad " << k << " lane " << i
                        << ": (" << out[size_t(i)].x << ", " << out[size_t(i)].y << ", " << out[size_t(i)].z << ", "
                        << out[size_t(i)].w << ") against (" << ref.x << ", " << ref.y << ", " << ref.z << ", " << ref.w << ")";
                    ASSERT_EQ(ff[size_t(i)], uint32_t(i + 1) + fr) << "the lane's taps are added to its count";
                    if (fr == 8) ++blended;
                    ++compared;
                }
            }
        }
    }
    std::printf("quad fetch: %d lanes compared (%d between two levels), %d samplers refused\n", compared, blended, refused);
    EXPECT_GT(refused, 100);
    EXPECT_GT(compared, 40000);
    EXPECT_GT(blended, 4000) << "lanes between two levels";
}

// The quad fetch on an analytic case: an RGBA8 texture whose level l holds the byte 20·l
// (alpha 255) everywhere reads, between levels k and k + 1 at λ = k + e/8, the blend
// ((1 − e/8)·20k + (e/8)·20(k + 1))/255 — up to float rounding — on every lane, and a
// whole level (λ = k exactly) reads 20k/255 exactly.
TEST(ProgramFetch, QuadFetchBlendsUniformLevelsAsTheirMix) {
    if (!avx2Enabled()) GTEST_SKIP() << "programFetchQuad8 needs AVX2, which this CPU lacks or RETROGLASS_NO_AVX2 turns off";
    TextureMemory memory(profile(ProfileId::GeForce8800));
    auto t = uniformLevels(memory, TexelFormat::RGBA8, [](int l) {
        const uint8_t v = uint8_t(20 * l);
        return std::array<uint8_t, 4>{v, v, v, 255};
    });
    SamplerState s;
    s.magFilter = s.minFilter = FilterMode::Linear;
    s.mipFilter = MipMode::Linear;
    const std::array<glm::vec4, 4> q{glm::vec4(0.1f, 0.2f, 0, 0), glm::vec4(0.7f, 0.3f, 0, 0),
                                     glm::vec4(-0.4f, 0.9f, 0, 0), glm::vec4(1.3f, -0.2f, 0, 0)};
    for (int k = 0; k < 6; ++k)
        for (int e = 0; e < 8; ++e) {
            const float f = float(e) / 8.0f;
            std::array<glm::vec4, 4> out;
            std::array<uint32_t, 4> n{};
            programFetchQuad8(*t, s, q, programLambdaLod(s, float(k) + f), 0xF, out, n);
            const double want = ((1.0 - f) * 20.0 * k + f * 20.0 * (k + 1)) / 255.0;
            for (int i = 0; i < 4; ++i) {
                if (e == 0)
                    EXPECT_EQ(out[size_t(i)].x, float(20 * k) / 255.0f) << "level " << k;
                else
                    EXPECT_NEAR(out[size_t(i)].x, want, 1e-6) << "λ " << k << " + " << e << "/8";
                EXPECT_EQ(out[size_t(i)].y, out[size_t(i)].x);
                EXPECT_EQ(out[size_t(i)].w, 1.0f);
                EXPECT_EQ(n[size_t(i)], k == 0 && e == 0 ? 4u : 8u) << "λ ≤ 0 magnifies: one level";
            }
        }
}

}  // namespace
}  // namespace rg::tex
