// The bilinear float cube-map and 2D fetches of the AVX2 kernel (rasterizer/program.h LinearFloatCube,
// LinearFloat2D; quad_program_wide.h detail::linearCubeFetchAvx2, linear2DFetchAvx2) against the tap-list reference
// (tex::programFetch on Path::Reference), bit for bit, over random RGBA16F and RGBA32F cube
// maps and directions — face ties, ±0, NaN, ±infinity, zero vectors, huge and denormal
// components and texel edges included, with texels that make the order of the taps' sum
// show — and which units qualify.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "core/profile.h"
#include "rasterizer/programmable_device.h"
#include "rasterizer/quad_program_wide.h"
#include "texunit/program_fetch.h"

namespace rg::raster {
namespace {

using tex::FilterMode;
using tex::TexelFormat;

std::string show(const glm::vec4& v) {
    char b[160];
    std::snprintf(b, sizeof b, "(%a, %a, %a, %a)", double(v.x), double(v.y), double(v.z), double(v.w));
    return b;
}

// A direction component from the cases face selection and addressing can get wrong.
float component(std::mt19937& rng, float other) {
    const float inf = std::numeric_limits<float>::infinity();
    std::uniform_real_distribution<float> u(-2.0f, 2.0f);
    switch (rng() % 14) {
        case 0: return std::numeric_limits<float>::quiet_NaN();
        case 1: return (rng() & 1) ? inf : -inf;
        case 2: return (rng() & 1) ? 0.0f : -0.0f;
        case 3: return (rng() & 1) ? 1.0e-40f : -1.0e-40f;              // denormal
        case 4: return (rng() & 1) ? 3.0e38f : -3.0e38f;
        case 5: case 6: return (rng() & 1) ? other : -other;           // a tie with the other axis
        case 7: return std::nextafter(other, (rng() & 1) ? inf : -inf);  // one ulp off a tie
        default: return u(rng);
    }
}

// Random texels for one face of level l of an RGBA16F or RGBA32F texture: finite halves
// (±0 included); or, with `palette`, values that cancel exactly or absorb each other in the
// double sum, so that the order of the taps shows (with the equal weights of a texel edge,
// (2^100 − 2^100) + 1 is 1 but (2^100 + 1) − 2^100 is 0); or floats over 60 binades with
// −0 among them.
std::vector<uint8_t> levelBytes(std::mt19937& rng, const tex::Texture& t, int l, bool palette) {
    const auto& s = t.levelSize(l);
    const int bpt = tex::formatInfo(t.desc().format).bytesPerTexel;
    std::vector<uint8_t> b(static_cast<size_t>(s[0]) * size_t(s[1]) * size_t(bpt));
    if (bpt == 8) {
        for (size_t i = 0; i < b.size() / 2; ++i) {
            const uint16_t h = uint16_t(rng() & 0xFBFF);
            std::memcpy(&b[i * 2], &h, 2);
        }
    } else if (palette) {
        const float values[] = {0x1p100f, -0x1p100f, 1.0f, -1.0f, 0x1p-100f, -0.75f, -0.0f};
        for (size_t i = 0; i < b.size() / 4; ++i) std::memcpy(&b[i * 4], &values[rng() % 7], 4);
    } else {
        for (size_t i = 0; i < b.size() / 4; ++i) {
            const int e = int(rng() % 60) - 30;
            const float v = (i % 9 == 0) ? -0.0f : std::ldexp(float(int(rng() % 2001) - 1000) / 997.0f, e);
            std::memcpy(&b[i * 4], &v, 4);
        }
    }
    return b;
}

TEST(ProgramFetch, BilinearCubeFastFetchMatchesTheTapListBitForBit) {
    if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "the AVX2 kernel's fetch needs AVX2";
    std::mt19937 rng(1999);
    tex::TextureMemory memory(profile(ProfileId::GeForce8800));
    const int sizes[] = {1, 2, 3, 4, 7, 8, 16, 32, 128};
    int compared = 0;
    for (int tcase = 0; tcase < 60; ++tcase) {
        tex::TextureDesc d;
        d.format = (rng() & 1) ? TexelFormat::RGBA16F : TexelFormat::RGBA32F;
        d.target = tex::TextureTarget::CubeMap;
        d.width = d.height = sizes[rng() % 9];
        d.levels = 1 + int(rng() % tex::fullChainLevels(d));
        auto t = memory.create(d);
        const bool palette = rng() & 1;
        for (int l = 0; l < d.levels; ++l)
            for (int f = 0; f < 6; ++f) memory.upload(*t, l, f, levelBytes(rng, *t, l, palette));
        tex::SamplerState s;  // LINEAR, LINEAR, no mipmaps: the fast case
        s.baseLevel = int(rng() % 3);
        s.lodBias = float(int(rng() % 9) - 4) * 0.5f;
        const detail::LinearFloatCube cube = detail::linearFloatCube(t.get(), s);
        ASSERT_TRUE(cube.valid()) << "case " << tcase;
        for (int rcase = 0; rcase < 20; ++rcase) {
            alignas(32) float x[16], y[16], z[16];
            alignas(32) int32_t live[16];
            glm::vec4 want[16];
            for (int i = 0; i < 16; ++i) {
                std::uniform_real_distribution<float> u(-2.0f, 2.0f);
                x[i] = u(rng);
                y[i] = component(rng, x[i]);
                z[i] = component(rng, (rng() & 1) ? x[i] : y[i]);
                if (rng() % 4 == 0) std::swap(x[i], z[i]);
                if (rng() % 12 == 0) {
                    // A zero vector, each sign: +X's centre, whatever the signs.
                    x[i] = (rng() & 1) ? 0.0f : -0.0f;
                    y[i] = (rng() & 1) ? 0.0f : -0.0f;
                    z[i] = (rng() & 1) ? 0.0f : -0.0f;
                } else if (rng() % 3 == 0) {
                    // On a texel edge of the base level's +Z face (sc = x, tc = −y, |ma| = 1):
                    // equal weights 128 across the edge.
                    const int n = t->levelSize(std::min(s.baseLevel, d.levels - 1))[0];
                    x[i] = -1.0f + 2.0f * float(int(rng() % unsigned(n + 1))) / float(n);
                    y[i] = (rng() & 1) ? -1.0f + 2.0f * float(int(rng() % unsigned(n + 1))) / float(n) : u(rng) * 0.5f;
                    z[i] = 1.0f;
                }
                live[i] = (rng() % 5) ? -1 : 0;
                uint32_t fetches = 0;
                const float lod = float(int(rng() % 17) - 8) * 0.75f;
                want[i] = tex::programFetch(*t, s, glm::vec4(x[i], y[i], z[i], 0.0f), tex::programLambdaLod(s, lod),
                                            Path::Reference, fetches);
                ASSERT_EQ(fetches, 4u);
            }
            alignas(32) float gx[16], gy[16], gz[16], gw[16];
            detail::linearCubeFetchAvx2<2>(cube, x, y, z, live, gx, gy, gz, gw);
            for (int i = 0; i < 16; ++i) {
                const glm::vec4 expect = live[i] ? want[i] : glm::vec4(0.0f);
                const glm::vec4 got(gx[i], gy[i], gz[i], gw[i]);
                ASSERT_EQ(std::memcmp(&got, &expect, sizeof got), 0)
                    << "case " << tcase << "/" << rcase << " lane " << i << ", direction (" << x[i] << ", " << y[i]
                    << ", " << z[i] << "): " << show(got) << " want " << show(expect);
                ++compared;
            }
        }
    }
    EXPECT_GT(compared, 15000);
}

// Only a four-channel float cube map with LINEAR min and mag filters and no mipmaps takes
// the fast fetch: any other λ may choose another level or filter.
TEST(ProgramFetch, BilinearCubeFastCaseQualifiesOnlyItsUnits) {
    tex::TextureMemory memory(profile(ProfileId::GeForce8800));
    tex::TextureDesc d;
    d.target = tex::TextureTarget::CubeMap;
    d.format = TexelFormat::RGBA16F;
    d.width = d.height = 4;
    const auto rgba = memory.createRenderTarget(d);
    d.format = TexelFormat::R32F;
    const auto red = memory.createRenderTarget(d);
    d.format = TexelFormat::RGBA32F;
    d.target = tex::TextureTarget::Texture2D;
    const auto flat = memory.createRenderTarget(d);
    const tex::SamplerState linear;
    EXPECT_TRUE(detail::linearFloatCube(rgba.get(), linear).valid());
    EXPECT_FALSE(detail::linearFloatCube(red.get(), linear).valid());
    EXPECT_FALSE(detail::linearFloatCube(flat.get(), linear).valid());
    tex::SamplerState s = linear;
    s.mipFilter = tex::MipMode::Nearest;
    EXPECT_FALSE(detail::linearFloatCube(rgba.get(), s).valid());
    s = linear;
    s.magFilter = FilterMode::Nearest;
    EXPECT_FALSE(detail::linearFloatCube(rgba.get(), s).valid());
    s = linear;
    s.minFilter = FilterMode::Nearest;
    EXPECT_FALSE(detail::linearFloatCube(rgba.get(), s).valid());
    EXPECT_EQ(detail::linearFloatCube(rgba.get(), linear).size, 4);
    EXPECT_EQ(detail::linearFloatCube(rgba.get(), linear).faceTexels, 16);
}

// The bilinear float 2D fetch (LinearFloat2D, detail::linear2DFetchAvx2: the impostors'
// light and caustic maps, read by `sample`) against the tap-list reference at random λ —
// the fast case has none, so any λ must give its sum — over random RGBA16F and RGBA32F
// textures of any shape; coordinates on texel edges, outside [0, 1], NaN, ±infinity,
// huge and denormal.
TEST(ProgramFetch, Bilinear2DFastFetchMatchesTheTapListBitForBitAtAnyLod) {
    if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "the AVX2 kernel's fetch needs AVX2";
    std::mt19937 rng(2008);
    tex::TextureMemory memory(profile(ProfileId::GeForce8800));
    const int sizes[] = {1, 2, 3, 5, 8, 16, 33, 64, 256};
    const float inf = std::numeric_limits<float>::infinity();
    int compared = 0;
    for (int tcase = 0; tcase < 60; ++tcase) {
        tex::TextureDesc d;
        d.format = (rng() & 1) ? TexelFormat::RGBA16F : TexelFormat::RGBA32F;
        d.width = sizes[rng() % 9];
        d.height = sizes[rng() % 9];
        d.levels = 1 + int(rng() % tex::fullChainLevels(d));
        auto t = memory.create(d);
        const bool palette = rng() & 1;
        for (int l = 0; l < d.levels; ++l) memory.upload(*t, l, 0, levelBytes(rng, *t, l, palette));
        tex::SamplerState s;  // LINEAR, LINEAR, no mipmaps, CLAMP_TO_EDGE: the fast case
        s.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::Wrap,
                     tex::AddressMode::Wrap};
        s.baseLevel = int(rng() % 3);
        s.lodBias = float(int(rng() % 9) - 4) * 0.5f;
        const detail::LinearFloat2D fast = detail::linearFloat2D(t.get(), s);
        ASSERT_TRUE(fast.valid()) << "case " << tcase;
        const int base = std::min(s.baseLevel, d.levels - 1);
        auto coordinate = [&](int n) {
            std::uniform_real_distribution<float> u(-0.5f, 1.5f);
            switch (rng() % 12) {
                case 0: return std::numeric_limits<float>::quiet_NaN();
                case 1: return (rng() & 1) ? inf : -inf;
                case 2: return (rng() & 1) ? 0.0f : -0.0f;
                case 3: return (rng() & 1) ? 1.0e-40f : -1.0e-40f;
                case 4: return (rng() & 1) ? 3.0e38f : -3.0e38f;
                case 5: case 6: return float(int(rng() % unsigned(n + 1))) / float(n);  // a texel edge
                case 7: return (float(int(rng() % unsigned(n))) + 0.5f) / float(n);      // a texel centre
                default: return u(rng);
            }
        };
        for (int rcase = 0; rcase < 20; ++rcase) {
            alignas(32) float x[16], y[16];
            alignas(32) int32_t live[16];
            glm::vec4 want[16];
            for (int i = 0; i < 16; ++i) {
                x[i] = coordinate(t->levelSize(base)[0]);
                y[i] = coordinate(t->levelSize(base)[1]);
                live[i] = (rng() % 5) ? -1 : 0;
                uint32_t fetches = 0;
                const float lod = float(int(rng() % 17) - 8) * 0.75f;
                want[i] = tex::programFetch(*t, s, glm::vec4(x[i], y[i], 0.25f, 1.0f), tex::programLambdaLod(s, lod),
                                            Path::Reference, fetches);
                ASSERT_EQ(fetches, 4u);
            }
            alignas(32) float gx[16], gy[16], gz[16], gw[16];
            detail::linear2DFetchAvx2<2>(fast, x, y, live, gx, gy, gz, gw);
            for (int i = 0; i < 16; ++i) {
                const glm::vec4 expect = live[i] ? want[i] : glm::vec4(0.0f);
                const glm::vec4 got(gx[i], gy[i], gz[i], gw[i]);
                ASSERT_EQ(std::memcmp(&got, &expect, sizeof got), 0)
                    << "case " << tcase << "/" << rcase << " lane " << i << ", " << d.width << "x" << d.height
                    << " at (" << x[i] << ", " << y[i] << "): " << show(got) << " want " << show(expect);
                ++compared;
            }
        }
    }
    EXPECT_GT(compared, 15000);
}

// Only a four-channel float 2D texture with LINEAR filters, no mipmaps and CLAMP_TO_EDGE in
// s and t takes the fast 2D fetch.
TEST(ProgramFetch, Bilinear2DFastCaseQualifiesOnlyItsUnits) {
    tex::TextureMemory memory(profile(ProfileId::GeForce8800));
    tex::TextureDesc d;
    d.format = TexelFormat::RGBA32F;
    d.width = 8;
    d.height = 4;
    const auto rgba = memory.createRenderTarget(d);
    d.format = TexelFormat::R32F;
    const auto red = memory.createRenderTarget(d);
    d.format = TexelFormat::RGBA8;
    const auto bytes = memory.createRenderTarget(d);
    d.format = TexelFormat::RGBA16F;
    d.target = tex::TextureTarget::CubeMap;
    d.width = 4;
    const auto cube = memory.createRenderTarget(d);
    tex::SamplerState clamp;
    clamp.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::Wrap,
                     tex::AddressMode::Wrap};
    EXPECT_TRUE(detail::linearFloat2D(rgba.get(), clamp).valid());
    EXPECT_EQ(detail::linearFloat2D(rgba.get(), clamp).width, 8);
    EXPECT_EQ(detail::linearFloat2D(rgba.get(), clamp).height, 4);
    EXPECT_FALSE(detail::linearFloat2D(red.get(), clamp).valid());
    EXPECT_FALSE(detail::linearFloat2D(bytes.get(), clamp).valid());
    EXPECT_FALSE(detail::linearFloat2D(cube.get(), clamp).valid());
    tex::SamplerState s = clamp;
    s.address[0] = tex::AddressMode::Wrap;
    EXPECT_FALSE(detail::linearFloat2D(rgba.get(), s).valid());
    s = clamp;
    s.address[1] = tex::AddressMode::Border;
    EXPECT_FALSE(detail::linearFloat2D(rgba.get(), s).valid());
    s = clamp;
    s.mipFilter = tex::MipMode::Linear;
    EXPECT_FALSE(detail::linearFloat2D(rgba.get(), s).valid());
    s = clamp;
    s.magFilter = FilterMode::Nearest;
    EXPECT_FALSE(detail::linearFloat2D(rgba.get(), s).valid());
    s = clamp;
    s.minFilter = FilterMode::Nearest;
    EXPECT_FALSE(detail::linearFloat2D(rgba.get(), s).valid());
}

}  // namespace
}  // namespace rg::raster
