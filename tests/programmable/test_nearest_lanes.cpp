// The point-sampled fast fetch of fragment programs (rasterizer/program.h NearestFloat2D,
// its four-lane and N-quad forms in quad_program.h: detail::nearestIndices and
// detail::nearestLoads; the wide indices and the one- and four-channel AVX2 fetches of quad_program_wide.h) against the tap-list reference (tex::programFetch on
// Path::Reference), bit for bit, over random float textures, samplers and coordinates —
// NaN, ±infinity, negative, huge, denormal, −0 and texel boundaries ± one ulp included.
#include <gtest/gtest.h>

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

using tex::AddressMode;
using tex::TexelFormat;

bool sameBits(const glm::vec4& a, const glm::vec4& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

std::string show(const glm::vec4& v) {
    char b[160];
    std::snprintf(b, sizeof b, "(%a, %a, %a, %a)", double(v.x), double(v.y), double(v.z), double(v.w));
    return b;
}

// A coordinate from the cases addressing can get wrong.
float coordinate(std::mt19937& rng, int size) {
    std::uniform_real_distribution<float> u(-3.0f, 4.0f);
    const float inf = std::numeric_limits<float>::infinity();
    switch (rng() % 12) {
        case 0: return std::numeric_limits<float>::quiet_NaN();
        case 1: return (rng() & 1) ? inf : -inf;
        case 2: return float(int(rng() % 2000) - 1000) * 1.0e6f;             // huge, both signs
        case 3: return (rng() & 1) ? 3.0e38f : -3.0e38f;
        case 4: return (rng() & 1) ? 1.0e-40f : -1.0e-40f;                   // denormal
        case 5: return (rng() & 1) ? 0.0f : -0.0f;
        case 6: case 7: {                                                    // a texel edge ± 1 ulp
            const float edge = float(int(rng() % (6 * size)) - 2 * size) / float(size);
            const int dir = int(rng() % 3) - 1;
            return dir == 0 ? edge : std::nextafter(edge, dir > 0 ? inf : -inf);
        }
        case 8: return float(int(rng() % 20000000) - 10000000) / 4096.0f;    // far, both signs
        default: return u(rng);
    }
}

TEST(ProgramFetch, PointSampledFastFetchMatchesTheTapListBitForBit) {
    std::mt19937 rng(2024);
    tex::TextureMemory memory(profile(ProfileId::GeForce8800));
    const TexelFormat formats[] = {TexelFormat::R32F, TexelFormat::R16F, TexelFormat::RGBA32F,
                                   TexelFormat::RGBA16F, TexelFormat::Depth32F};
    const int sizes[] = {1, 2, 3, 4, 5, 8, 16, 24, 32, 100, 128};
    const AddressMode modes[] = {AddressMode::Wrap, AddressMode::ClampToEdge, AddressMode::Wrap,
                                 AddressMode::ClampToEdge, AddressMode::Border};
    int compared = 0, comparedLanes = 0, casesLanes4 = 0, comparedAvx2 = 0, comparedAvx2Four = 0;
    for (int tcase = 0; tcase < 160; ++tcase) {
        tex::TextureDesc d;
        d.format = formats[rng() % 5];
        const bool oneD = d.format != TexelFormat::Depth32F && rng() % 5 == 0;
        d.target = oneD ? tex::TextureTarget::Texture1D : tex::TextureTarget::Texture2D;
        d.width = sizes[rng() % 11];
        d.height = oneD ? 1 : sizes[rng() % 11];
        d.levels = 1 + int(rng() % tex::fullChainLevels(d));
        auto t = memory.create(d);
        for (int l = 0; l < d.levels; ++l) {
            const auto& s = t->levelSize(l);
            const int bpt = tex::formatInfo(d.format).bytesPerTexel;
            std::vector<uint8_t> b(static_cast<size_t>(s[0] * s[1] * bpt));
            if (bpt == 2 || bpt == 8) {
                for (size_t i = 0; i < b.size() / 2; ++i) {
                    const uint16_t h = uint16_t(rng() & 0xFBFF);  // finite halves, ±0 included
                    std::memcpy(&b[i * 2], &h, 2);
                }
            } else {
                for (size_t i = 0; i < b.size() / 4; ++i) {
                    const float v = (i % 7 == 0) ? -0.0f : float(int(rng() % 4001) - 2000) / 997.0f;
                    std::memcpy(&b[i * 4], &v, 4);
                }
            }
            memory.upload(*t, l, 0, b);
        }
        for (int scase = 0; scase < 12; ++scase) {
            tex::SamplerState s;
            s.address[0] = modes[rng() % 5];
            s.address[1] = modes[rng() % 5];
            s.magFilter = s.minFilter = tex::FilterMode::Nearest;
            if (rng() % 6 == 0) s.minFilter = tex::FilterMode::Linear;  // not the fast case
            s.baseLevel = int(rng() % 3);
            s.lodBias = float(int(rng() % 9) - 4) * 0.5f;
            const detail::NearestFloat2D n = detail::nearestFloat2D(t.get(), s);
            const bool pointSampled = s.minFilter == tex::FilterMode::Nearest &&
                                      s.address[0] != AddressMode::Border &&
                                      (oneD || s.address[1] != AddressMode::Border);
            ASSERT_EQ(n.valid(), pointSampled) << "case " << tcase << "/" << scase;
            if (!n.valid()) continue;
            casesLanes4 += n.lanes4;
            // 16 lanes (four quads), a random live mask.
            constexpr int kQuads = 4;
            float sx[4 * kQuads], ty[4 * kQuads];
            glm::vec4 want[4 * kQuads];
            for (int i = 0; i < 4 * kQuads; ++i) {
                sx[i] = coordinate(rng, n.width);
                ty[i] = coordinate(rng, n.height);
                const float lod = float(int(rng() % 17) - 8) * 0.75f;
                uint32_t fetches = 0;
                want[i] = tex::programFetch(*t, s, glm::vec4(sx[i], ty[i], 0.5f, 1.0f),
                                            tex::programLambdaLod(s, lod), Path::Reference, fetches);
                ASSERT_EQ(fetches, 1u);
                const glm::vec4 got = n.fetch(sx[i], ty[i]);
                ASSERT_TRUE(sameBits(got, want[i]))
                    << "NearestFloat2D::fetch, case " << tcase << "/" << scase << " at (" << sx[i] << ", " << ty[i]
                    << "): " << show(got) << " want " << show(want[i]);
                ++compared;
            }
            if (!n.lanes4) continue;
            __m128 s4[kQuads], t4[kQuads], live[kQuads];
            uint32_t liveBits[kQuads];
            for (int q = 0; q < kQuads; ++q) {
                s4[q] = _mm_loadu_ps(sx + 4 * q);
                t4[q] = _mm_loadu_ps(ty + 4 * q);
                liveBits[q] = rng() % 16;
                live[q] = Mask4::fromBits(liveBits[q]).v;
            }
            __m128i idx[kQuads];
            __m128 x[kQuads], y[kQuads], z[kQuads], w[kQuads];
            detail::nearestIndices<kQuads>(n, s4, t4, idx);
            detail::nearestLoads<kQuads>(n, idx, live, x, y, z, w);
            // The wide form (quad_program_wide.h) computes the same texel indices, eight
            // lanes per register.
            using W = WideLanes<2>;
            for (int k = 0; k < 2; ++k) {
                W::F ws, wt;
                std::memcpy(&ws, sx + 8 * k, 32);
                std::memcpy(&wt, ty + 8 * k, 32);
                W::I wx, wy;
                detail::nearestTexelsWide<2>(ws, n.width, n.wrapS, wx);
                detail::nearestTexelsWide<2>(wt, n.height, n.wrapT, wy);
                for (int lane = 0; lane < 8; ++lane) {
                    const int i = 8 * k + lane;
                    const int32_t wide = n.height == 1 ? wx[lane] : wy[lane] * n.width + wx[lane];
                    alignas(16) int32_t narrow[4];
                    _mm_store_si128(reinterpret_cast<__m128i*>(narrow), idx[i / 4]);
                    ASSERT_EQ(wide, narrow[i % 4]) << "nearestTexelsWide, case " << tcase << "/" << scase << " at ("
                                                   << sx[i] << ", " << ty[i] << ")";
                }
            }
            // The AVX2 kernel's one-channel fetch, where the CPU has AVX2.
            if (n.data1 && __builtin_cpu_supports("avx2")) {
                alignas(32) int32_t liveBits32[16];
                for (int i = 0; i < 16; ++i) liveBits32[i] = ((liveBits[i / 4] >> (i % 4)) & 1u) ? -1 : 0;
                alignas(32) float got[16];
                detail::nearestFetchAvx2<2>(n, sx, ty, liveBits32, got);
                for (int i = 0; i < 16; ++i) {
                    const float expect = ((liveBits[i / 4] >> (i % 4)) & 1u) ? want[i].x : 0.0f;
                    ASSERT_EQ(std::memcmp(&got[i], &expect, 4), 0)
                        << "nearestFetchAvx2, case " << tcase << "/" << scase << " lane " << i << " at (" << sx[i]
                        << ", " << ty[i] << "): " << got[i] << " want " << expect;
                    ++comparedAvx2;
                }
            }
            // The AVX2 kernel's four-channel fetch (RGBA16F, RGBA32F), where the CPU has AVX2.
            if (n.data4 && __builtin_cpu_supports("avx2")) {
                alignas(32) int32_t liveBits32[16];
                for (int i = 0; i < 16; ++i) liveBits32[i] = ((liveBits[i / 4] >> (i % 4)) & 1u) ? -1 : 0;
                alignas(32) float gx[16], gy[16], gz[16], gw[16];
                detail::nearestFetch4Avx2<2>(n, sx, ty, liveBits32, gx, gy, gz, gw);
                for (int i = 0; i < 16; ++i) {
                    const glm::vec4 expect = ((liveBits[i / 4] >> (i % 4)) & 1u) ? want[i] : glm::vec4(0.0f);
                    const glm::vec4 got(gx[i], gy[i], gz[i], gw[i]);
                    ASSERT_TRUE(sameBits(got, expect))
                        << "nearestFetch4Avx2, case " << tcase << "/" << scase << " lane " << i << " at (" << sx[i]
                        << ", " << ty[i] << "): " << show(got) << " want " << show(expect);
                    ++comparedAvx2Four;
                }
            }
            // And one quad alone (the QuadContext form).
            __m128i idx1[1];
            __m128 x1[1], y1[1], z1[1], w1[1];
            const __m128 s1[1] = {s4[1]}, t1[1] = {t4[1]}, live1[1] = {live[1]};
            detail::nearestIndices<1>(n, s1, t1, idx1);
            detail::nearestLoads<1>(n, idx1, live1, x1, y1, z1, w1);
            for (int q = 0; q < kQuads; ++q) {
                const Vec4x4 r{Float4{x[q]}, Float4{y[q]}, Float4{z[q]}, Float4{w[q]}};
                for (int lane = 0; lane < 4; ++lane) {
                    const int i = 4 * q + lane;
                    const glm::vec4 expect = ((liveBits[q] >> lane) & 1u) ? want[i] : glm::vec4(0.0f);
                    ASSERT_TRUE(sameBits(r.lane(lane), expect))
                        << "nearestLoads, case " << tcase << "/" << scase << " lane " << i << " at (" << sx[i]
                        << ", " << ty[i] << "): " << show(r.lane(lane)) << " want " << show(expect);
                    ++comparedLanes;
                }
            }
            const Vec4x4 r1{Float4{x1[0]}, Float4{y1[0]}, Float4{z1[0]}, Float4{w1[0]}};
            for (int lane = 0; lane < 4; ++lane) {
                const glm::vec4 expect = ((liveBits[1] >> lane) & 1u) ? want[4 + lane] : glm::vec4(0.0f);
                ASSERT_TRUE(sameBits(r1.lane(lane), expect)) << "one quad, case " << tcase << "/" << scase;
            }
        }
    }
    // The draw covered the forms it claims to.
    EXPECT_GT(compared, 4000);
    EXPECT_GT(comparedLanes, 2000);
    EXPECT_GT(casesLanes4, 100);
    if (__builtin_cpu_supports("avx2")) {
        EXPECT_GT(comparedAvx2, 1000);
        EXPECT_GT(comparedAvx2Four, 1000);
    }
}

// A cube-map direction from the cases face selection can get wrong: ties between the
// major axes (|x| = |y|, |x| = |z|, all three), zeros of either sign, NaN, infinities, face
// edges ± 1 ulp, denormals, and plain random directions.
glm::vec3 direction(std::mt19937& rng, int size) {
    const float inf = std::numeric_limits<float>::infinity();
    auto component = [&](float base) {
        switch (rng() % 9) {
            case 0: return std::numeric_limits<float>::quiet_NaN();
            case 1: return (rng() & 1) ? inf : -inf;
            case 2: return (rng() & 1) ? 0.0f : -0.0f;
            case 3: return (rng() & 1) ? 1.0e-40f : -1.0e-40f;
            case 4: return (rng() & 1) ? base : -base;                              // a tie
            case 5: return std::nextafter(base, (rng() & 1) ? inf : -inf);          // a near tie
            default: return std::uniform_real_distribution<float>(-2.0f, 2.0f)(rng);
        }
    };
    if (rng() % 4 == 0) {
        // On a face: major axis ±1, the others at texel edges ± 1 ulp.
        auto edge = [&] {
            const float e = float(int(rng() % (2 * size + 1))) / float(size) - 1.0f;
            const int dir = int(rng() % 3) - 1;
            return dir == 0 ? e : std::nextafter(e, dir > 0 ? inf : -inf);
        };
        glm::vec3 d(edge(), edge(), edge());
        d[int(rng() % 3)] = (rng() & 1) ? 1.0f : -1.0f;
        return d;
    }
    const float base = std::uniform_real_distribution<float>(0.1f, 3.0f)(rng);
    return {component(base), component(base), component(base)};
}

// NearestFloat2D's cube form (fetchCube; nearestCubeIndices on one quad and on four) against
// the tap list (tex::programFetch on Path::Reference, which maps through selectCubeFace).
TEST(ProgramFetch, PointSampledCubeFetchMatchesTheTapListBitForBit) {
    std::mt19937 rng(1999);
    tex::TextureMemory memory(profile(ProfileId::GeForce8800));
    const TexelFormat formats[] = {TexelFormat::R32F, TexelFormat::RGBA32F, TexelFormat::RGBA16F};
    const int sizes[] = {1, 2, 3, 5, 8, 16, 24, 64};
    int compared = 0;
    for (int tcase = 0; tcase < 48; ++tcase) {
        tex::TextureDesc d;
        d.target = tex::TextureTarget::CubeMap;
        d.format = formats[rng() % 3];
        d.width = d.height = sizes[rng() % 8];
        auto t = memory.create(d);
        const int bpt = tex::formatInfo(d.format).bytesPerTexel;
        for (int f = 0; f < 6; ++f) {
            std::vector<uint8_t> b(size_t(d.width) * size_t(d.height) * size_t(bpt));
            if (bpt == 8) {
                for (size_t i = 0; i < b.size() / 2; ++i) {
                    const uint16_t h = uint16_t(rng() & 0xFBFF);
                    std::memcpy(&b[i * 2], &h, 2);
                }
            } else {
                for (size_t i = 0; i < b.size() / 4; ++i) {
                    const float v = (i % 7 == 0) ? -0.0f : float(int(rng() % 4001) - 2000) / 997.0f;
                    std::memcpy(&b[i * 4], &v, 4);
                }
            }
            memory.upload(*t, 0, f, b);
        }
        tex::SamplerState s;
        s.magFilter = s.minFilter = tex::FilterMode::Nearest;
        s.address[0] = (rng() & 1) ? AddressMode::Wrap : AddressMode::Border;  // cube maps clamp anyway
        const detail::NearestFloat2D n = detail::nearestFloat2D(t.get(), s);
        ASSERT_TRUE(n.valid() && n.cube && !n.lanes4) << "case " << tcase;
        constexpr int kQuads = 4;
        __m128 x[kQuads], y[kQuads], z[kQuads], live[kQuads];
        glm::vec4 want[4 * kQuads];
        uint32_t liveBits[kQuads];
        for (int q = 0; q < kQuads; ++q) {
            alignas(16) float xs[4], ys[4], zs[4];
            for (int lane = 0; lane < 4; ++lane) {
                const int i = 4 * q + lane;
                const glm::vec3 dir = direction(rng, d.width);
                xs[lane] = dir.x, ys[lane] = dir.y, zs[lane] = dir.z;
                uint32_t fetches = 0;
                want[i] = tex::programFetch(*t, s, glm::vec4(dir, 0.0f), tex::programLambdaLod(s, 0.0f), Path::Reference,
                                            fetches);
                const glm::vec4 got = n.fetchCube(dir);
                ASSERT_TRUE(sameBits(got, want[i])) << "fetchCube, case " << tcase << " at (" << dir.x << ", " << dir.y
                                                    << ", " << dir.z << "): " << show(got) << " want " << show(want[i]);
                ++compared;
            }
            x[q] = _mm_load_ps(xs), y[q] = _mm_load_ps(ys), z[q] = _mm_load_ps(zs);
            liveBits[q] = rng() % 16;
            live[q] = Mask4::fromBits(liveBits[q]).v;
        }
        __m128i idx[kQuads];
        __m128 rx[kQuads], ry[kQuads], rz[kQuads], rw[kQuads];
        detail::nearestCubeIndices<kQuads>(n, x, y, z, idx);
        detail::nearestLoads<kQuads>(n, idx, live, rx, ry, rz, rw);
        __m128i idx1[1];
        __m128 x1[1] = {x[2]}, y1[1] = {y[2]}, z1[1] = {z[2]}, live1[1] = {live[2]}, o[4][1];
        detail::nearestCubeIndices<1>(n, x1, y1, z1, idx1);
        detail::nearestLoads<1>(n, idx1, live1, o[0], o[1], o[2], o[3]);
        for (int q = 0; q < kQuads; ++q) {
            const Vec4x4 r{Float4{rx[q]}, Float4{ry[q]}, Float4{rz[q]}, Float4{rw[q]}};
            const Vec4x4 r1{Float4{o[0][0]}, Float4{o[1][0]}, Float4{o[2][0]}, Float4{o[3][0]}};
            for (int lane = 0; lane < 4; ++lane) {
                const glm::vec4 expect = ((liveBits[q] >> lane) & 1u) ? want[4 * q + lane] : glm::vec4(0.0f);
                ASSERT_TRUE(sameBits(r.lane(lane), expect))
                    << "nearestCubeIndices<4>, case " << tcase << " lane " << 4 * q + lane << ": " << show(r.lane(lane))
                    << " want " << show(expect);
                if (q == 2) {
                    ASSERT_TRUE(sameBits(r1.lane(lane), expect)) << "nearestCubeIndices<1>, case " << tcase;
                }
            }
        }
    }
    EXPECT_GT(compared, 700);
}

}  // namespace
}  // namespace rg::raster
