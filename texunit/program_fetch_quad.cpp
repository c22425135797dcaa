// The implicit-λ fetch of an 8-bit 2D texture for a whole quad (program_fetch_quad.h):
// programFetch's fast path (program_fetch.cpp: accumulateLevel) on four lanes, every
// operation the scalar one — the same float products and floors of the footprint, the same
// integer weights, the same double products and sums in the same order — so every lane
// gets its bits (tests/programmable/test_program_fetch.cpp holds it to the tap list).
#include "texunit/program_fetch_quad.h"

#include <immintrin.h>

#include <algorithm>

#include "addressing.h"

namespace rg::tex {

namespace {

bool powerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

bool axisApplies(AddressMode m, int n) {
    return m == AddressMode::ClampToEdge || (m == AddressMode::Wrap && powerOfTwo(n));
}

// One axis of the LINEAR footprint on four lanes, detail::axisFootprint's: u = c·n rounded
// to float, NaN → 0, clamped to ±2^22 (toSubTexel), ⌊u·2^8⌋ − 2^7 in 8-bit fixed point
// (the product is exact, the floor is floorToInt's for |u·2^8| ≤ 2^30), i0 its arithmetic
// shift by 8, α its low 8 bits; texels i0 and i0 + 1 through addressTexel — the mask
// under WRAP (n a power of two), the clamp to [0, n − 1] under CLAMP_TO_EDGE — and
// weights 2^8 − α and α.
[[gnu::target("avx2"), gnu::always_inline]] inline void linearAxis4(__m128 c, int n, bool wrap, __m128i& i0,
                                                                   __m128i& i1, __m128i& w0, __m128i& w1) {
    static_assert(kSubTexelBits == 8);
    __m128 u = _mm_mul_ps(c, _mm_set1_ps(float(n)));
    u = _mm_and_ps(u, _mm_cmpord_ps(u, u));  // NaN → 0
    u = _mm_min_ps(_mm_max_ps(u, _mm_set1_ps(-4194304.0f)), _mm_set1_ps(4194304.0f));
    const __m128i fixed =
        _mm_sub_epi32(_mm_cvttps_epi32(_mm_floor_ps(_mm_mul_ps(u, _mm_set1_ps(256.0f)))), _mm_set1_epi32(128));
    const __m128i i = _mm_srai_epi32(fixed, 8), j = _mm_add_epi32(i, _mm_set1_epi32(1));
    const __m128i last = _mm_set1_epi32(n - 1);
    if (wrap) {
        i0 = _mm_and_si128(i, last);
        i1 = _mm_and_si128(j, last);
    } else {
        const __m128i zero = _mm_setzero_si128();
        i0 = _mm_min_epi32(_mm_max_epi32(i, zero), last);
        i1 = _mm_min_epi32(_mm_max_epi32(j, zero), last);
    }
    w1 = _mm_and_si128(fixed, _mm_set1_epi32(255));
    w0 = _mm_sub_epi32(_mm_set1_epi32(256), w1);
}

// One level's four taps added into acc (a channel per register, a lane per double):
// accumulateLevel's taps (x0, y0), (x1, y0), (x0, y1), (x1, y1), each of weight
// double(levelWeight·w_x·w_y)·scale (≤ 2^24: exact, as is its product with v/255 in
// float, a 24-bit significand), then acc + weight·v in double.
[[gnu::target("avx2"), gnu::always_inline]] inline void accumulateLevel4(const Texture& t, const SamplerState& s,
                                                                        int level, __m128 cs, __m128 ct,
                                                                        int32_t levelWeight, __m256d scale,
                                                                        __m256d (&acc)[4]) {
    const auto& size = t.levelSize(level);
    __m128i x0, x1, wx0, wx1, y0, y1, wy0, wy1;
    linearAxis4(cs, size[0], s.address[0] == AddressMode::Wrap, x0, x1, wx0, wx1);
    linearAxis4(ct, size[1], s.address[1] == AddressMode::Wrap, y0, y1, wy0, wy1);
    const __m128i width = _mm_set1_epi32(size[0]);
    const __m128i row0 = _mm_mullo_epi32(y0, width), row1 = _mm_mullo_epi32(y1, width);
    const __m128i idx[4] = {_mm_add_epi32(row0, x0), _mm_add_epi32(row0, x1), _mm_add_epi32(row1, x0),
                            _mm_add_epi32(row1, x1)};
    const __m128i lw = _mm_set1_epi32(levelWeight);
    const __m128i wt[4] = {_mm_mullo_epi32(_mm_mullo_epi32(lw, wx0), wy0), _mm_mullo_epi32(_mm_mullo_epi32(lw, wx1), wy0),
                           _mm_mullo_epi32(_mm_mullo_epi32(lw, wx0), wy1), _mm_mullo_epi32(_mm_mullo_epi32(lw, wx1), wy1)};
    // An 8-bit texel (Rgba8: r, g, b, a in bytes 0–3) is one 32-bit word: four loads per
    // tap (VPGATHERDD, which this loop used before, is microcoded on AMD's Zen cores: the
    // board's pass took a tenth longer with it).
    const int* data = reinterpret_cast<const int*>(t.data8(level, 0));
    const __m128i byte = _mm_set1_epi32(255);
    const __m256d inv255 = _mm256_set1_pd(1.0 / 255.0);
    for (int tap = 0; tap < 4; ++tap) {
        alignas(16) int32_t at[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(at), idx[tap]);
        const __m128i texel = _mm_setr_epi32(data[at[0]], data[at[1]], data[at[2]], data[at[3]]);
        const __m256d w = _mm256_mul_pd(_mm256_cvtepi32_pd(wt[tap]), scale);
        for (int k = 0; k < 4; ++k) {
            const __m128i v8 = _mm_and_si128(_mm_srli_epi32(texel, 8 * k), byte);
            // texelAsFloat's v/255 in float, as v·(1/255) in double rounded to float: the
            // same bits for every v in 0..255 (ProgramFetch.Unorm8ProductEqualsDivision; v/255 repeats
            // v's byte in binary, so it is never within the product's error of a float
            // rounding boundary) for a multiply where a division per channel and tap cost
            // most of this fetch.
            const __m256d v = _mm256_cvtps_pd(_mm256_cvtpd_ps(_mm256_mul_pd(_mm256_cvtepi32_pd(v8), inv255)));
            acc[k] = _mm256_add_pd(acc[k], _mm256_mul_pd(w, v));
        }
    }
}

}  // namespace

bool quadFetch8Applies(const Texture& t, const SamplerState& s) {
    if (t.isFloat() || t.dims() != 2 || t.faces() != 1 || t.desc().target != TextureTarget::Texture2D) return false;
    if (s.magFilter != FilterMode::Linear || s.minFilter != FilterMode::Linear) return false;
    const auto& base = t.levelSize(std::clamp(s.baseLevel, 0, t.levels() - 1));
    return axisApplies(s.address[0], base[0]) && axisApplies(s.address[1], base[1]);
}

[[gnu::target("avx2")]] void programFetchQuad8(const Texture& t, const SamplerState& s,
                                                const std::array<glm::vec4, 4>& c, int32_t lambda, uint32_t lanes,
                                                std::array<glm::vec4, 4>& out, std::array<uint32_t, 4>& fetches) {
    // One λ for the quad, so one level choice (chooseLevels) for its four lanes; both
    // filters are LINEAR, so each level's footprint is 2×2.
    const LevelChoice ch = detail::chooseLevelsInline(detail::levelParams(t.levels(), s), lambda);
    const int bits = 2 * kSubTexelBits + (ch.blend ? kLodFracBits : 0);
    const __m256d scale = _mm256_set1_pd(1.0 / double(uint64_t(1) << bits));
    const __m128 cs = _mm_setr_ps(c[0].x, c[1].x, c[2].x, c[3].x);
    const __m128 ct = _mm_setr_ps(c[0].y, c[1].y, c[2].y, c[3].y);
    __m256d acc[4] = {_mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd()};
    accumulateLevel4(t, s, ch.level0, cs, ct, ch.blend ? kLodOne - ch.frac : 1, scale, acc);
    if (ch.blend) accumulateLevel4(t, s, ch.level1, cs, ct, ch.frac, scale, acc);
    // Rounded to float, lanes outside `lanes` zero, then channels per register to texels.
    const __m128i bit = _mm_setr_epi32(1, 2, 4, 8);
    const __m128 live = _mm_castsi128_ps(
        _mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(int32_t(lanes)), bit), bit));
    __m128 r = _mm_and_ps(_mm256_cvtpd_ps(acc[0]), live), g = _mm_and_ps(_mm256_cvtpd_ps(acc[1]), live);
    __m128 b = _mm_and_ps(_mm256_cvtpd_ps(acc[2]), live), a = _mm_and_ps(_mm256_cvtpd_ps(acc[3]), live);
    _MM_TRANSPOSE4_PS(r, g, b, a);
    _mm_storeu_ps(&out[0].x, r);
    _mm_storeu_ps(&out[1].x, g);
    _mm_storeu_ps(&out[2].x, b);
    _mm_storeu_ps(&out[3].x, a);
    const uint32_t taps = ch.blend ? 8u : 4u;
    for (int i = 0; i < 4; ++i)
        if ((lanes >> i) & 1u) fetches[size_t(i)] += taps;
}

}  // namespace rg::tex
