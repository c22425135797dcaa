// Fragment-program texture fetches: the fast path (no tap list) against the reference
// (gatherTaps + resolveTapsFloat), bit for bit, over random textures, samplers and λ.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "core/profile.h"
#include "texunit/program_fetch.h"

namespace rg::tex {
namespace {

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
    TextureDesc d;
    d.format = TexelFormat::R32F;
    d.width = d.height = 64;
    d.levels = 7;
    auto t = memory.create(d);
    for (int l = 0; l < 7; ++l) {
        const int n = 64 >> l;
        std::vector<uint8_t> b(size_t(n) * n * 4);
        for (size_t i = 0; i < b.size() / 4; ++i) {
            const float v = float(l);  // each level holds its own number
            std::memcpy(&b[i * 4], &v, 4);
        }
        memory.upload(*t, l, 0, b);
    }
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

}  // namespace
}  // namespace rg::tex
