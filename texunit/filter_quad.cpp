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
//
// Each kernel exists twice: SSE2 (any x86-64) and AVX2, chosen when compiled (haveAvx2,
// allowAvx2Kernels). The AVX2 twin runs s and t through one 8-lane register for the tap
// indices and weights, and the taps of two pixels through one 256-bit pmaddwd; its float
// operations are the SSE2 ones lane for lane and its integer sums the same sums, so both
// give the same bytes (tests/texunit runs the randomized comparisons under each).
#include "filter_quad.h"

#include <emmintrin.h>
#include <immintrin.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>

#include "addressing.h"
#include "core/cpu.h"
#include "cube_select.h"
#include "stage_arith.h"

namespace rg::tex::detail {

namespace {

enum class Target : uint8_t { OneD, TwoD, Cube };
// The address modes the kernels specialise on: CLAMP_TO_EDGE, and WRAP on a power of two
// (addressTexel's mask branch).
enum class Addr : uint8_t { Edge, Pow2 };

// ---- addressing, four pixels per register ------------------------------------------
// The texel coordinates of the quad's four pixels on one level: toSubTexel, floorToInt
// and addressTexel lane for lane (the same IEEE operations as the scalar code: mulps is
// mulss, cvttps2dq is the int32 cast, min/max of a non-NaN value are std::clamp).
template <Addr kA>
inline __m128i address4(__m128i i, int32_t n) {
    if constexpr (kA == Addr::Edge) {
        i = _mm_andnot_si128(_mm_srai_epi32(i, 31), i);  // max(i, 0)
        const __m128i top = _mm_set1_epi32(n - 1);
        const __m128i over = _mm_cmpgt_epi32(i, top);
        return _mm_or_si128(_mm_andnot_si128(over, i), _mm_and_si128(over, top));
    } else {
        return _mm_and_si128(i, _mm_set1_epi32(n - 1));
    }
}

// ⌊c·n·256⌋ per lane as toSubTexel, NaN coordinates counting as 0 (axisFootprint).
inline __m128i subTexel4(__m128 c, int32_t n) {
    c = _mm_and_ps(c, _mm_cmpord_ps(c, c));
    __m128 u = _mm_mul_ps(c, _mm_set1_ps(float(n)));
    u = _mm_and_ps(u, _mm_cmpord_ps(u, u));
    u = _mm_min_ps(_mm_max_ps(u, _mm_set1_ps(-4194304.0f)), _mm_set1_ps(4194304.0f));
    const __m128 v = _mm_mul_ps(u, _mm_set1_ps(float(1 << kSubTexelBits)));
    const __m128i i = _mm_cvttps_epi32(v);
    return _mm_add_epi32(i, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(i), v)));
}

template <Addr kA>
inline __m128i nearestLanes(__m128 c, int32_t n) {
    return address4<kA>(_mm_srai_epi32(subTexel4(c, n), kSubTexelBits), n);
}

// axisFootprint(Linear) of the four pixels: texel indices and packed weight pairs per
// lane.
struct AxisLanes {
    __m128i i0, i1, weights;
};
template <Addr kA>
inline AxisLanes linearLanes(__m128 c, int32_t n) {
    const __m128i u =
        _mm_sub_epi32(subTexel4(c, n), _mm_set1_epi32(1 << (kSubTexelBits - 1)));
    const __m128i b = _mm_srai_epi32(u, kSubTexelBits);
    const __m128i frac = _mm_and_si128(u, _mm_set1_epi32((1 << kSubTexelBits) - 1));
    return {address4<kA>(b, n), address4<kA>(_mm_add_epi32(b, _mm_set1_epi32(1)), n),
            _mm_or_si128(_mm_slli_epi32(frac, 16),
                         _mm_sub_epi32(_mm_set1_epi32(1 << kSubTexelBits), frac))};
}
// a·b per lane for 0 ≤ a, b and a·b < 2^31 (texel offsets inside one level): SSE2 has
// only the 32×32 → 64 multiply of lanes 0 and 2.
inline __m128i mulLanes(__m128i a, uint32_t b) {
    const __m128i bv = _mm_set1_epi32(int32_t(b));
    const __m128i even = _mm_mul_epu32(a, bv),
                  odd = _mm_mul_epu32(_mm_srli_epi64(a, 32), bv);
    return _mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                              _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0)));
}

// ---- the weighted sums --------------------------------------------------------------
inline __m128i load4(const Rgba8* p) {
    int32_t v;
    std::memcpy(&v, p, 4);
    return _mm_cvtsi32_si128(v);
}
// (256 − w, w) in each pair of int16 lanes: the weights of the first and second tap.
inline __m128i weightPair(int32_t w) {
    return _mm_set1_epi32(int32_t((uint32_t(w) << 16) | uint32_t(256 - w)));
}
// Interleaves the int16 lanes of p = (a0 a1 a2 a3 b0 b1 b2 b3) into (a0 b0 a1 b1 ...).
inline __m128i interleaveHalves(__m128i p) {
    return _mm_unpacklo_epi16(p, _mm_srli_si128(p, 8));
}

// Σ wx·(t − 128) over taps a (weight 256 − α) and b (weight α), `w` = weightPair(α):
// R − 2^15 per channel.
inline __m128i pairBiased(__m128i a, __m128i b, __m128i w) {
    const __m128i t =
        _mm_sub_epi16(_mm_unpacklo_epi8(_mm_unpacklo_epi8(a, b), _mm_setzero_si128()),
                      _mm_set1_epi16(128));
    return _mm_madd_epi16(t, w);
}

// The bilinear sum S − 2^23 per channel over texels t00, t01 (row y0) and t10, t11 (row
// y1); wx, wy the packed weight pairs (AxisLanes::weights).
inline __m128i bilinearBiased(const Rgba8* t00, const Rgba8* t01, const Rgba8* t10,
                              const Rgba8* t11, int32_t wxPair, int32_t wyPair) {
    const __m128i zero = _mm_setzero_si128();
    const __m128i row0 = _mm_unpacklo_epi8(load4(t00), load4(t01));
    const __m128i row1 = _mm_unpacklo_epi8(load4(t10), load4(t11));
    const __m128i both = _mm_unpacklo_epi64(row0, row1);
    const __m128i k128 = _mm_set1_epi16(128);
    const __m128i t0 = _mm_sub_epi16(_mm_unpacklo_epi8(both, zero), k128);
    const __m128i t1 = _mm_sub_epi16(_mm_unpackhi_epi8(both, zero), k128);
    const __m128i wx = _mm_set1_epi32(wxPair);
    const __m128i p = _mm_packs_epi32(_mm_madd_epi16(t0, wx), _mm_madd_epi16(t1, wx));
    return _mm_madd_epi16(interleaveHalves(p), _mm_set1_epi32(wyPair));
}

// Rounded results (docs/hardware.md, "Filtering": ⌊(Σ + 2^(bits−1)) / 2^bits⌋), int32
// lanes r, g, b, a of one pixel.
inline __m128i finishPair(__m128i rBiased) {  // 8 weight bits, R − 2^15
    return _mm_srai_epi32(_mm_add_epi32(rBiased, _mm_set1_epi32(32768 + 128)), 8);
}
inline __m128i finishBilinear(__m128i sBiased) {  // 16 weight bits, S − 2^23
    return _mm_srai_epi32(_mm_add_epi32(sBiased, _mm_set1_epi32((1 << 23) + (1 << 15))),
                          16);
}
// Two levels of 8-bit-weight sums (R − 2^15 each), blended by f: 16 weight bits.
inline __m128i finishPairBlend(__m128i r0, __m128i r1, int32_t f) {
    const __m128i s =
        _mm_madd_epi16(interleaveHalves(_mm_packs_epi32(r0, r1)), weightPair(f));
    return _mm_srai_epi32(_mm_add_epi32(s, _mm_set1_epi32((1 << 23) + (1 << 15))), 16);
}
// Two levels of bilinear sums (S − 2^23 each), blended by f: 24 weight bits.
inline __m128i finishBilinearBlend(__m128i s0, __m128i s1, int32_t f) {
    const __m128i w = weightPair(f);
    const __m128i hi = _mm_packs_epi32(_mm_srai_epi32(s0, 8), _mm_srai_epi32(s1, 8));
    const __m128i m = _mm_set1_epi32(255);
    const __m128i lo = _mm_packs_epi32(_mm_and_si128(s0, m), _mm_and_si128(s1, m));
    const __m128i sum =
        _mm_add_epi32(_mm_slli_epi32(_mm_madd_epi16(interleaveHalves(hi), w), 8),
                      _mm_madd_epi16(interleaveHalves(lo), w));
    // + 2^31 (the bias) + 2^23 (the rounding half), wrapping; the true value is < 2^32.
    const __m128i t = _mm_add_epi32(sum, _mm_set1_epi32(int32_t(0x80800000u)));
    return _mm_srli_epi32(t, 24);
}
// Four pixels' int32 lanes in [0, 255] → 16 bytes, pixel p in bytes 4p..4p+3.
inline __m128i packQuad(const __m128i v[4]) {
    return _mm_packus_epi16(_mm_packs_epi32(v[0], v[1]), _mm_packs_epi32(v[2], v[3]));
}

// ---- projection and λ, as TextureUnits::projectQuad -----------------------------------
template <int kLane>
inline float lane(__m128 v) {
    return _mm_cvtss_f32(_mm_shuffle_ps(v, v, _MM_SHUFFLE(kLane, kLane, kLane, kLane)));
}
inline __m128 flipSign(__m128 v) { return _mm_xor_ps(v, _mm_set1_ps(-0.0f)); }
inline __m128 select(__m128 mask, __m128 a, __m128 b) {  // mask ? a : b
    return _mm_or_ps(_mm_and_ps(mask, a), _mm_andnot_ps(mask, b));
}

// The level choice of a cube quad from its directions (x, y, z), face coordinates (s, t)
// and faces: λ from all four pixels measured on pixel 0's face.
[[gnu::always_inline]] inline LevelChoice cubeChoice(const QuadSampler& qs, __m128 x, __m128 y,
                                                     __m128 z, __m128 s, __m128 t,
                                                     const int face[4]) {
    float s1 = lane<1>(s), t1 = lane<1>(t), s2 = lane<2>(s), t2 = lane<2>(t);
    if (face[1] != face[0]) {
        const CubeCoord cc =
            detail::projectOntoCubeFace(CubeFace(face[0]), glm::vec3(lane<1>(x), lane<1>(y), lane<1>(z)));
        s1 = cc.s;
        t1 = cc.t;
    }
    if (face[2] != face[0]) {
        const CubeCoord cc =
            detail::projectOntoCubeFace(CubeFace(face[0]), glm::vec3(lane<2>(x), lane<2>(y), lane<2>(z)));
        s2 = cc.s;
        t2 = cc.t;
    }
    const int32_t lambda = quadLambdaInline(lane<0>(s), s1, s2, lane<0>(t), t1, t2,
                                            qs.baseSizeF[0], qs.baseSizeF[1], 2);
    return chooseLevelsInline(qs.levels, std::clamp(lambda + qs.lodBias, qs.lodMin, qs.lodMax));
}
// Coordinates of the four pixels (s, t per lane; cube: on each pixel's own face) and the
// level choice from the biased, clamped λ — or the constant choice when λ cannot matter.
// x, y, z, w: the four pixels' s, t, r, q (one component per register, pixel p in lane p).
template <Target kTarget>
[[gnu::always_inline]] inline LevelChoice projectLanes(const QuadSampler& qs, __m128 x,
                                                       __m128 y, __m128 z, __m128 w,
                                                       __m128& s, __m128& t, int face[4],
                                                       __m128i& face4) {
    int32_t lambda;
    if constexpr (kTarget == Target::Cube) {
        // selectCubeFace lane for lane: ties X before Y before Z (>=, false on NaN as the
        // scalar comparisons), the sign of a zero counts as positive.
        const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
        const __m128 ax = _mm_and_ps(x, absMask), ay = _mm_and_ps(y, absMask),
                     az = _mm_and_ps(z, absMask);
        const __m128 zero = _mm_setzero_ps();
        const __m128 isX = _mm_and_ps(_mm_cmpge_ps(ax, ay), _mm_cmpge_ps(ax, az));
        const __m128 isY = _mm_andnot_ps(isX, _mm_cmpge_ps(ay, az));
        const __m128 isZ =
            _mm_andnot_ps(_mm_or_ps(isX, isY), _mm_castsi128_ps(_mm_set1_epi32(-1)));
        const __m128 px = _mm_cmpge_ps(x, zero), py = _mm_cmpge_ps(y, zero),
                     pz = _mm_cmpge_ps(z, zero);
        // The table: +X (−z, −y, x), −X (z, −y, x), +Y (x, z, y), −Y (x, −z, y),
        // +Z (x, −y, z), −Z (−x, −y, z).
        const __m128 sc = select(isX, select(px, flipSign(z), z),
                                 select(isY, x, select(pz, x, flipSign(x))));
        const __m128 tc = select(isY, select(py, z, flipSign(z)), flipSign(y));
        const __m128 ma = select(isX, x, select(isY, y, z));
        const __m128 a = _mm_and_ps(ma, absMask);
        const __m128 ok = _mm_cmpgt_ps(a, zero);  // zero or NaN major axis: face centre
        const __m128 one = _mm_set1_ps(1.0f), half = _mm_set1_ps(0.5f);
        s = select(ok, _mm_mul_ps(_mm_add_ps(_mm_div_ps(sc, a), one), half), half);
        t = select(ok, _mm_mul_ps(_mm_add_ps(_mm_div_ps(tc, a), one), half), half);
        const __m128i fi =
            _mm_or_si128(_mm_and_si128(_mm_castps_si128(isY), _mm_set1_epi32(2)),
                         _mm_and_si128(_mm_castps_si128(isZ), _mm_set1_epi32(4)));
        const __m128 pos = select(isX, px, select(isY, py, pz));
        face4 =
            _mm_add_epi32(fi, _mm_andnot_si128(_mm_castps_si128(pos), _mm_set1_epi32(1)));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(face), face4);
        if (qs.constantChoice) return qs.choice;
        return cubeChoice(qs, x, y, z, s, t, face);
    } else {
        // x/1 is x (exact division; a NaN stays a NaN, which every later step treats
        // alike whatever its payload), so q = 1 on all four pixels — affine coordinates,
        // the common case — skips the two divisions.
        if (qs.projected && _mm_movemask_ps(_mm_cmpneq_ps(w, _mm_set1_ps(1.0f))) != 0) {
            x = _mm_div_ps(x, w);
            y = _mm_div_ps(y, w);
        }
        s = x;
        t = y;
        for (int p = 0; p < 4; ++p) face[p] = 0;
        face4 = _mm_setzero_si128();
        if (qs.constantChoice) return qs.choice;
        lambda = quadLambdaInline(lane<0>(s), lane<1>(s), lane<2>(s), lane<0>(t),
                                  lane<1>(t), lane<2>(t), qs.baseSizeF[0],
                                  qs.baseSizeF[1], kTarget == Target::OneD ? 1 : 2);
    }
    return chooseLevelsInline(qs.levels,
                              std::clamp(lambda + qs.lodBias, qs.lodMin, qs.lodMax));
}
// The same from a FragmentQuad's coordinate set (per pixel (s, t, r, q)), transposed.
template <Target kTarget>
[[gnu::always_inline]] inline LevelChoice projectQuad(const QuadSampler& qs,
                                                      const std::array<glm::vec4, 4>& in,
                                                      __m128& s, __m128& t, int face[4],
                                                      __m128i& face4) {
    __m128 x = _mm_loadu_ps(&in[0][0]), y = _mm_loadu_ps(&in[1][0]);
    __m128 z = _mm_loadu_ps(&in[2][0]), w = _mm_loadu_ps(&in[3][0]);
    _MM_TRANSPOSE4_PS(x, y, z, w);
    return projectLanes<kTarget>(qs, x, y, z, w, s, t, face, face4);
}

// Phase 1 of a kernel: everything that depends on the coordinates and the texture's
// shape but not on its texels — projection, λ, level choice, tap indices and weights.
// The level part of phase 1, from the projected coordinates: tap indices and weights per
// level used, and the fetch count.
template <Target kTarget, Addr kS, Addr kT>
[[gnu::always_inline]] inline uint64_t prepareLevels(const QuadSampler& qs, LevelChoice ch,
                                                     __m128 s, __m128 t, __m128i face4,
                                                     QuadFootprint& fp) {
    constexpr bool kTwoD = kTarget != Target::OneD;
    fp.ch = ch;
    auto store = [](int32_t* dst, __m128i v) {
        _mm_store_si128(reinterpret_cast<__m128i*>(dst), v);
    };
    const int nLevels = ch.blend ? 2 : 1;
    for (int li = 0; li < nLevels; ++li) {
        const LevelView& L = qs.level[size_t(li == 0 ? ch.level0 : ch.level1)];
        const __m128i faceBase =
            kTarget == Target::Cube ? mulLanes(face4, L.faceStride) : _mm_setzero_si128();
        if (ch.filter == FilterMode::Linear) {
            const AxisLanes ax = linearLanes<kS>(s, L.width);
            store(fp.wx[li], ax.weights);
            if constexpr (kTwoD) {
                const AxisLanes ay = linearLanes<kT>(t, L.height);
                const __m128i row0 =
                    _mm_add_epi32(faceBase, mulLanes(ay.i0, uint32_t(L.width)));
                const __m128i row1 =
                    _mm_add_epi32(faceBase, mulLanes(ay.i1, uint32_t(L.width)));
                store(fp.i00[li], _mm_add_epi32(row0, ax.i0));
                store(fp.i01[li], _mm_add_epi32(row0, ax.i1));
                store(fp.i10[li], _mm_add_epi32(row1, ax.i0));
                store(fp.i11[li], _mm_add_epi32(row1, ax.i1));
                store(fp.wy[li], ay.weights);
            } else {
                store(fp.i00[li], _mm_add_epi32(faceBase, ax.i0));
                store(fp.i01[li], _mm_add_epi32(faceBase, ax.i1));
            }
        } else {
            __m128i i = nearestLanes<kS>(s, L.width);
            if constexpr (kTwoD)
                i = _mm_add_epi32(
                    i, mulLanes(nearestLanes<kT>(t, L.height), uint32_t(L.width)));
            store(fp.i00[li], _mm_add_epi32(faceBase, i));
        }
    }
    const uint64_t perPixel =
        (ch.filter == FilterMode::Linear ? (kTwoD ? 4 : 2) : 1) * uint64_t(nLevels);
    fp.fetches = perPixel * 4;
    return fp.fetches;
}
template <Target kTarget, Addr kS, Addr kT>
[[gnu::always_inline]] inline uint64_t prepareQuad(const QuadSampler& qs,
                                                   const std::array<glm::vec4, 4>& in,
                                                   QuadFootprint& fp) {
    __m128 s, t;
    int face[4];
    __m128i face4;
    const LevelChoice ch = projectQuad<kTarget>(qs, in, s, t, face, face4);
    return prepareLevels<kTarget, kS, kT>(qs, ch, s, t, face4, fp);
}

// Phase 2: the texels and their exactly rounded weighted sum, from the level data of the
// sampler's texture (which may be another texture of the same shape: footprint sharing).
template <bool kTwoD>
[[gnu::always_inline]] inline __m128i gatherQuad(const QuadSampler& qs,
                                                 const QuadFootprint& fp) {
    const LevelChoice& ch = fp.ch;
    const Rgba8* d0 = qs.level[size_t(ch.level0)].data;
    const Rgba8* d1 = qs.level[size_t(ch.level1)].data;
    __m128i v[4];
    if (ch.filter == FilterMode::Linear) {
        // One level's sums for the four pixels: S − 2^23 (2D) or R − 2^15 (1D).
        auto levelSums = [&](const Rgba8* d, int li, __m128i sum[4]) {
            for (int p = 0; p < 4; ++p) {
                if constexpr (kTwoD)
                    sum[p] = bilinearBiased(d + fp.i00[li][p], d + fp.i01[li][p],
                                            d + fp.i10[li][p], d + fp.i11[li][p],
                                            fp.wx[li][p], fp.wy[li][p]);
                else
                    sum[p] =
                        pairBiased(load4(d + fp.i00[li][p]), load4(d + fp.i01[li][p]),
                                   _mm_set1_epi32(fp.wx[li][p]));
            }
        };
        __m128i a[4];
        levelSums(d0, 0, a);
        if (ch.blend) {
            __m128i b[4];
            levelSums(d1, 1, b);
            for (int p = 0; p < 4; ++p)
                v[p] = kTwoD ? finishBilinearBlend(a[p], b[p], ch.frac)
                             : finishPairBlend(a[p], b[p], ch.frac);
        } else {
            for (int p = 0; p < 4; ++p)
                v[p] = kTwoD ? finishBilinear(a[p]) : finishPair(a[p]);
        }
        return packQuad(v);
    }
    // NEAREST: one texel per level; two levels blend with 8 weight bits.
    if (ch.blend) {
        const __m128i w = weightPair(ch.frac);
        for (int p = 0; p < 4; ++p)
            v[p] = finishPair(
                pairBiased(load4(d0 + fp.i00[0][p]), load4(d1 + fp.i00[1][p]), w));
        return packQuad(v);
    }
    return _mm_unpacklo_epi64(
        _mm_unpacklo_epi32(load4(d0 + fp.i00[0][0]), load4(d0 + fp.i00[0][1])),
        _mm_unpacklo_epi32(load4(d0 + fp.i00[0][2]), load4(d0 + fp.i00[0][3])));
}

// ---- AVX2: the four pixels of a quad in two 256-bit registers ------------------------
// The same integer sums as gatherQuad (so the same bytes: integer arithmetic is exact and
// the operands are identical), arranged for width instead of per pixel: the taps of pixels
// 0 and 2 go through the lanes of one register (128-bit lane 0: pixel 0, lane 1: pixel 2)
// and those of pixels 1 and 3 through another, so one pmaddwd weighs a row pair of two
// pixels, all four channels. Chosen at run time (haveAvx2), as the rasterizer's spans.
#define RG_AVX2 __attribute__((target("avx2")))

// RETROGLASS_NO_AVX2 (any value) selects the SSE2 kernels, as it does the rasterizer's
// (PathsAgree.WithoutAvx2 then holds them to the reference end to end).
bool haveAvx2() {
    return avx2Enabled();
}
}  // namespace
std::atomic<bool> avx2Allowed{true};  // allowAvx2Kernels (texture_units.h)
namespace {

// Per-pixel int32 values of an aligned [4] array, pixel p's value repeated over the four
// 32-bit lanes of its half: (v0 ×4 | v2 ×4) in `even`, (v1 ×4 | v3 ×4) in `odd`.
RG_AVX2 inline void spreadPixels(const int32_t* v, __m256i& even, __m256i& odd) {
    const __m256i x = _mm256_castsi128_si256(_mm_load_si128(reinterpret_cast<const __m128i*>(v)));
    even = _mm256_permutevar8x32_epi32(x, _mm256_setr_epi32(0, 0, 0, 0, 2, 2, 2, 2));
    odd = _mm256_permutevar8x32_epi32(x, _mm256_setr_epi32(1, 1, 1, 1, 3, 3, 3, 3));
}
// (a0 b0 a1 b1 a2 b2 a3 b3) from int16 lanes (a0..a3 b0..b3) in each 128-bit lane: the
// interleaveHalves of gatherQuad.
RG_AVX2 inline __m256i interleaveHalves8(__m256i p) {
    const __m256i m = _mm256_setr_epi8(0, 1, 8, 9, 2, 3, 10, 11, 4, 5, 12, 13, 6, 7, 14, 15, 0,
                                       1, 8, 9, 2, 3, 10, 11, 4, 5, 12, 13, 6, 7, 14, 15);
    return _mm256_shuffle_epi8(p, m);
}
struct Lanes8 {
    __m256i even, odd;  // int32 per channel: pixels 0 | 2 and 1 | 3
};
// Σ wx·(t − 128) over taps a (weight 256 − α) and b (weight α) of each pixel: R − 2^15
// per channel (pairBiased for four pixels). `we`/`wo`: spreadPixels of the weight pairs.
[[gnu::always_inline]] RG_AVX2 inline Lanes8 rowPairs8(const Rgba8* d, const int32_t* ia, const int32_t* ib,
                                __m256i we, __m256i wo, bool adjacent) {
    // Texels (a0 b0 a1 b1 | a2 b2 a3 b3), loaded one by one: vpgatherdd measured slower
    // than eight scalar loads (AMD EPYC, tex_bilinear_2d: the sampler 28 → 31 % of the
    // frame). When every b is the texel after its a (QuadFootprint::adjacent), (a b) is one
    // 8-byte load of two texels that both exist: the same values, half the loads.
    // (Forced inline: in the pair kernel GCC's inliner otherwise gives up on it.)
    auto two = [&](int p) __attribute__((always_inline)) {
        if (adjacent) return _mm_loadl_epi64(reinterpret_cast<const __m128i*>(d + ia[p]));
        return _mm_unpacklo_epi32(load4(d + ia[p]), load4(d + ib[p]));
    };
    const __m256i g = _mm256_set_m128i(_mm_unpacklo_epi64(two(2), two(3)),
                                       _mm_unpacklo_epi64(two(0), two(1)));
    // Per channel the int16 pair (a, b), zero-extended: pixel 0 | 2, then pixel 1 | 3.
    const __m256i z = _mm256_setr_epi8(0, -1, 4, -1, 1, -1, 5, -1, 2, -1, 6, -1, 3, -1, 7, -1,
                                       0, -1, 4, -1, 1, -1, 5, -1, 2, -1, 6, -1, 3, -1, 7, -1);
    const __m256i zo = _mm256_setr_epi8(8, -1, 12, -1, 9, -1, 13, -1, 10, -1, 14, -1, 11, -1, 15,
                                        -1, 8, -1, 12, -1, 9, -1, 13, -1, 10, -1, 14, -1, 11,
                                        -1, 15, -1);
    const __m256i k128 = _mm256_set1_epi16(128);
    const __m256i te = _mm256_sub_epi16(_mm256_shuffle_epi8(g, z), k128);
    const __m256i to = _mm256_sub_epi16(_mm256_shuffle_epi8(g, zo), k128);
    return {_mm256_madd_epi16(te, we), _mm256_madd_epi16(to, wo)};
}
// The bilinear sums S − 2^23 per channel of one level (bilinearBiased for four pixels).
[[gnu::always_inline]] RG_AVX2 inline Lanes8 bilinear8(const Rgba8* d, const QuadFootprint& fp, int li) {
    __m256i wxe, wxo, wye, wyo;
    spreadPixels(fp.wx[li], wxe, wxo);
    spreadPixels(fp.wy[li], wye, wyo);
    const Lanes8 r0 = rowPairs8(d, fp.i00[li], fp.i01[li], wxe, wxo, fp.adjacent[li]);
    const Lanes8 r1 = rowPairs8(d, fp.i10[li], fp.i11[li], wxe, wxo, fp.adjacent[li]);
    return {_mm256_madd_epi16(interleaveHalves8(_mm256_packs_epi32(r0.even, r1.even)), wye),
            _mm256_madd_epi16(interleaveHalves8(_mm256_packs_epi32(r0.odd, r1.odd)), wyo)};
}
// finishBilinearBlend lane for lane (24 weight bits, S' split into int16 halves).
RG_AVX2 inline __m256i bilinearBlend8(__m256i s0, __m256i s1, __m256i w) {
    const __m256i m = _mm256_set1_epi32(255);
    const __m256i hi = _mm256_packs_epi32(_mm256_srai_epi32(s0, 8), _mm256_srai_epi32(s1, 8));
    const __m256i lo = _mm256_packs_epi32(_mm256_and_si256(s0, m), _mm256_and_si256(s1, m));
    const __m256i sum =
        _mm256_add_epi32(_mm256_slli_epi32(_mm256_madd_epi16(interleaveHalves8(hi), w), 8),
                         _mm256_madd_epi16(interleaveHalves8(lo), w));
    return _mm256_srli_epi32(_mm256_add_epi32(sum, _mm256_set1_epi32(int32_t(0x80800000u))),
                             24);
}
// finishPairBlend lane for lane (16 weight bits).
RG_AVX2 inline __m256i pairBlend8(__m256i r0, __m256i r1, __m256i w) {
    const __m256i s = _mm256_madd_epi16(interleaveHalves8(_mm256_packs_epi32(r0, r1)), w);
    return _mm256_srai_epi32(_mm256_add_epi32(s, _mm256_set1_epi32((1 << 23) + (1 << 15))), 16);
}
// int32 lanes in [0, 255] of pixels 0 | 2 and 1 | 3 → 16 bytes, pixel p in bytes 4p..4p+3.
RG_AVX2 inline __m128i packQuad8(const Lanes8& v) {
    __m256i p = _mm256_packs_epi32(v.even, v.odd);  // (0 1 | 2 3) as int16
    p = _mm256_packus_epi16(p, p);                  // (0 1 0 1 | 2 3 2 3) as bytes
    return _mm256_castsi256_si128(_mm256_permute4x64_epi64(p, _MM_SHUFFLE(2, 0, 2, 0)));
}

// prepareLevels for LINEAR with s in lanes 0–3 and t in lanes 4–7 of one register: the
// same float operations lane for lane (subTexel4), the same integer results.
template <Addr kA>
RG_AVX2 inline __m256i address8(__m256i i, __m256i top) {
    if constexpr (kA == Addr::Edge)
        return _mm256_min_epi32(_mm256_max_epi32(i, _mm256_setzero_si256()), top);
    else
        return _mm256_and_si256(i, top);
}
template <Addr kS, Addr kT>
RG_AVX2 inline __m256i address8(__m256i i, __m256i top) {
    if constexpr (kS == kT)
        return address8<kS>(i, top);
    else
        return _mm256_blend_epi32(address8<kS>(i, top), address8<kT>(i, top), 0xf0);
}
template <Target kTarget, Addr kS, Addr kT>
[[gnu::always_inline]] RG_AVX2 inline uint64_t prepareLevelsAvx2(const QuadSampler& qs,
                                                                 LevelChoice ch, __m128 s,
                                                                 __m128 t, __m128i face4,
                                                                 QuadFootprint& fp) {
    if (ch.filter != FilterMode::Linear)
        return prepareLevels<kTarget, kS, kT>(qs, ch, s, t, face4, fp);
    constexpr bool kTwoD = kTarget != Target::OneD;
    fp.ch = ch;
    auto store = [](int32_t* dst, __m128i v) {
        _mm_store_si128(reinterpret_cast<__m128i*>(dst), v);
    };
    __m256 c = _mm256_set_m128(t, s);
    c = _mm256_and_ps(c, _mm256_cmp_ps(c, c, _CMP_ORD_Q));
    const int nLevels = ch.blend ? 2 : 1;
    for (int li = 0; li < nLevels; ++li) {
        const LevelView& L = qs.level[size_t(li == 0 ? ch.level0 : ch.level1)];
        const int32_t h = kTwoD ? L.height : 1;
        // subTexel4 on both axes.
        __m256 u = _mm256_mul_ps(
            c, _mm256_setr_ps(float(L.width), float(L.width), float(L.width), float(L.width),
                              float(h), float(h), float(h), float(h)));
        u = _mm256_and_ps(u, _mm256_cmp_ps(u, u, _CMP_ORD_Q));
        u = _mm256_min_ps(_mm256_max_ps(u, _mm256_set1_ps(-4194304.0f)),
                          _mm256_set1_ps(4194304.0f));
        const __m256 v = _mm256_mul_ps(u, _mm256_set1_ps(float(1 << kSubTexelBits)));
        __m256i sub = _mm256_cvttps_epi32(v);
        sub = _mm256_add_epi32(
            sub, _mm256_castps_si256(_mm256_cmp_ps(_mm256_cvtepi32_ps(sub), v, _CMP_GT_OQ)));
        // linearLanes on both axes.
        sub = _mm256_sub_epi32(sub, _mm256_set1_epi32(1 << (kSubTexelBits - 1)));
        const __m256i b = _mm256_srai_epi32(sub, kSubTexelBits);
        const __m256i frac = _mm256_and_si256(sub, _mm256_set1_epi32((1 << kSubTexelBits) - 1));
        const __m256i top = _mm256_setr_epi32(L.width - 1, L.width - 1, L.width - 1,
                                              L.width - 1, h - 1, h - 1, h - 1, h - 1);
        const __m256i i0 = address8<kS, kT>(b, top);
        const __m256i i1 = address8<kS, kT>(_mm256_add_epi32(b, _mm256_set1_epi32(1)), top);
        const __m256i w =
            _mm256_or_si256(_mm256_slli_epi32(frac, 16),
                            _mm256_sub_epi32(_mm256_set1_epi32(1 << kSubTexelBits), frac));
        const __m128i faceBase =
            kTarget == Target::Cube
                ? _mm_mullo_epi32(face4, _mm_set1_epi32(int32_t(L.faceStride)))
                : _mm_setzero_si128();
        const __m128i x0 = _mm256_castsi256_si128(i0), x1 = _mm256_castsi256_si128(i1);
        fp.adjacent[li] = _mm_movemask_epi8(_mm_cmpeq_epi32(
                              x1, _mm_add_epi32(x0, _mm_set1_epi32(1)))) == 0xFFFF;
        store(fp.wx[li], _mm256_castsi256_si128(w));
        if constexpr (kTwoD) {
            const __m128i wv = _mm_set1_epi32(L.width);
            const __m128i row0 =
                _mm_add_epi32(faceBase, _mm_mullo_epi32(_mm256_extracti128_si256(i0, 1), wv));
            const __m128i row1 =
                _mm_add_epi32(faceBase, _mm_mullo_epi32(_mm256_extracti128_si256(i1, 1), wv));
            store(fp.i00[li], _mm_add_epi32(row0, x0));
            store(fp.i01[li], _mm_add_epi32(row0, x1));
            store(fp.i10[li], _mm_add_epi32(row1, x0));
            store(fp.i11[li], _mm_add_epi32(row1, x1));
            store(fp.wy[li], _mm256_extracti128_si256(w, 1));
        } else {
            store(fp.i00[li], _mm_add_epi32(faceBase, x0));
            store(fp.i01[li], _mm_add_epi32(faceBase, x1));
        }
    }
    fp.fetches = uint64_t(kTwoD ? 4 : 2) * uint64_t(nLevels) * 4;
    return fp.fetches;
}
template <Target kTarget, Addr kS, Addr kT>
[[gnu::always_inline]] RG_AVX2 inline uint64_t prepareQuadAvx2(
    const QuadSampler& qs, const std::array<glm::vec4, 4>& in, QuadFootprint& fp) {
    __m128 s, t;
    int face[4];
    __m128i face4;
    const LevelChoice ch = projectQuad<kTarget>(qs, in, s, t, face, face4);
    return prepareLevelsAvx2<kTarget, kS, kT>(qs, ch, s, t, face4, fp);
}

// One level's sums of the four pixels: S − 2^23 (2D) or R − 2^15 (1D) per channel.
template <bool kTwoD>
[[gnu::always_inline]] RG_AVX2 inline Lanes8 levelSums8(const Rgba8* d, const QuadFootprint& fp,
                                                        int li) {
    if constexpr (kTwoD) {
        return bilinear8(d, fp, li);
    } else {
        __m256i we, wo;
        spreadPixels(fp.wx[li], we, wo);
        return rowPairs8(d, fp.i00[li], fp.i01[li], we, wo, fp.adjacent[li]);
    }
}
// The rounded texels of a quad from its level sums `a` (and `b`, the second level's, when
// ch.blend): int32 lanes in [0, 255], pixels 0 | 2 and 1 | 3 as the sums.
template <bool kTwoD>
[[gnu::always_inline]] RG_AVX2 inline Lanes8 finishLanes8(const LevelChoice& ch, const Lanes8& a,
                                                          const Lanes8* b) {
    if (ch.blend) {
        const __m256i w = _mm256_set1_epi32(int32_t((uint32_t(ch.frac) << 16) | uint32_t(256 - ch.frac)));
        if constexpr (kTwoD)
            return {bilinearBlend8(a.even, b->even, w), bilinearBlend8(a.odd, b->odd, w)};
        else
            return {pairBlend8(a.even, b->even, w), pairBlend8(a.odd, b->odd, w)};
    }
    if constexpr (kTwoD) {
        const __m256i r = _mm256_set1_epi32((1 << 23) + (1 << 15));
        return {_mm256_srai_epi32(_mm256_add_epi32(a.even, r), 16),
                _mm256_srai_epi32(_mm256_add_epi32(a.odd, r), 16)};
    } else {
        const __m256i r = _mm256_set1_epi32(32768 + 128);
        return {_mm256_srai_epi32(_mm256_add_epi32(a.even, r), 8),
                _mm256_srai_epi32(_mm256_add_epi32(a.odd, r), 8)};
    }
}
template <bool kTwoD>
[[gnu::always_inline]] RG_AVX2 inline __m128i finishLevels8(const LevelChoice& ch, const Lanes8& a,
                                                           const Lanes8* b) {
    return packQuad8(finishLanes8<kTwoD>(ch, a, b));
}
template <bool kTwoD>
[[gnu::always_inline]] RG_AVX2 inline __m128i gatherQuadAvx2(const QuadSampler& qs, const QuadFootprint& fp) {
    const LevelChoice& ch = fp.ch;
    if (ch.filter != FilterMode::Linear) return gatherQuad<kTwoD>(qs, fp);
    const Lanes8 a = levelSums8<kTwoD>(qs.level[size_t(ch.level0)].data, fp, 0);
    if (ch.blend) {
        const Lanes8 b = levelSums8<kTwoD>(qs.level[size_t(ch.level1)].data, fp, 1);
        return finishLevels8<kTwoD>(ch, a, &b);
    }
    return finishLevels8<kTwoD>(ch, a, nullptr);
}

template <Target kTarget, Addr kS, Addr kT>
RG_AVX2 uint64_t sampleQuadKernelAvx2(const QuadSampler& qs, const std::array<glm::vec4, 4>& in,
                                      __m128i& out) {
    QuadFootprint fp;
    const uint64_t n = prepareQuadAvx2<kTarget, kS, kT>(qs, in, fp);
    out = gatherQuadAvx2<kTarget != Target::OneD>(qs, fp);
    return n;
}
template <Target kTarget, Addr kS, Addr kT>
RG_AVX2 uint64_t prepareKernelAvx2(const QuadSampler& qs, const std::array<glm::vec4, 4>& in,
                                   QuadFootprint& fp) {
    return prepareQuadAvx2<kTarget, kS, kT>(qs, in, fp);
}
template <bool kTwoD>
RG_AVX2 __m128i gatherKernelAvx2(const QuadSampler& qs, const QuadFootprint& fp) {
    return gatherQuadAvx2<kTwoD>(qs, fp);
}

template <Target kTarget, Addr kS, Addr kT>
uint64_t sampleQuadKernel(const QuadSampler& qs, const std::array<glm::vec4, 4>& in,
                          __m128i& out) {
    QuadFootprint fp;
    const uint64_t n = prepareQuad<kTarget, kS, kT>(qs, in, fp);
    out = gatherQuad<kTarget != Target::OneD>(qs, fp);
    return n;
}
template <Target kTarget, Addr kS, Addr kT>
uint64_t prepareKernel(const QuadSampler& qs, const std::array<glm::vec4, 4>& in,
                       QuadFootprint& fp) {
    return prepareQuad<kTarget, kS, kT>(qs, in, fp);
}
template <bool kTwoD>
__m128i gatherKernel(const QuadSampler& qs, const QuadFootprint& fp) {
    return gatherQuad<kTwoD>(qs, fp);
}

// ---- whole cascades ---------------------------------------------------------------------
// One sampled stage of a cascade: the sampler of kind (kT, kS, kU) inlined, then the
// stage's MODULATE/MODULATE arithmetic (quad::evaluate, as shadeQuad's general loop).
// kTexCur: both ops read (TEXTURE, CURRENT) without modifiers or scale (GL MODULATE, the
// PEM passes), where evaluate<Modulate, Modulate> is mulDiv255(texel, CURRENT) on all
// four channels — its colour result, returned for alpha too (same op, same arguments) —
// so the argument selection is left out.
template <Target kT, Addr kS, Addr kU, bool kTexCur>
[[gnu::always_inline]] RG_AVX2 inline uint64_t cascadeStage(const CompiledStages& c, int i,
                                                            const FragmentQuad& q,
                                                            quad::Regs& r) {
    const QuadSampler& qs = c.stage[size_t(i)];
    const StageState& st = c.state[size_t(i)];
    QuadFootprint fp;
    const uint64_t n = prepareQuadAvx2<kT, kS, kU>(qs, q.texCoord[st.texCoordIndex], fp);
    r[arg::Texture] = gatherQuadAvx2<kT != Target::OneD>(qs, fp);
    if constexpr (kTexCur)
        r[arg::Current] = quad::mulDiv255(r[arg::Texture], r[arg::Current]);
    else
        r[arg::Current] = quad::evaluate<TextureOp::Modulate, TextureOp::Modulate>(st, r);
    return n;
}
// The two forms of a one-texture cascade besides MODULATE of colour and alpha, both exact
// through mulDiv255(x, 255) = x for every byte x ((255x + 128 + ((255x + 128) >> 8)) >> 8
// = x), so that an alpha that passes is a multiply by 255 (the hybrid layer passes,
// demos/hybrid/hybrid_renderer.cpp):
//  - kAlpha0 = SelectArg1: stage 0 is colour MODULATE(TEXTURE, CURRENT), alpha
//    SELECTARG1(TEXTURE). With kTexCur that is mulDiv255(texel, CURRENT) once CURRENT's
//    alpha byte is 255: the colour bytes as MODULATE's, the alpha the texel's.
//  - kTail: a last stage that samples nothing, colour MODULATE(CURRENT, TFACTOR), alpha
//    SELECTARG1(CURRENT): mulDiv255(CURRENT, TFACTOR with alpha 255) on all four bytes.
constexpr uint32_t kAlphaByte = 0xff000000u;
template <TextureOp kAlpha0>
[[gnu::always_inline]] inline void stage0AlphaIn(quad::Regs& r) {
    static_assert(kAlpha0 == TextureOp::Modulate || kAlpha0 == TextureOp::SelectArg1);
    if constexpr (kAlpha0 == TextureOp::SelectArg1)
        r[arg::Current] =
            _mm_or_si128(r[arg::Current], _mm_set1_epi32(int32_t(kAlphaByte)));
}
template <bool kTail>
[[gnu::always_inline]] inline __m128i tfactorTail(__m128i current, __m128i tfactor) {
    if constexpr (kTail)
        return quad::mulDiv255(
            current, _mm_or_si128(tfactor, _mm_set1_epi32(int32_t(kAlphaByte))));
    return current;
}
// The stage inputs; with kTexCur only CURRENT (= DIFFUSE) is read. The rasterizer writes
// the quad's colours with one 16-byte store (fragment_quad_textured.h) or as an array copy,
// so one 16-byte load.
template <bool kTexCur>
[[gnu::always_inline]] inline quad::Regs cascadeInputs(const FragmentQuad& q, __m128i tfactor) {
    quad::Regs r;
    r[arg::Diffuse] = quad::load(q.diffuse);
    r[arg::Current] = r[arg::Diffuse];
    if constexpr (!kTexCur) {
        r[arg::Specular] = quad::load(q.specular);
        r[arg::TFactor] = tfactor;
    }
    return r;
}
// kAlpha0 and kTail (above) only with kTexCur, where CURRENT is the one input read.
template <Target kT, Addr kS, Addr kU, bool kTexCur,
          TextureOp kAlpha0 = TextureOp::Modulate, bool kTail = false>
RG_AVX2 uint64_t cascadeOne(const CompiledStages& c, const FragmentQuad& q,
                            __m128i tfactor, __m128i& out) {
    static_assert(kTexCur || (kAlpha0 == TextureOp::Modulate && !kTail));
    quad::Regs r = cascadeInputs<kTexCur>(q, tfactor);
    stage0AlphaIn<kAlpha0>(r);
    const uint64_t n = cascadeStage<kT, kS, kU, kTexCur>(c, 0, q, r);
    out = tfactorTail<kTail>(r[arg::Current], tfactor);
    return n;
}
template <Target kT0, Addr kS0, Addr kU0, Target kT1, Addr kS1, Addr kU1, bool kTexCur>
RG_AVX2 uint64_t cascadeTwo(const CompiledStages& c, const FragmentQuad& q, __m128i tfactor,
                            __m128i& out) {
    quad::Regs r = cascadeInputs<kTexCur>(q, tfactor);
    uint64_t n = cascadeStage<kT0, kS0, kU0, kTexCur>(c, 0, q, r);
    n += cascadeStage<kT1, kS1, kU1, kTexCur>(c, 1, q, r);
    out = r[arg::Current];
    return n;
}
// ---- both quads of a pair through one 8-lane footprint -----------------------------------
// When the two quads of a pair get LINEAR level choices of the same levels (always, for a
// constant choice; their blend fractions may differ), their tap indices and weights come from one 8-lane pass per axis (quad h in
// lanes 4h..4h+3) and stay in registers: the same float operations lane for lane as
// prepareLevelsAvx2 (so the same integers), the same sums as gatherQuadAvx2.

// A constant in every 32-bit lane as one broadcast from memory. GCC 12 builds each
// _mm256_set1 constant as a move, a vmovd and a vpbroadcastd at every use (three µops; the
// pair kernels use a dozen per pair); the asm keeps it a load, which GCC may still hoist
// or share. Only where it was measured to matter (the 2D block path).
template <uint32_t kBits>
[[gnu::always_inline]] RG_AVX2 inline __m256i splat32() {
    static const uint32_t value = kBits;
    __m256i r;
    __asm__("vpbroadcastd %1, %0" : "=x"(r) : "m"(value));
    return r;
}
template <uint32_t kBits>
[[gnu::always_inline]] RG_AVX2 inline __m256 splatF() {
    return _mm256_castsi256_ps(splat32<kBits>());
}

// ⌊c·n·256⌋ per lane, NaNs as 0: prepareLevelsAvx2's sub-texel steps.
// Two steps of subTexel4 are folded: c·n cannot be a NaN once c is not one (n ≥ 1 is
// finite, so ±∞·n is ±∞), so its second NaN test is the identity; and v lies in
// [−2^30, 2^30] and is never a NaN, where ⌊v⌋ rounded in float (vroundps toward −∞) is an
// integer the conversion takes exactly — the value the truncation and its correction give.
[[gnu::always_inline]] RG_AVX2 inline __m256i subTexel8(__m256 c, int32_t n) {
    c = _mm256_and_ps(c, _mm256_cmp_ps(c, c, _CMP_ORD_Q));
    __m256 u = _mm256_mul_ps(c, _mm256_set1_ps(float(n)));
    // ∓2^22 and 2^kSubTexelBits = 256 as float bits.
    static_assert(kSubTexelBits == 8);
    u = _mm256_min_ps(_mm256_max_ps(u, splatF<0xCA800000u>()), splatF<0x4A800000u>());
    const __m256 v = _mm256_mul_ps(u, splatF<0x43800000u>());
    return _mm256_cvttps_epi32(_mm256_round_ps(v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
}
struct Axis8 {
    __m256i i0, i1, w;  // tap indices and packed weight pairs, eight pixels
};
// The floors and packed weight pairs (frac << 16 | 256 − frac) of eight coordinates on an
// axis of n texels, before addressing: prepareLevelsAvx2's steps.
struct RawAxis8 {
    __m256i b, w;
};
[[gnu::always_inline]] RG_AVX2 inline RawAxis8 rawAxis8(__m256 c, int32_t n) {
    const __m256i sub = _mm256_sub_epi32(subTexel8(c, n), splat32<1u << (kSubTexelBits - 1)>());
    const __m256i frac = _mm256_and_si256(sub, splat32<(1u << kSubTexelBits) - 1>());
    return {_mm256_srai_epi32(sub, kSubTexelBits),
            _mm256_or_si256(_mm256_slli_epi32(frac, 16),
                            _mm256_sub_epi32(splat32<1u << kSubTexelBits>(), frac))};
}
// rawAxis8 with both taps addressed.
template <Addr kA>
[[gnu::always_inline]] RG_AVX2 inline Axis8 linearAxis8(__m256 c, int32_t n) {
    const RawAxis8 raw = rawAxis8(c, n);
    const __m256i top = _mm256_set1_epi32(n - 1);
    return {address8<kA>(raw.b, top), address8<kA>(_mm256_add_epi32(raw.b, splat32<1>()), top),
            raw.w};
}
// spreadPixels of quad h's lanes of an 8-lane register.
[[gnu::always_inline]] RG_AVX2 inline void spreadQuad(__m256i v, int h, __m256i& even, __m256i& odd) {
    const int b = 4 * h;
    even = _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(b, b, b, b, b + 2, b + 2, b + 2, b + 2));
    odd = _mm256_permutevar8x32_epi32(v, _mm256_setr_epi32(b + 1, b + 1, b + 1, b + 1, b + 3, b + 3,
                                                           b + 3, b + 3));
}
[[gnu::always_inline]] RG_AVX2 inline void store8(int32_t* dst, __m256i v) {
    _mm256_store_si256(reinterpret_cast<__m256i*>(dst), v);
}
// One level's sums (levelSums8) of both quads: S − 2^23 (2D, cube) or R − 2^15 (1D).
template <Target kTarget, Addr kS, Addr kT>
[[gnu::always_inline]] RG_AVX2 inline void levelSumsPair(const LevelView& L, __m256 s, __m256 t,
                                                         __m256i face8, Lanes8 sum[2]) {
    constexpr bool kTwoD = kTarget != Target::OneD;
    const Axis8 ax = linearAxis8<kS>(s, L.width);
    const __m256i faceBase = kTarget == Target::Cube
                                 ? _mm256_mullo_epi32(face8, _mm256_set1_epi32(int32_t(L.faceStride)))
                                 : _mm256_setzero_si256();
    const int adj = _mm256_movemask_epi8(
        _mm256_cmpeq_epi32(ax.i1, _mm256_add_epi32(ax.i0, _mm256_set1_epi32(1))));
    const bool adjacent[2] = {(adj & 0xFFFF) == 0xFFFF, (uint32_t(adj) >> 16) == 0xFFFFu};
    alignas(32) int32_t i00[8], i01[8], i10[8], i11[8];
    if constexpr (kTwoD) {
        const Axis8 ay = linearAxis8<kT>(t, L.height);
        const __m256i wv = _mm256_set1_epi32(L.width);
        const __m256i row0 = _mm256_add_epi32(faceBase, _mm256_mullo_epi32(ay.i0, wv));
        const __m256i row1 = _mm256_add_epi32(faceBase, _mm256_mullo_epi32(ay.i1, wv));
        store8(i00, _mm256_add_epi32(row0, ax.i0));
        store8(i01, _mm256_add_epi32(row0, ax.i1));
        store8(i10, _mm256_add_epi32(row1, ax.i0));
        store8(i11, _mm256_add_epi32(row1, ax.i1));
        #pragma GCC unroll 2
        for (int h = 0; h < 2; ++h) {
            __m256i wxe, wxo, wye, wyo;
            spreadQuad(ax.w, h, wxe, wxo);
            spreadQuad(ay.w, h, wye, wyo);
            const Lanes8 r0 = rowPairs8(L.data, i00 + 4 * h, i01 + 4 * h, wxe, wxo, adjacent[h]);
            const Lanes8 r1 = rowPairs8(L.data, i10 + 4 * h, i11 + 4 * h, wxe, wxo, adjacent[h]);
            sum[h] = {
                _mm256_madd_epi16(interleaveHalves8(_mm256_packs_epi32(r0.even, r1.even)), wye),
                _mm256_madd_epi16(interleaveHalves8(_mm256_packs_epi32(r0.odd, r1.odd)), wyo)};
        }
    } else {
        (void)t;
        store8(i00, _mm256_add_epi32(faceBase, ax.i0));
        store8(i01, _mm256_add_epi32(faceBase, ax.i1));
        #pragma GCC unroll 2
        for (int h = 0; h < 2; ++h) {
            __m256i we, wo;
            spreadQuad(ax.w, h, we, wo);
            sum[h] = rowPairs8(L.data, i00 + 4 * h, i01 + 4 * h, we, wo, adjacent[h]);
        }
    }
}
// Both quads' texels for LINEAR choices `ch` of the same levels (the taps depend on the
// levels only; each quad's own frac blends them), as finishLanes8 leaves them; returns
// the fetches of both.
template <Target kTarget, Addr kS, Addr kT>
[[gnu::always_inline]] RG_AVX2 inline uint64_t gatherPair(const QuadSampler& qs, const LevelChoice ch[2],
                                                          const __m128 s[2], const __m128 t[2],
                                                          const __m128i face4[2], Lanes8 tex[2]) {
    constexpr bool kTwoD = kTarget != Target::OneD;
    const __m256 s8 = _mm256_set_m128(s[1], s[0]);
    const __m256 t8 = kTwoD ? _mm256_set_m128(t[1], t[0]) : _mm256_setzero_ps();
    const __m256i face8 =
        kTarget == Target::Cube ? _mm256_set_m128i(face4[1], face4[0]) : _mm256_setzero_si256();
    Lanes8 a[2];
    levelSumsPair<kTarget, kS, kT>(qs.level[size_t(ch[0].level0)], s8, t8, face8, a);
    if (ch[0].blend) {
        Lanes8 b[2];
        levelSumsPair<kTarget, kS, kT>(qs.level[size_t(ch[0].level1)], s8, t8, face8, b);
        #pragma GCC unroll 2
        for (int h = 0; h < 2; ++h) tex[h] = finishLanes8<kTwoD>(ch[h], a[h], &b[h]);
    } else {
        #pragma GCC unroll 2
        for (int h = 0; h < 2; ++h) tex[h] = finishLanes8<kTwoD>(ch[h], a[h], nullptr);
    }
    return 2 * uint64_t(kTwoD ? 4 : 2) * uint64_t(ch[0].blend ? 2 : 1) * 4;
}
// ---- 2D magnification: both quads' taps from one 4×3 texel block ------------------------
// Near magnification the eight pixels of a pair (four columns, two rows) touch a few
// neighbouring texels. When every pixel's taps lie in the 4 columns and 3 rows from the
// smallest first taps (columns c..c+3, rows r..r+2: i0 − c ≤ 2 and j0 − r ≤ 1 for every
// pixel, with no wrap or clamp between a pixel's two taps on either axis, and the block
// inside the level), the 16 texels per row pair come from two 8-texel registers (rows
// r | r + 1 and r + 1 | r + 2, four texels each) by vpermd instead of 32 scalar loads:
// the same texels as the tap indices address, so the same sums.

// The smallest of eight int32 lanes, in every lane.
[[gnu::always_inline]] RG_AVX2 inline __m256i minLanes8(__m256i v) {
    __m256i m = _mm256_min_epi32(v, _mm256_permute2x128_si256(v, v, 1));
    m = _mm256_min_epi32(m, _mm256_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    return _mm256_min_epi32(m, _mm256_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1)));
}
// Σ wx·(t − 128) per channel of one row of taps a, b (pixel k in lane k), pixels
// (k | k + 4) in rows[k]; wx[k] their weight pairs.
[[gnu::always_inline]] RG_AVX2 inline void blockRowSums(__m256i a, __m256i b, const __m256i wx[4],
                                                        __m256i rows[4]) {
    const __m256i zero = _mm256_setzero_si256(), k128 = splat32<0x00800080u>();  // 128 per int16
    const __m256i x = _mm256_unpacklo_epi8(a, b), y = _mm256_unpackhi_epi8(a, b);
    const __m256i px[4] = {_mm256_unpacklo_epi8(x, zero), _mm256_unpackhi_epi8(x, zero),
                           _mm256_unpacklo_epi8(y, zero), _mm256_unpackhi_epi8(y, zero)};
    #pragma GCC unroll 4
    for (int k = 0; k < 4; ++k) rows[k] = _mm256_madd_epi16(_mm256_sub_epi16(px[k], k128), wx[k]);
}
// quad::mulDiv255Half on 16 int16 lanes.
[[gnu::always_inline]] RG_AVX2 inline __m256i mulDiv255x16(__m256i a, __m256i b) {
    const __m256i t = _mm256_add_epi16(_mm256_mullo_epi16(a, b), splat32<0x00800080u>());
    return _mm256_srli_epi16(_mm256_add_epi16(t, _mm256_srli_epi16(t, 8)), 8);
}
// The block's first texel on an axis of extent n whose unaddressed first taps start at b
// (the smallest over the pixels), when the block's `span` texels b..b + span − 1 address
// to consecutive texels (no wrap or clamp inside it): then every pixel's taps are its
// unaddressed ones shifted by the same amount. −1 otherwise.
template <Addr kA>
[[gnu::always_inline]] inline int32_t blockStart(int32_t b, int32_t n, int32_t span) {
    if constexpr (kA == Addr::Edge) {
        return b >= 0 && b <= n - span ? b : -1;  // clamp is the identity on [0, n − 1]
    } else {
        const int32_t a = b & (n - 1);  // address4's mask, also for a negative b
        return a <= n - span ? a : -1;  // no carry into bit log2(n) up to b + span − 1
    }
}
// GL MODULATE (mulDiv255 per channel) of both quads' bilinearBlockPair results w01, w23 by
// CURRENT's bytes `cur` (quad 0 | quad 1), packed to bytes: quad 0 | quad 1.
[[gnu::always_inline]] RG_AVX2 inline __m256i modulateBlockPair(__m256i w01, __m256i w23, __m256i cur) {
    const __m256i z = _mm256_setzero_si256();
    return _mm256_packus_epi16(mulDiv255x16(w01, _mm256_unpacklo_epi8(cur, z)),
                               mulDiv255x16(w23, _mm256_unpackhi_epi8(cur, z)));
}
// The bilinear results of the eight pixels (quad h in lanes 4h..4h+3) on level L as int16
// channel values, w01 = (quad 0 pixels 0, 1 | quad 1 pixels 0, 1) and w23 the same of
// pixels 2, 3 — or false when the taps do not fit the block (nothing written).
// The arithmetic is bilinear8's (rowPairs8 and its column pass) with the pixels arranged
// by position instead of even/odd: the same biased pmaddwd sums, the same rounding.
template <Addr kS, Addr kT>
[[gnu::always_inline]] RG_AVX2 inline bool bilinearBlockPair(const LevelView& L, __m256 s8, __m256 t8,
                                                             __m256i& w01, __m256i& w23) {
    // linearAxis8's floors and weights; the taps are addressed once, for the block: tap
    // i0 of a pixel is address(b), i1 address(b + 1), and with b − bmin in [0, 2] both lie
    // in the block's 4 columns (rows: b − bmin in [0, 1], 3 rows).
    const RawAxis8 ax = rawAxis8(s8, L.width);
    const RawAxis8 ay = rawAxis8(t8, L.height);
    const __m256i one = splat32<1>(), two = splat32<2>();
    // The block's origin: pixel 0's floors (the smallest when the coordinates grow to the
    // right and down, the common case: no reduction), else the smallest over the pixels.
    // Any origin from which every pixel's offsets fit gives the same taps.
    __m256i col0 = _mm256_broadcastd_epi32(_mm256_castsi256_si128(ax.b));
    __m256i row0 = _mm256_broadcastd_epi32(_mm256_castsi256_si128(ay.b));
    __m256i dcol = _mm256_sub_epi32(ax.b, col0), drow = _mm256_sub_epi32(ay.b, row0);
    // Offsets in [0, 2] and [0, 1]: unsigned, a negative one is above the bound.
    const __m256i fits = _mm256_and_si256(_mm256_cmpeq_epi32(_mm256_max_epu32(dcol, two), two),
                                          _mm256_cmpeq_epi32(_mm256_max_epu32(drow, one), one));
    if (_mm256_movemask_epi8(fits) != -1) {
        col0 = minLanes8(ax.b);
        row0 = minLanes8(ay.b);
        dcol = _mm256_sub_epi32(ax.b, col0);
        drow = _mm256_sub_epi32(ay.b, row0);
        const __m256i bad = _mm256_or_si256(_mm256_cmpgt_epi32(dcol, two),
                                            _mm256_cmpgt_epi32(drow, one));
        if (!_mm256_testz_si256(bad, bad)) return false;
    }
    const int32_t c = blockStart<kS>(_mm256_cvtsi256_si32(col0), L.width, 4);
    const int32_t r = blockStart<kT>(_mm256_cvtsi256_si32(row0), L.height, 3);
    if (c < 0 || r < 0) return false;
    const Rgba8* row = L.data + (size_t(r) * size_t(L.width) + size_t(c));
    auto load4texels = [](const Rgba8* q) __attribute__((always_inline)) {
        return _mm_loadu_si128(reinterpret_cast<const __m128i*>(q));
    };
    const __m128i mid = load4texels(row + L.width);
    const __m256i block01 = _mm256_set_m128i(mid, load4texels(row));
    const __m256i block12 = _mm256_set_m128i(load4texels(row + 2 * L.width), mid);
    const __m256i idx = _mm256_add_epi32(_mm256_slli_epi32(drow, 2), dcol);
    const __m256i idx1 = _mm256_add_epi32(idx, one);
    // Per pixel k (lane k): t00, t01 on row j0, t10, t11 on row j0 + 1.
    const __m256i t00 = _mm256_permutevar8x32_epi32(block01, idx),
                  t01 = _mm256_permutevar8x32_epi32(block01, idx1),
                  t10 = _mm256_permutevar8x32_epi32(block12, idx),
                  t11 = _mm256_permutevar8x32_epi32(block12, idx1);
    // Weight pairs of pixel k (and k + 4) over its half: wx, wy (pixels 0–3 and 4–7 are
    // the two 128-bit halves, so an in-lane shuffle).
    const __m256i wx[4] = {_mm256_shuffle_epi32(ax.w, 0x00), _mm256_shuffle_epi32(ax.w, 0x55),
                           _mm256_shuffle_epi32(ax.w, 0xAA), _mm256_shuffle_epi32(ax.w, 0xFF)};
    const __m256i wy[4] = {_mm256_shuffle_epi32(ay.w, 0x00), _mm256_shuffle_epi32(ay.w, 0x55),
                           _mm256_shuffle_epi32(ay.w, 0xAA), _mm256_shuffle_epi32(ay.w, 0xFF)};
    __m256i r0[4], r1[4], f[4];
    blockRowSums(t00, t01, wx, r0);
    blockRowSums(t10, t11, wx, r1);
    const __m256i round = splat32<(1u << 23) + (1u << 15)>();
    #pragma GCC unroll 4
    for (int k = 0; k < 4; ++k) {
        const __m256i sum =
            _mm256_madd_epi16(interleaveHalves8(_mm256_packs_epi32(r0[k], r1[k])), wy[k]);
        f[k] = _mm256_srai_epi32(_mm256_add_epi32(sum, round), 16);
    }
    w01 = _mm256_packs_epi32(f[0], f[1]);
    w23 = _mm256_packs_epi32(f[2], f[3]);
    return true;
}

// select on eight lanes: mask ? a : b.
[[gnu::always_inline]] RG_AVX2 inline __m256 sel(__m256 m, __m256 a, __m256 b) {
    return _mm256_or_ps(_mm256_and_ps(m, a), _mm256_andnot_ps(m, b));
}
// projectLanes' cube-face selection for the eight pixels of a pair (quad h in lanes
// 4h..4h+3): the same comparisons (ordered, false on NaN), selections, division, add and
// multiply lane for lane, so the same s, t and faces.
[[gnu::always_inline]] RG_AVX2 inline void selectCube8(__m256 x, __m256 y, __m256 z, __m256& s,
                                                       __m256& t, __m256i& face8) {
    const __m256 absMask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m256 signBit = _mm256_set1_ps(-0.0f);
    const __m256 ax = _mm256_and_ps(x, absMask), ay = _mm256_and_ps(y, absMask),
                 az = _mm256_and_ps(z, absMask);
    const __m256 zero = _mm256_setzero_ps();
    const __m256 isX = _mm256_and_ps(_mm256_cmp_ps(ax, ay, _CMP_GE_OS), _mm256_cmp_ps(ax, az, _CMP_GE_OS));
    const __m256 isY = _mm256_andnot_ps(isX, _mm256_cmp_ps(ay, az, _CMP_GE_OS));
    const __m256 isZ =
        _mm256_andnot_ps(_mm256_or_ps(isX, isY), _mm256_castsi256_ps(_mm256_set1_epi32(-1)));
    const __m256 px = _mm256_cmp_ps(x, zero, _CMP_GE_OS), py = _mm256_cmp_ps(y, zero, _CMP_GE_OS),
                 pz = _mm256_cmp_ps(z, zero, _CMP_GE_OS);
    const __m256 nx = _mm256_xor_ps(x, signBit), ny = _mm256_xor_ps(y, signBit),
                 nz = _mm256_xor_ps(z, signBit);
    const __m256 sc = sel(isX, sel(px, nz, z), sel(isY, x, sel(pz, x, nx)));
    const __m256 tc = sel(isY, sel(py, z, nz), ny);
    const __m256 ma = sel(isX, x, sel(isY, y, z));
    const __m256 a = _mm256_and_ps(ma, absMask);
    const __m256 ok = _mm256_cmp_ps(a, zero, _CMP_GT_OS);
    const __m256 one = _mm256_set1_ps(1.0f), half = _mm256_set1_ps(0.5f);
    s = sel(ok, _mm256_mul_ps(_mm256_add_ps(_mm256_div_ps(sc, a), one), half), half);
    t = sel(ok, _mm256_mul_ps(_mm256_add_ps(_mm256_div_ps(tc, a), one), half), half);
    const __m256i fi =
        _mm256_or_si256(_mm256_and_si256(_mm256_castps_si256(isY), _mm256_set1_epi32(2)),
                        _mm256_and_si256(_mm256_castps_si256(isZ), _mm256_set1_epi32(4)));
    const __m256 pos = sel(isX, px, sel(isY, py, pz));
    face8 = _mm256_add_epi32(fi, _mm256_andnot_si256(_mm256_castps_si256(pos), _mm256_set1_epi32(1)));
}

// cascadeStageOfPair for both quads (both covered) of a pair.
template <Target kT, Addr kS, Addr kU, bool kTexCur>
[[gnu::always_inline]] RG_AVX2 inline uint64_t cascadeStageOfBoth(const CompiledStages& c, int i,
                                                                  const FragmentQuadPair& p,
                                                                  quad::Regs r[2]) {
    const QuadSampler& qs = c.stage[size_t(i)];
    const StageState& st = c.state[size_t(i)];
    const float(&tc)[4][8] = p.texCoord[st.texCoordIndex];
    __m128 s[2], t[2];
    int face[2][4];
    __m128i face4[2];
    LevelChoice ch[2];
    if constexpr (kT == Target::Cube) {
        // Both quads' face selection in one pass (selectCube8), then each quad's λ.
        const __m256 x8 = _mm256_load_ps(tc[0]), y8 = _mm256_load_ps(tc[1]),
                     z8 = _mm256_load_ps(tc[2]);
        __m256 s8, t8;
        __m256i face8;
        selectCube8(x8, y8, z8, s8, t8, face8);
        s[0] = _mm256_castps256_ps128(s8);
        s[1] = _mm256_extractf128_ps(s8, 1);
        t[0] = _mm256_castps256_ps128(t8);
        t[1] = _mm256_extractf128_ps(t8, 1);
        face4[0] = _mm256_castsi256_si128(face8);
        face4[1] = _mm256_extracti128_si256(face8, 1);
        #pragma GCC unroll 2
        for (int h = 0; h < 2; ++h) {
            if (qs.constantChoice) {
                ch[h] = qs.choice;
                continue;
            }
            _mm_storeu_si128(reinterpret_cast<__m128i*>(face[h]), face4[h]);
            ch[h] = cubeChoice(qs, _mm_load_ps(&tc[0][4 * h]), _mm_load_ps(&tc[1][4 * h]),
                               _mm_load_ps(&tc[2][4 * h]), s[h], t[h], face[h]);
        }
    } else {
        #pragma GCC unroll 2
        for (int h = 0; h < 2; ++h)
            ch[h] = projectLanes<kT>(qs, _mm_load_ps(&tc[0][4 * h]), _mm_load_ps(&tc[1][4 * h]),
                                     _mm_load_ps(&tc[2][4 * h]), _mm_load_ps(&tc[3][4 * h]),
                                     s[h], t[h], face[h], face4[h]);
    }
    uint64_t n = 0;
    __m128i tex[2];
    const bool sameLinear = ch[0].filter == FilterMode::Linear &&
                            ch[1].filter == FilterMode::Linear && ch[0].level0 == ch[1].level0 &&
                            ch[0].level1 == ch[1].level1 && ch[0].blend == ch[1].blend;
    bool fromBlock = false;  // tex[] already holds both quads' texels from the 4×3 block
    if constexpr (kT == Target::TwoD) {
        __m256i w01, w23;
        if (sameLinear && !ch[0].blend &&
            bilinearBlockPair<kS, kU>(qs.level[size_t(ch[0].level0)], _mm256_set_m128(s[1], s[0]),
                                      _mm256_set_m128(t[1], t[0]), w01, w23)) {
            n = 2 * 4 * 4;
            if constexpr (kTexCur) {
                // mulDiv255(texel, CURRENT) as below, CURRENT's bytes widened to the
                // same (pixels 0, 1 | 2, 3 per quad) arrangement; the pack gives quad 0 | 1.
                const __m256i both = modulateBlockPair(
                    w01, w23, _mm256_set_m128i(r[1][arg::Current], r[0][arg::Current]));
                r[0][arg::Current] = _mm256_castsi256_si128(both);
                r[1][arg::Current] = _mm256_extracti128_si256(both, 1);
                return n;
            }
            const __m256i both = _mm256_packus_epi16(w01, w23);
            tex[0] = _mm256_castsi256_si128(both);
            tex[1] = _mm256_extracti128_si256(both, 1);
            fromBlock = true;
        }
    }
    if (fromBlock) {
    } else if (sameLinear) {
        Lanes8 lanes[2];
        n = gatherPair<kT, kS, kU>(qs, ch, s, t, face4, lanes);
        if constexpr (kTexCur) {
            // mulDiv255(texel, CURRENT) of both quads in one register, on the int16 texel
            // values before they are packed to bytes: (p0 p1 | p2 p3) per quad, the layout
            // vpmovzxbw gives CURRENT's bytes. The same per-channel arithmetic as
            // quad::mulDiv255 (exact in 16 bits: a·b + 128 + (… >> 8) < 2^16), then one
            // pack of both quads.
            __m256i m[2];
            #pragma GCC unroll 2
            for (int h = 0; h < 2; ++h) {
                m[h] = mulDiv255x16(_mm256_packs_epi32(lanes[h].even, lanes[h].odd),
                                    _mm256_cvtepu8_epi16(r[h][arg::Current]));
            }
            // (q0 p0 p1, q1 p0 p1 | q0 p2 p3, q1 p2 p3) → (quad 0 | quad 1).
            const __m256i both = _mm256_permute4x64_epi64(_mm256_packus_epi16(m[0], m[1]),
                                                          _MM_SHUFFLE(3, 1, 2, 0));
            r[0][arg::Current] = _mm256_castsi256_si128(both);
            r[1][arg::Current] = _mm256_extracti128_si256(both, 1);
            return n;
        }
        tex[0] = packQuad8(lanes[0]);
        tex[1] = packQuad8(lanes[1]);
    } else {
        #pragma GCC unroll 2
        for (int h = 0; h < 2; ++h) {
            QuadFootprint fp;
            n += prepareLevelsAvx2<kT, kS, kU>(qs, ch[h], s[h], t[h], face4[h], fp);
            tex[h] = gatherQuadAvx2<kT != Target::OneD>(qs, fp);
        }
    }
    #pragma GCC unroll 2
    for (int h = 0; h < 2; ++h) {
        r[h][arg::Texture] = tex[h];
        if constexpr (kTexCur)
            r[h][arg::Current] = quad::mulDiv255(r[h][arg::Texture], r[h][arg::Current]);
        else
            r[h][arg::Current] = quad::evaluate<TextureOp::Modulate, TextureOp::Modulate>(st, r[h]);
    }
    return n;
}
// ---- whole cascades of a FragmentQuadPair ------------------------------------------------
// cascadeStage for quad h of the pair: its coordinates read as the four component rows
// projectQuad would transpose them into (lanes 4h..4h+3), the rest the same code.
template <Target kT, Addr kS, Addr kU, bool kTexCur>
[[gnu::always_inline]] RG_AVX2 inline uint64_t cascadeStageOfPair(const CompiledStages& c,
                                                                  int i,
                                                                  const FragmentQuadPair& p,
                                                                  int h, quad::Regs& r) {
    const QuadSampler& qs = c.stage[size_t(i)];
    const StageState& st = c.state[size_t(i)];
    const float(&tc)[4][8] = p.texCoord[st.texCoordIndex];
    __m128 s, t;
    int face[4];
    __m128i face4;
    const LevelChoice ch =
        projectLanes<kT>(qs, _mm_load_ps(&tc[0][4 * h]), _mm_load_ps(&tc[1][4 * h]),
                         _mm_load_ps(&tc[2][4 * h]), _mm_load_ps(&tc[3][4 * h]), s, t, face,
                         face4);
    QuadFootprint fp;
    const uint64_t n = prepareLevelsAvx2<kT, kS, kU>(qs, ch, s, t, face4, fp);
    r[arg::Texture] = gatherQuadAvx2<kT != Target::OneD>(qs, fp);
    if constexpr (kTexCur)
        r[arg::Current] = quad::mulDiv255(r[arg::Texture], r[arg::Current]);
    else
        r[arg::Current] = quad::evaluate<TextureOp::Modulate, TextureOp::Modulate>(st, r);
    return n;
}
template <bool kTexCur>
[[gnu::always_inline]] inline quad::Regs cascadeInputsOfPair(const FragmentQuadPair& p, int h,
                                                             __m128i tfactor) {
    quad::Regs r;
    r[arg::Diffuse] = _mm_load_si128(reinterpret_cast<const __m128i*>(p.diffuse.data() + 4 * h));
    r[arg::Current] = r[arg::Diffuse];
    if constexpr (!kTexCur) {
        r[arg::Specular] =
            _mm_load_si128(reinterpret_cast<const __m128i*>(p.specular.data() + 4 * h));
        r[arg::TFactor] = tfactor;
    }
    return r;
}
// Both quads in one body (no call or counter update between them), so the out-of-order
// core overlaps the second quad's chain with the first's.
// kAlpha0 and kTail as cascadeOne's.
template <Target kT, Addr kS, Addr kU, bool kTexCur,
          TextureOp kAlpha0 = TextureOp::Modulate, bool kTail = false>
RG_AVX2 uint64_t cascadePairOne(const CompiledStages& c, const FragmentQuadPair& p,
                                __m128i tfactor, Rgba8* out) {
    static_assert(kTexCur || (kAlpha0 == TextureOp::Modulate && !kTail));
    if (p.coverage[0] && p.coverage[1]) {
        quad::Regs r[2] = {cascadeInputsOfPair<kTexCur>(p, 0, tfactor),
                           cascadeInputsOfPair<kTexCur>(p, 1, tfactor)};
        stage0AlphaIn<kAlpha0>(r[0]);
        stage0AlphaIn<kAlpha0>(r[1]);
        const uint64_t n = cascadeStageOfBoth<kT, kS, kU, kTexCur>(c, 0, p, r);
        if constexpr (kTail) {
            // tfactorTail of both quads in one register: quad::mulDiv255's arithmetic on
            // 16 int16 lanes (mulDiv255x16); unpacks and pack keep each quad in its half.
            const __m256i z = _mm256_setzero_si256();
            const __m256i both = _mm256_set_m128i(r[1][arg::Current], r[0][arg::Current]);
            const __m256i f = _mm256_cvtepu8_epi16(_mm_or_si128(
                tfactor, _mm_set1_epi32(int32_t(kAlphaByte))));  // 2 pixels a half
            _mm256_storeu_si256(
                reinterpret_cast<__m256i*>(out),
                _mm256_packus_epi16(mulDiv255x16(_mm256_unpacklo_epi8(both, z), f),
                                    mulDiv255x16(_mm256_unpackhi_epi8(both, z), f)));
            return n;
        }
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out), r[0][arg::Current]);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 4), r[1][arg::Current]);
        return n;
    }
    uint64_t n = 0;
    for (int h = 0; h < 2; ++h) {
        __m128i* dst = reinterpret_cast<__m128i*>(out + 4 * h);
        if (!p.coverage[size_t(h)]) {
            _mm_storeu_si128(dst, _mm_setzero_si128());
            continue;
        }
        quad::Regs r = cascadeInputsOfPair<kTexCur>(p, h, tfactor);
        stage0AlphaIn<kAlpha0>(r);
        n += cascadeStageOfPair<kT, kS, kU, kTexCur>(c, 0, p, h, r);
        _mm_storeu_si128(dst, tfactorTail<kTail>(r[arg::Current], tfactor));
    }
    return n;
}
template <Target kT0, Addr kS0, Addr kU0, Target kT1, Addr kS1, Addr kU1, bool kTexCur>
RG_AVX2 uint64_t cascadePairTwo(const CompiledStages& c, const FragmentQuadPair& p,
                                __m128i tfactor, Rgba8* out) {
    if (p.coverage[0] && p.coverage[1]) {
        quad::Regs r[2] = {cascadeInputsOfPair<kTexCur>(p, 0, tfactor),
                           cascadeInputsOfPair<kTexCur>(p, 1, tfactor)};
        uint64_t n = cascadeStageOfBoth<kT0, kS0, kU0, kTexCur>(c, 0, p, r);
        n += cascadeStageOfBoth<kT1, kS1, kU1, kTexCur>(c, 1, p, r);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out), r[0][arg::Current]);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 4), r[1][arg::Current]);
        return n;
    }
    uint64_t n = 0;
    for (int h = 0; h < 2; ++h) {
        __m128i* dst = reinterpret_cast<__m128i*>(out + 4 * h);
        if (!p.coverage[size_t(h)]) {
            _mm_storeu_si128(dst, _mm_setzero_si128());
            continue;
        }
        quad::Regs r = cascadeInputsOfPair<kTexCur>(p, h, tfactor);
        n += cascadeStageOfPair<kT0, kS0, kU0, kTexCur>(c, 0, p, h, r);
        n += cascadeStageOfPair<kT1, kS1, kU1, kTexCur>(c, 1, p, h, r);
        _mm_storeu_si128(dst, r[arg::Current]);
    }
    return n;
}

// cascadePairOne for GL MODULATE over a 2D texture whose level choice is constant and
// bilinear on one level (a magnified texture without mipmaps: tex_bilinear_2d), both quads
// covered and their taps inside one block (bilinearBlockPair): a short body without the
// general pair path's branches and stack traffic. Anything else goes to cascadePairOne.
// The coordinates: projectLanes' divide by q when some pixel has q ≠ 1, done here on all
// eight lanes when one of them has — x/1 is x, so the quad whose q are all 1 gets the
// same values as projectLanes gives it.
template <Addr kS, Addr kU>
RG_AVX2 uint64_t cascadePairBlock2D(const CompiledStages& c, const FragmentQuadPair& p,
                                    __m128i tfactor, Rgba8* out) {
    const QuadSampler& qs = c.stage[0];
    if (p.coverage[0] && p.coverage[1]) {
        const float(&tc)[4][8] = p.texCoord[c.state[0].texCoordIndex];
        __m256 x = _mm256_load_ps(tc[0]), y = _mm256_load_ps(tc[1]);
        if (qs.projected) {
            const __m256 w = _mm256_load_ps(tc[3]);
            if (_mm256_movemask_ps(_mm256_cmp_ps(w, _mm256_set1_ps(1.0f), _CMP_NEQ_UQ)) != 0) {
                x = _mm256_div_ps(x, w);
                y = _mm256_div_ps(y, w);
            }
        }
        __m256i w01, w23;
        if (bilinearBlockPair<kS, kU>(qs.level[size_t(qs.choice.level0)], x, y, w01, w23)) {
            // GL MODULATE of both quads as in cascadeStageOfBoth; CURRENT is DIFFUSE.
            const __m256i both = modulateBlockPair(
                w01, w23, _mm256_load_si256(reinterpret_cast<const __m256i*>(p.diffuse.data())));
            _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), both);
            return 2 * 4 * 4;
        }
    }
    return cascadePairOne<Target::TwoD, kS, kU, true>(c, p, tfactor, out);
}

// True when every one of the `active` stages is MODULATE(TEXTURE, CURRENT) for colour and
// alpha with no scale (cascadeStage's kTexCur).
bool texCurOnly(const CompiledStages& c, int active) {
    for (int i = 0; i < active; ++i) {
        const StageState& st = c.state[size_t(i)];
        if (st.colorArg1 != arg::Texture || st.colorArg2 != arg::Current ||
            st.alphaArg1 != arg::Texture || st.alphaArg2 != arg::Current ||
            st.colorScaleShift != 0 || st.alphaScaleShift != 0)
            return false;
    }
    return true;
}

// The hybrid layer pass's stages (compileCascade): stage 0 colour MODULATE(TEXTURE,
// DIFFUSE or CURRENT, the same at stage 0), alpha SELECTARG1(TEXTURE), no scale...
bool texelAlphaStage(const StageState& st) {
    return st.colorOp == TextureOp::Modulate && st.alphaOp == TextureOp::SelectArg1 &&
           st.colorArg1 == arg::Texture &&
           (st.colorArg2 == arg::Diffuse || st.colorArg2 == arg::Current) &&
           st.alphaArg1 == arg::Texture && st.colorScaleShift == 0 &&
           st.alphaScaleShift == 0;
}
// ... and a stage 1 that samples nothing: colour MODULATE(CURRENT, TFACTOR) in either
// order, alpha SELECTARG1(CURRENT), no scale (a sample's weight when two are summed).
bool tfactorTailStage(const StageState& st) {
    return st.colorOp == TextureOp::Modulate && st.alphaOp == TextureOp::SelectArg1 &&
           ((st.colorArg1 == arg::Current && st.colorArg2 == arg::TFactor) ||
            (st.colorArg1 == arg::TFactor && st.colorArg2 == arg::Current)) &&
           st.alphaArg1 == arg::Current && st.colorScaleShift == 0 &&
           st.alphaScaleShift == 0;
}

bool specialisable(AddressMode m, int n) {
    return m == AddressMode::ClampToEdge ||
           (m == AddressMode::Wrap && (n & (n - 1)) == 0);
}
Addr addrOf(AddressMode m) {
    return m == AddressMode::ClampToEdge ? Addr::Edge : Addr::Pow2;
}

template <Target kTarget, Addr kS, Addr kT>
void setKernels(QuadSampler& q) {
    if (haveAvx2() && avx2Allowed.load(std::memory_order_relaxed)) {
        q.prepare = &prepareKernelAvx2<kTarget, kS, kT>;
        q.fn = &sampleQuadKernelAvx2<kTarget, kS, kT>;
        q.gather = &gatherKernelAvx2<kTarget != Target::OneD>;
    } else {
        q.prepare = &prepareKernel<kTarget, kS, kT>;
        q.fn = &sampleQuadKernel<kTarget, kS, kT>;
        q.gather = &gatherKernel<kTarget != Target::OneD>;
    }
}
template <Target kTarget>
void pick(QuadSampler& q, Addr s, Addr t) {
    if (s == Addr::Edge) {
        if (t == Addr::Edge)
            setKernels<kTarget, Addr::Edge, Addr::Edge>(q);
        else
            setKernels<kTarget, Addr::Edge, Addr::Pow2>(q);
    } else {
        if (t == Addr::Edge)
            setKernels<kTarget, Addr::Pow2, Addr::Edge>(q);
        else
            setKernels<kTarget, Addr::Pow2, Addr::Pow2>(q);
    }
}

}  // namespace

// Formats whose every texel has alpha 255 (OpenGL 1.2 table 3.15: L → (L, L, L, 1), RGB →
// (R, G, B, 1)); filtering 255s gives 255, and the compiled samplers have no border colour.
bool opaqueFormat(TexelFormat f) {
    return f == TexelFormat::L8 || f == TexelFormat::RGB8 || f == TexelFormat::RGB565;
}

void compileCascade(CompiledStages& c, int active, uint32_t sampling) {
    c.cascade = nullptr;
    c.cascadePair = nullptr;
    if (active < 1 || active > 2 || c.sharesFootprint != 0) return;
    // The hybrid layer passes: a cube map's texel times DIFFUSE with the texel's alpha,
    // optionally times TFACTOR (cascadeOne's kAlpha0 = SelectArg1 and kTail). Stage 0's
    // CURRENT is DIFFUSE, so the stage is the kTexCur form's mulDiv255(texel, CURRENT).
    if ((sampling & 1u) && texelAlphaStage(c.state[0]) &&
        c.stage[0].fn == &sampleQuadKernelAvx2<Target::Cube, Addr::Edge, Addr::Edge> &&
        (active == 1 || (!(sampling & 2u) && tfactorTailStage(c.state[1])))) {
        constexpr Target kC = Target::Cube;
        constexpr Addr kE = Addr::Edge;
        constexpr TextureOp kSel = TextureOp::SelectArg1;
        if (active == 1) {
            c.cascade = &cascadeOne<kC, kE, kE, true, kSel, false>;
            c.cascadePair = &cascadePairOne<kC, kE, kE, true, kSel, false>;
        } else {
            c.cascade = &cascadeOne<kC, kE, kE, true, kSel, true>;
            c.cascadePair = &cascadePairOne<kC, kE, kE, true, kSel, true>;
        }
        return;
    }
    // GL MODULATE of a texture without alpha (texEnvStage(Modulate, RGB or L)) keeps the
    // fragment's alpha: colour MODULATE, alpha SELECTARG1 of CURRENT. Its texels' alpha is
    // 255, and mulDiv255(255, a) = a for every byte a ((255a + 128 + ((255a + 128) >> 8))
    // >> 8 = a), so the stage is MODULATE of both, which the cascades below run: the same
    // bytes through the whole-quad kernels instead of the generic stage loop.
    decltype(c.state) state = c.state;
    for (int i = 0; i < active; ++i) {
        StageState& st = state[size_t(i)];
        const QuadSampler& q = c.stage[size_t(i)];
        if ((sampling & (1u << i)) && q.fn && q.texture && opaqueFormat(q.texture->desc().format) &&
            quad::StageKernel(c.stageKernel[size_t(i)]) == quad::StageKernel::ModulateSelect1 &&
            st.colorOp == TextureOp::Modulate && st.alphaOp == TextureOp::SelectArg1 &&
            st.alphaArg1 == arg::Current && st.alphaScaleShift == 0) {
            st.alphaOp = TextureOp::Modulate;
            st.alphaArg1 = arg::Texture;
            st.alphaArg2 = arg::Current;
        }
    }
    for (int i = 0; i < active; ++i) {
        const StageState& st = state[size_t(i)];
        if (!(sampling & (1u << i)) || !c.stage[size_t(i)].fn ||
            quad::stageKernel(st) != quad::StageKernel::ModulateModulate ||
            st.colorOp != TextureOp::Modulate || st.alphaOp != TextureOp::Modulate)
            return;
    }
    c.state = state;
    const QuadSampleFn f0 = c.stage[0].fn;
    const bool texCur = texCurOnly(c, active);
    auto one = [&]<Target kT, Addr kS, Addr kU>() {
        c.cascade = texCur ? &cascadeOne<kT, kS, kU, true> : &cascadeOne<kT, kS, kU, false>;
        c.cascadePair =
            texCur ? &cascadePairOne<kT, kS, kU, true> : &cascadePairOne<kT, kS, kU, false>;
    };
    if (active == 1) {
        // A magnified single-level 2D texture under GL MODULATE: cascadePairBlock2D.
        const QuadSampler& q0 = c.stage[0];
        const bool block = texCur && q0.constantChoice && q0.choice.filter == FilterMode::Linear &&
                           !q0.choice.blend;
        if (f0 == &sampleQuadKernelAvx2<Target::TwoD, Addr::Pow2, Addr::Pow2>) {
            one.template operator()<Target::TwoD, Addr::Pow2, Addr::Pow2>();
            if (block) c.cascadePair = &cascadePairBlock2D<Addr::Pow2, Addr::Pow2>;
        } else if (f0 == &sampleQuadKernelAvx2<Target::TwoD, Addr::Edge, Addr::Edge>) {
            one.template operator()<Target::TwoD, Addr::Edge, Addr::Edge>();
            if (block) c.cascadePair = &cascadePairBlock2D<Addr::Edge, Addr::Edge>;
        } else if (f0 == &sampleQuadKernelAvx2<Target::Cube, Addr::Edge, Addr::Edge>) {
            one.template operator()<Target::Cube, Addr::Edge, Addr::Edge>();
        }
        return;
    }
    if (f0 == &sampleQuadKernelAvx2<Target::Cube, Addr::Edge, Addr::Edge> &&
        c.stage[1].fn == &sampleQuadKernelAvx2<Target::OneD, Addr::Edge, Addr::Edge>) {
        c.cascade = texCur ? &cascadeTwo<Target::Cube, Addr::Edge, Addr::Edge, Target::OneD,
                                         Addr::Edge, Addr::Edge, true>
                           : &cascadeTwo<Target::Cube, Addr::Edge, Addr::Edge, Target::OneD,
                                         Addr::Edge, Addr::Edge, false>;
        c.cascadePair = texCur ? &cascadePairTwo<Target::Cube, Addr::Edge, Addr::Edge,
                                                 Target::OneD, Addr::Edge, Addr::Edge, true>
                               : &cascadePairTwo<Target::Cube, Addr::Edge, Addr::Edge,
                                                 Target::OneD, Addr::Edge, Addr::Edge, false>;
    }
}

bool sameFootprint(const QuadSampler& a, const QuadSampler& b) {
    if (!a.fn || a.prepare != b.prepare || a.projected != b.projected ||
        a.lodBias != b.lodBias || a.constantChoice != b.constantChoice ||
        a.lodMin != b.lodMin || a.lodMax != b.lodMax || a.baseSize != b.baseSize ||
        a.levels.base != b.levels.base || a.levels.q != b.levels.q ||
        a.levels.c != b.levels.c || a.levels.mag != b.levels.mag ||
        a.levels.min != b.levels.min || a.levels.mip != b.levels.mip ||
        a.texture->levels() != b.texture->levels())
        return false;
    for (int l = 0; l < a.texture->levels(); ++l) {
        const LevelView &x = a.level[size_t(l)], &y = b.level[size_t(l)];
        if (x.width != y.width || x.height != y.height || x.faceStride != y.faceStride)
            return false;
    }
    return true;
}

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
    q.baseSizeF[0] = float(q.baseSize[0]);
    q.baseSizeF[1] = float(q.baseSize[1]);
    q.levels = levelParams(t.levels(), s);
    // With one filter both ways (then c = 0), every λ chooses the same {filter, base,
    // base, 0, no blend} when there are no mipmaps, or when the chain cannot leave level
    // base (q = base: one level, or base/max level pinning it). chooseLevelsInline: λ ≤ 0
    // gives {mag, base}; λ > 0 with MipMode::None {min, base}; NEAREST d = base +
    // ⌈λ + ½⌉ − 1 ≥ base, min(d, q) = base; LINEAR λ ≥ (q − base)·256 = 0, so {min, q = base}.
    q.constantChoice = s.magFilter == s.minFilter &&
                       (s.mipFilter == MipMode::None || q.levels.q == q.levels.base);
    q.choice = chooseLevelsInline(q.levels, 0);
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
            setKernels<Target::Cube, Addr::Edge, Addr::Edge>(q);
            break;
        case TextureTarget::Texture2D:
            if (specialisable(s.address[0], w) && specialisable(s.address[1], h))
                pick<Target::TwoD>(q, addrOf(s.address[0]), addrOf(s.address[1]));
            break;
        case TextureTarget::Texture1D:
            if (specialisable(s.address[0], w))
                pick<Target::OneD>(q, addrOf(s.address[0]), Addr::Edge);
            break;
        default:
            break;
    }
    return q;
}

}  // namespace rg::tex::detail

namespace rg::tex {
void allowAvx2Kernels(bool allowed) {
    detail::avx2Allowed.store(allowed, std::memory_order_relaxed);
}
}  // namespace rg::tex
