// The per-quad sampling kernels of the fast path (see filter_quad.h for what they cover).
//
// Coordinates and λ: the same inline functions and float operations as projectQuad,
// quadLambda and axisFootprint (cube_select.h, addressing.h), so the taps are the
// reference's taps. Filtering: the reference's exact sum Σ weight·texel rounded once,
// evaluated with SSE2 pmaddwd (16×16 → 32-bit pair sums), which needs every factor in
// int16. Texels enter biased by −128, so that a row of two taps,
//     R' = Σ wx·(t − 128) = R − 128·256      with wx0 + wx1 = 256, R ∈ [0, 65280],
// lies in [−32768, 32512] and packs into int16 exactly; the column pass gives
//     S' = Σ wy·R' = S − 2^23                 (S the 16-bit-weight bilinear sum),
// and the level blend splits S' = 256·⌊S'/256⌋ + (S' mod 256), both parts int16, so
//     Σ lw·S' = 256·Σ lw·⌊S'/256⌋ + Σ lw·(S' mod 256) = Σ lw·S − 2^31
// fits int32 (|S'| ≤ 2^23, Σ lw = 256). Adding the biases back in wrapping 32-bit
// arithmetic gives the unbiased sum, below 2^32, before the final shift. Integer sums are
// exact, so the order of the taps does not matter.
#include "filter_quad.h"

#include <emmintrin.h>

#include <algorithm>
#include <cstring>

#include "addressing.h"
#include "cube_select.h"

namespace rg::tex::detail {

namespace {

enum class Target : uint8_t { OneD, TwoD, Cube };
// The address modes the kernels specialise on: CLAMP_TO_EDGE, and WRAP on a power of two
// (addressTexel's mask branch).
enum class Addr : uint8_t { Edge, Pow2 };

template <Addr kA>
inline int32_t address(int32_t i, int32_t n) {
    if constexpr (kA == Addr::Edge) return std::clamp(i, 0, n - 1);
    else return i & (n - 1);
}

// axisFootprint(c, n, m, Linear) for the two modes: i0, i1 and the weight α of i1.
// |toSubTexel| ≤ 2^30, so the int32 arithmetic is the reference's int64 arithmetic.
template <Addr kA>
inline void linearAxis(float c, int32_t n, int32_t& i0, int32_t& i1, int32_t& frac) {
    if (!(c == c)) c = 0.0f;
    const int32_t u = int32_t(toSubTexel(c, n)) - (1 << (kSubTexelBits - 1));
    const int32_t b = u >> kSubTexelBits;
    frac = u & ((1 << kSubTexelBits) - 1);
    i0 = address<kA>(b, n);
    i1 = address<kA>(b + 1, n);
}

template <Addr kA>
inline int32_t nearestAxis(float c, int32_t n) {
    if (!(c == c)) c = 0.0f;
    return address<kA>(int32_t(toSubTexel(c, n) >> kSubTexelBits), n);
}

inline __m128i load4(const Rgba8* p) {
    int32_t v;
    std::memcpy(&v, p, 4);
    return _mm_cvtsi32_si128(v);
}
inline Rgba8 store4(__m128i v) {  // int32 lanes in [0, 255] → Rgba8
    const __m128i b = _mm_packus_epi16(_mm_packs_epi32(v, v), v);
    const uint32_t x = uint32_t(_mm_cvtsi128_si32(b));
    return {uint8_t(x), uint8_t(x >> 8), uint8_t(x >> 16), uint8_t(x >> 24)};
}
// (256 − w, w) in each pair of int16 lanes: the weights of the first and second tap.
inline __m128i weightPair(int32_t w) {
    return _mm_set1_epi32(int32_t((uint32_t(w) << 16) | uint32_t(256 - w)));
}
// Interleaves the int16 lanes of p = (a0 a1 a2 a3 b0 b1 b2 b3) into (a0 b0 a1 b1 ...).
inline __m128i interleaveHalves(__m128i p) { return _mm_unpacklo_epi16(p, _mm_srli_si128(p, 8)); }

// Σ wx·(t − 128) over taps a (weight 256 − fx) and b (weight fx): R − 2^15 per channel.
inline __m128i pairBiased(__m128i a, __m128i b, int32_t fx) {
    const __m128i t = _mm_sub_epi16(_mm_unpacklo_epi8(_mm_unpacklo_epi8(a, b), _mm_setzero_si128()),
                                    _mm_set1_epi16(128));
    return _mm_madd_epi16(t, weightPair(fx));
}

// The bilinear sum S − 2^23 per channel over rows r0 (y0) and r1 (y1).
inline __m128i bilinearBiased(const Rgba8* r0, const Rgba8* r1, int32_t x0, int32_t x1,
                              int32_t fx, int32_t fy) {
    const __m128i zero = _mm_setzero_si128();
    const __m128i row0 = _mm_unpacklo_epi8(load4(r0 + x0), load4(r0 + x1));
    const __m128i row1 = _mm_unpacklo_epi8(load4(r1 + x0), load4(r1 + x1));
    const __m128i both = _mm_unpacklo_epi64(row0, row1);
    const __m128i k128 = _mm_set1_epi16(128);
    const __m128i t0 = _mm_sub_epi16(_mm_unpacklo_epi8(both, zero), k128);
    const __m128i t1 = _mm_sub_epi16(_mm_unpackhi_epi8(both, zero), k128);
    const __m128i wx = weightPair(fx);
    const __m128i p = _mm_packs_epi32(_mm_madd_epi16(t0, wx), _mm_madd_epi16(t1, wx));
    return _mm_madd_epi16(interleaveHalves(p), weightPair(fy));
}

// Rounded results (docs/hardware.md, "Filtering": ⌊(Σ + 2^(bits−1)) / 2^bits⌋).
inline Rgba8 finishPair(__m128i rBiased) {  // 8 weight bits, R − 2^15
    return store4(_mm_srai_epi32(_mm_add_epi32(rBiased, _mm_set1_epi32(32768 + 128)), 8));
}
inline Rgba8 finishBilinear(__m128i sBiased) {  // 16 weight bits, S − 2^23
    return store4(
        _mm_srai_epi32(_mm_add_epi32(sBiased, _mm_set1_epi32((1 << 23) + (1 << 15))), 16));
}
// Two levels of 8-bit-weight sums (R − 2^15 each), blended by f: 16 weight bits.
inline Rgba8 finishPairBlend(__m128i r0, __m128i r1, int32_t f) {
    const __m128i s = _mm_madd_epi16(interleaveHalves(_mm_packs_epi32(r0, r1)), weightPair(f));
    return store4(_mm_srai_epi32(_mm_add_epi32(s, _mm_set1_epi32((1 << 23) + (1 << 15))), 16));
}
// Two levels of bilinear sums (S − 2^23 each), blended by f: 24 weight bits.
inline Rgba8 finishBilinearBlend(__m128i s0, __m128i s1, int32_t f) {
    const __m128i w = weightPair(f);
    const __m128i hi = _mm_packs_epi32(_mm_srai_epi32(s0, 8), _mm_srai_epi32(s1, 8));
    const __m128i m = _mm_set1_epi32(255);
    const __m128i lo = _mm_packs_epi32(_mm_and_si128(s0, m), _mm_and_si128(s1, m));
    const __m128i sum = _mm_add_epi32(_mm_slli_epi32(_mm_madd_epi16(interleaveHalves(hi), w), 8),
                                      _mm_madd_epi16(interleaveHalves(lo), w));
    // + 2^31 (the bias) + 2^23 (the rounding half), wrapping; the true value is < 2^32.
    const __m128i t = _mm_add_epi32(sum, _mm_set1_epi32(int32_t(0x80800000u)));
    return store4(_mm_srli_epi32(t, 24));
}

// Projection and λ, as TextureUnits::projectQuad; face per pixel (cube maps).
template <Target kTarget>
inline int32_t projectQuad(const QuadSampler& qs, const std::array<glm::vec4, 4>& in,
                           float s[4], float t[4], int face[4]) {
    int32_t lambda;
    if constexpr (kTarget == Target::Cube) {
        std::array<glm::vec4, 4> onFace;
        CubeFace f0 = CubeFace::PositiveX;
        for (int p = 0; p < 4; ++p) {
            const glm::vec3 r(in[size_t(p)]);
            const CubeCoord own = detail::selectCubeFace(r);
            if (p == 0) f0 = own.face;
            s[p] = own.s;
            t[p] = own.t;
            face[p] = int(own.face);
            const CubeCoord cc = own.face == f0 ? own : detail::projectOntoCubeFace(f0, r);
            onFace[size_t(p)] = glm::vec4(cc.s, cc.t, 0.0f, 0.0f);
        }
        lambda = quadLambda(onFace, qs.baseSize, 2);
    } else {
        std::array<glm::vec4, 4> c;
        if (qs.projected) {
            for (int p = 0; p < 4; ++p) {
                const glm::vec4& v = in[size_t(p)];
                c[size_t(p)] = glm::vec4(v.x / v.w, v.y / v.w, v.z / v.w, 0.0f);
            }
        } else {
            for (int p = 0; p < 4; ++p) c[size_t(p)] = glm::vec4(glm::vec3(in[size_t(p)]), 0.0f);
        }
        for (int p = 0; p < 4; ++p) {
            s[p] = c[size_t(p)].x;
            t[p] = c[size_t(p)].y;
            face[p] = 0;
        }
        lambda = quadLambda(c, qs.baseSize, kTarget == Target::OneD ? 1 : 2);
    }
    return std::clamp(lambda + qs.lodBias, qs.lodMin, qs.lodMax);
}

template <Target kTarget, Addr kS, Addr kT>
uint64_t sampleQuadKernel(const QuadSampler& qs, const std::array<glm::vec4, 4>& in,
                          std::array<Rgba8, 4>& out) {
    constexpr bool kTwoD = kTarget != Target::OneD;
    float s[4], t[4];
    int face[4];
    const int32_t lambda = projectQuad<kTarget>(qs, in, s, t, face);
    const LevelChoice ch = chooseLevels(*qs.texture, qs.sampler, lambda);
    const LevelView& L0 = qs.level[size_t(ch.level0)];
    const LevelView& L1 = qs.level[size_t(ch.level1)];

    if (ch.filter == FilterMode::Linear) {
        // One level's sum for pixel p: S − 2^23 (2D) or R − 2^15 (1D).
        auto levelSum = [&](const LevelView& L, int p) {
            const Rgba8* base = L.data + size_t(face[p]) * L.faceStride;
            int32_t x0, x1, fx;
            linearAxis<kS>(s[p], L.width, x0, x1, fx);
            if constexpr (kTwoD) {
                int32_t y0, y1, fy;
                linearAxis<kT>(t[p], L.height, y0, y1, fy);
                return bilinearBiased(base + size_t(y0) * size_t(L.width),
                                      base + size_t(y1) * size_t(L.width), x0, x1, fx, fy);
            } else {
                return pairBiased(load4(base + x0), load4(base + x1), fx);
            }
        };
        if (ch.blend) {
            for (int p = 0; p < 4; ++p) {
                const __m128i a = levelSum(L0, p), b = levelSum(L1, p);
                out[size_t(p)] = kTwoD ? finishBilinearBlend(a, b, ch.frac)
                                       : finishPairBlend(a, b, ch.frac);
            }
        } else {
            for (int p = 0; p < 4; ++p) {
                const __m128i a = levelSum(L0, p);
                out[size_t(p)] = kTwoD ? finishBilinear(a) : finishPair(a);
            }
        }
        return uint64_t(kTwoD ? 4 : 2) * (ch.blend ? 2 : 1) * 4;
    }
    // NEAREST: one texel per level; two levels blend with 8 weight bits.
    auto texel = [&](const LevelView& L, int p) {
        const Rgba8* base = L.data + size_t(face[p]) * L.faceStride;
        const int32_t x = nearestAxis<kS>(s[p], L.width);
        const int32_t y = kTwoD ? nearestAxis<kT>(t[p], L.height) : 0;
        return base + size_t(y) * size_t(L.width) + size_t(x);
    };
    if (ch.blend) {
        for (int p = 0; p < 4; ++p)
            out[size_t(p)] = finishPair(pairBiased(load4(texel(L0, p)), load4(texel(L1, p)), ch.frac));
    } else {
        for (int p = 0; p < 4; ++p) out[size_t(p)] = *texel(L0, p);
    }
    return uint64_t(ch.blend ? 2 : 1) * 4;
}

bool specialisable(AddressMode m, int n) {
    return m == AddressMode::ClampToEdge || (m == AddressMode::Wrap && (n & (n - 1)) == 0);
}
Addr addrOf(AddressMode m) { return m == AddressMode::ClampToEdge ? Addr::Edge : Addr::Pow2; }

template <Target kTarget>
QuadSampleFn pick(Addr s, Addr t) {
    if (s == Addr::Edge)
        return t == Addr::Edge ? &sampleQuadKernel<kTarget, Addr::Edge, Addr::Edge>
                               : &sampleQuadKernel<kTarget, Addr::Edge, Addr::Pow2>;
    return t == Addr::Edge ? &sampleQuadKernel<kTarget, Addr::Pow2, Addr::Edge>
                           : &sampleQuadKernel<kTarget, Addr::Pow2, Addr::Pow2>;
}

}  // namespace

QuadSampler compileQuadSampler(const Texture& t, const SamplerState& s, bool projected,
                               bool hasColorTable) {
    QuadSampler q;
    q.texture = &t;
    q.sampler = s;
    q.projected = projected;
    const TextureTarget target = t.desc().target;
    if (t.isFloat() || hasColorTable || t.levels() > QuadSampler::kMaxLevels) return q;
    const int base = std::clamp(s.baseLevel, 0, t.levels() - 1);
    q.baseSize = t.levelSize(base);
    // biasAndClampLambda with its three conversions done once.
    q.lodBias = lodFixedFromFloat(s.lodBias);
    q.lodMin = lodFixedFromFloat(s.minLod);
    q.lodMax = std::max(q.lodMin, lodFixedFromFloat(s.maxLod));
    for (int l = 0; l < t.levels(); ++l) {
        LevelView& v = q.level[size_t(l)];
        v.data = t.data8(l, 0);
        v.faceStride = t.faces() > 1 ? uint32_t(t.data8(l, 1) - t.data8(l, 0)) : 0u;
        v.width = t.levelSize(l)[0];
        v.height = t.levelSize(l)[1];
    }
    const int w = t.desc().width, h = t.desc().height;
    switch (target) {
        case TextureTarget::CubeMap:
            q.fn = &sampleQuadKernel<Target::Cube, Addr::Edge, Addr::Edge>;
            break;
        case TextureTarget::Texture2D:
            if (specialisable(s.address[0], w) && specialisable(s.address[1], h))
                q.fn = pick<Target::TwoD>(addrOf(s.address[0]), addrOf(s.address[1]));
            break;
        case TextureTarget::Texture1D:
            if (specialisable(s.address[0], w))
                q.fn = addrOf(s.address[0]) == Addr::Edge
                           ? &sampleQuadKernel<Target::OneD, Addr::Edge, Addr::Edge>
                           : &sampleQuadKernel<Target::OneD, Addr::Pow2, Addr::Edge>;
            break;
        default: break;
    }
    return q;
}

}  // namespace rg::tex::detail
