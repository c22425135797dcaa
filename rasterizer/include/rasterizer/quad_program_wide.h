// Quad groups in wide registers: the lane types of QuadGroupContext (quad_program.h) as
// GCC/Clang vector extensions of 4N floats, so that the AVX2 kernel (programmable_device.h:
// runQuadGroupsAvx2) runs two quads per 256-bit operation. The vector types are plain
// C++ — no target intrinsics — so the program compiles for any target; inlined into the
// kernel built for AVX2 they become AVX2 instructions, elsewhere the compiler splits them.
//
// Every operation is the IEEE binary32 operation lane by lane that Float4's SSE
// instruction performs (add, sub, mul, div, compares; select and min/max as written in
// quad_program.h, NaN included), so lane j of quad i computes what it computes alone.
#pragma once

#include <immintrin.h>

#include <cmath>
#include <cstring>

#include "rasterizer/quad_program.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"  // the AVX2 kernel inlines all of it: no call uses the ABI

namespace rg::raster {

// 4N lanes in N/2 registers of eight (one 256-bit register each on AVX2): wider vector
// types would be split by the compiler lane by lane on AVX2, and two or more registers
// give the core independent chains to overlap.
template <int N>
struct WideLanes {
    static_assert(N % 2 == 0, "wide groups hold whole registers of two quads");
    static constexpr int kRegs = N / 2;
    typedef float F __attribute__((vector_size(32)));
    typedef int32_t I __attribute__((vector_size(32)));
};

template <int N>
struct MaskW {
    using I = typename WideLanes<N>::I;
    static constexpr int kRegs = WideLanes<N>::kRegs;
    I r[kRegs]{};
    static MaskW allLanes() {
        MaskW m;
        for (auto& x : m.r) x = x == x;  // all ones
        return m;
    }
    static_assert(4 * N <= 64, "a group's lanes fit the 64 bits of bits()");
    uint64_t bits() const {  // bit 4i + j: lane j of quad i
        uint64_t b = 0;
        for (int k = 0; k < kRegs; ++k)
            for (int i = 0; i < 8; ++i) b |= uint64_t(r[k][i] & 1) << (8 * k + i);
        return b;
    }
    bool any() const { return bits() != 0; }
    bool all() const { return bits() == ~uint64_t(0) >> (64 - 4 * N); }
    Mask4 quad(int i) const {
        __m128 q;
        std::memcpy(&q, reinterpret_cast<const char*>(r) + 16 * i, 16);
        return Mask4(q);
    }
    void setQuad(int i, Mask4 m) { std::memcpy(reinterpret_cast<char*>(r) + 16 * i, &m.v, 16); }
    // Register k from quads 2k and 2k + 1 in registers (setQuad's two 16-byte stores, read
    // back as one 32-byte load, miss store forwarding).
    void setPair(int k, Mask4 a, Mask4 b) {
        typedef int32_t I4 __attribute__((vector_size(16)));
        r[k] = __builtin_shufflevector(reinterpret_cast<I4>(a.v), reinterpret_cast<I4>(b.v), 0, 1, 2, 3, 4, 5, 6, 7);
    }
    template <class Op>
    static MaskW zip(const MaskW& a, const MaskW& b, Op op) {
        MaskW m;
        for (int k = 0; k < kRegs; ++k) op(m.r[k], a.r[k], b.r[k]);
        return m;
    }
    friend MaskW operator&(const MaskW& a, const MaskW& b) { return zip(a, b, [](I& o, const I& x, const I& y) { o = x & y; }); }
    friend MaskW operator|(const MaskW& a, const MaskW& b) { return zip(a, b, [](I& o, const I& x, const I& y) { o = x | y; }); }
    friend MaskW operator^(const MaskW& a, const MaskW& b) { return zip(a, b, [](I& o, const I& x, const I& y) { o = x ^ y; }); }
    friend MaskW andNot(const MaskW& a, const MaskW& b) {
        return zip(a, b, [](I& o, const I& x, const I& y) { o = x & ~y; });
    }
};

template <int N>
struct FloatW {
    using F = typename WideLanes<N>::F;
    using I = typename WideLanes<N>::I;
    static constexpr int kRegs = WideLanes<N>::kRegs;
    F r[kRegs]{};
    FloatW() = default;
    FloatW(float s) {  // NOLINT: broadcasts like a scalar
        for (auto& x : r) x = F{} + s;
    }
    float operator[](int i) const { return r[i >> 3][i & 7]; }
    Float4 quad(int i) const {
        __m128 q;
        std::memcpy(&q, reinterpret_cast<const char*>(r) + 16 * i, 16);
        return Float4(q);
    }
    void setQuad(int i, Float4 f) { std::memcpy(reinterpret_cast<char*>(r) + 16 * i, &f.v, 16); }
    // As MaskW::setPair: register k from quads 2k and 2k + 1 without a trip through memory.
    void setPair(int k, Float4 a, Float4 b) {
        typedef float F4 __attribute__((vector_size(16)));
        r[k] = __builtin_shufflevector(static_cast<F4>(a.v), static_cast<F4>(b.v), 0, 1, 2, 3, 4, 5, 6, 7);
    }
    template <class Op>
    static FloatW zip(const FloatW& a, const FloatW& b, Op op) {
        FloatW o;
        for (int k = 0; k < kRegs; ++k) op(o.r[k], a.r[k], b.r[k]);
        return o;
    }
    template <class Op>
    static MaskW<N> compare(const FloatW& a, const FloatW& b, Op op) {
        MaskW<N> m;
        for (int k = 0; k < kRegs; ++k) op(m.r[k], a.r[k], b.r[k]);
        return m;
    }
    friend FloatW operator+(const FloatW& a, const FloatW& b) { return zip(a, b, [](F& o, const F& x, const F& y) { o = x + y; }); }
    friend FloatW operator-(const FloatW& a, const FloatW& b) { return zip(a, b, [](F& o, const F& x, const F& y) { o = x - y; }); }
    friend FloatW operator*(const FloatW& a, const FloatW& b) { return zip(a, b, [](F& o, const F& x, const F& y) { o = x * y; }); }
    friend FloatW operator/(const FloatW& a, const FloatW& b) { return zip(a, b, [](F& o, const F& x, const F& y) { o = x / y; }); }
    friend FloatW operator-(const FloatW& a) { return zip(a, a, [](F& o, const F& x, const F&) { o = -x; }); }
    FloatW& operator+=(const FloatW& b) { return *this = *this + b; }
    FloatW& operator-=(const FloatW& b) { return *this = *this - b; }
    FloatW& operator*=(const FloatW& b) { return *this = *this * b; }
    friend MaskW<N> operator<(const FloatW& a, const FloatW& b) { return compare(a, b, [](I& o, const F& x, const F& y) { o = x < y; }); }
    friend MaskW<N> operator<=(const FloatW& a, const FloatW& b) { return compare(a, b, [](I& o, const F& x, const F& y) { o = x <= y; }); }
    friend MaskW<N> operator>(const FloatW& a, const FloatW& b) { return compare(a, b, [](I& o, const F& x, const F& y) { o = x > y; }); }
    friend MaskW<N> operator>=(const FloatW& a, const FloatW& b) { return compare(a, b, [](I& o, const F& x, const F& y) { o = x >= y; }); }
    friend MaskW<N> operator==(const FloatW& a, const FloatW& b) { return compare(a, b, [](I& o, const F& x, const F& y) { o = x == y; }); }
    friend MaskW<N> operator!=(const FloatW& a, const FloatW& b) { return compare(a, b, [](I& o, const F& x, const F& y) { o = x != y; }); }
};

template <int N>
FloatW<N> select(const MaskW<N>& m, const FloatW<N>& a, const FloatW<N>& b) {
    FloatW<N> o;
    for (int k = 0; k < FloatW<N>::kRegs; ++k) o.r[k] = m.r[k] ? a.r[k] : b.r[k];
    return o;
}
template <int N>
FloatW<N> min(const FloatW<N>& a, const FloatW<N>& b) {  // (b < a) ? b : a, as min(Float4)
    return select(b < a, b, a);
}
template <int N>
FloatW<N> max(const FloatW<N>& a, const FloatW<N>& b) {  // (a < b) ? b : a, as max(Float4)
    return select(a < b, b, a);
}
template <int N>
FloatW<N> sqrt(const FloatW<N>& a) {  // correctly rounded, as SQRTPS
    FloatW<N> o;
    for (int k = 0; k < FloatW<N>::kRegs; ++k)
        for (int i = 0; i < 8; ++i) o.r[k][i] = std::sqrt(a.r[k][i]);
    return o;
}
template <int N>
FloatW<N> abs(const FloatW<N>& a) {  // the sign bit cleared, as abs(Float4)
    using I = typename WideLanes<N>::I;
    using F = typename WideLanes<N>::F;
    FloatW<N> o;
    for (int k = 0; k < FloatW<N>::kRegs; ++k)
        o.r[k] = reinterpret_cast<F>(reinterpret_cast<I>(a.r[k]) & (I{} + 0x7FFFFFFF));
    return o;
}

template <int N>
using Vec3W = Vec3L<FloatW<N>>;
template <int N>
using Vec4W = Vec4L<FloatW<N>>;

namespace detail {

// nearestTexels (quad_program.h) on 4N lanes in wide vectors: the same steps — a compare
// and select where MAXPS/MINPS stood (u > lo ? u : lo is MAXPS(u, lo), NaN → lo), the
// conversion truncating, the step down for negative non-integers.
// (Results through references: no wide vector is passed or returned by value.)
template <int N>
inline void nearestTexelsWide(const typename WideLanes<N>::F& c, int n, bool wrap, typename WideLanes<N>::I& out) {
    using F = typename WideLanes<N>::F;
    using I = typename WideLanes<N>::I;
    F u = c * float(n);
    if (!wrap) {
        const F zero{}, last = F{} + float(n - 1);
        u = u > zero ? u : zero;
        u = u < last ? u : last;
        out = __builtin_convertvector(u, I);
        return;
    }
    const F lo = F{} - 4194304.0f, hi = F{} + 4194304.0f;
    u = u > lo ? u : lo;
    u = u < hi ? u : hi;
    const I t = __builtin_convertvector(u, I);
    out = (t + (__builtin_convertvector(t, F) > u)) & (n - 1);
}

// The one-channel point fetch of kRegs registers (8 lanes each) with AVX2 instructions:
// nearestTexelsWide's steps with MAXPS/MINPS in nearestTexels' operand order, both address
// modes in one form (NearestFloat2D::Axis: CLAMP_TO_EDGE is the WRAP steps with bounds 0 and
// size − 1 and an all-ones mask, so the loop has no branch on the mode), the eight texels
// read one by one — every index is inside the level, whatever the lane — and the lanes
// outside `live` zeroed, as nearestLoads does, then 0 + texel for −0. Eight loads rather
// than VGATHERDPS: on the Zen 4 machines the benchmarks run on, the gather is the slower
// (binary_search, 1 thread: 3.6 -> 3.2 CPU-ms per frame); the indices leave in pairs
// (64-bit extracts), unsigned, so no sign extension. Only the AVX2 kernel reaches it (it
// is inlined there, programmable_device.h: runQuadGroupsAvx2 is flattened); a target
// function taking its vectors by pointer, so no call passes one in registers.
[[gnu::target("avx2"), gnu::always_inline]] inline __m256i nearestAxisAvx2(__m256 c, const NearestFloat2D::Axis& a) {
    const __m256 u = _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(c, _mm256_set1_ps(a.scale)), _mm256_set1_ps(a.lo)),
                                   _mm256_set1_ps(a.hi));
    // ⌊u⌋ as VROUNDPS toward −∞ then the conversion (u is clamped, never NaN, and the
    // floor of a float in [−2^22, 2^22] is exact): the integer the scalar steps' truncation
    // and step down give, in two operations on the search's dependent chain instead of four.
    const __m256i i = _mm256_cvttps_epi32(_mm256_round_ps(u, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
    return _mm256_and_si256(i, _mm256_set1_epi32(a.mask));
}

template <int kRegs>
[[gnu::target("avx2")]] inline void nearestFetchAvx2(const NearestFloat2D& n, const void* s, const void* t,
                                                     const void* live, void* out) {
    // The row offset y·width: a shift for a power-of-two width (y is 0 for a 1D texture).
    const bool shift = n.widthShift >= 0;
    const __m128i shiftCount = _mm_cvtsi32_si128(n.widthShift);
    const __m256i width = _mm256_set1_epi32(n.width);
    for (int k = 0; k < kRegs; ++k) {
        const __m256i x = nearestAxisAvx2(_mm256_loadu_ps(static_cast<const float*>(s) + 8 * k), n.axisS);
        const __m256i y = nearestAxisAvx2(_mm256_loadu_ps(static_cast<const float*>(t) + 8 * k), n.axisT);
        const __m256i idx = _mm256_add_epi32(x, shift ? _mm256_sll_epi32(y, shiftCount) : _mm256_mullo_epi32(y, width));
        const __m256 m = _mm256_loadu_ps(static_cast<const float*>(live) + 8 * k);
        const __m128i lo = _mm256_castsi256_si128(idx), hi = _mm256_extracti128_si256(idx, 1);
        const uint64_t p01 = uint64_t(_mm_cvtsi128_si64(lo)), p23 = uint64_t(_mm_extract_epi64(lo, 1));
        const uint64_t p45 = uint64_t(_mm_cvtsi128_si64(hi)), p67 = uint64_t(_mm_extract_epi64(hi, 1));
        const float* d = n.data1;
        const __m256 v = _mm256_and_ps(
            _mm256_setr_ps(d[uint32_t(p01)], d[p01 >> 32], d[uint32_t(p23)], d[p23 >> 32], d[uint32_t(p45)],
                           d[p45 >> 32], d[uint32_t(p67)], d[p67 >> 32]),
            m);
        _mm256_storeu_ps(static_cast<float*>(out) + 8 * k, _mm256_add_ps(v, _mm256_setzero_ps()));
    }
}

// The texels of lanes a (low half) and b (high half) of a vec4-per-texel level.
[[gnu::target("avx2"), gnu::always_inline]] inline __m256 texelPairAvx2(const float* d, uint64_t a, uint64_t b) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(d + 4 * size_t(a))), _mm_loadu_ps(d + 4 * size_t(b)), 1);
}

// The four-channel point fetch (RGBA16F, RGBA32F: a vec4 per texel, NearestFloat2D::data4)
// of kRegs registers: nearestFetchAvx2's addressing, each lane's texel one 16-byte load, a
// register's eight texels turned into x, y, z, w registers (a 4×4 transpose in each
// 128-bit half: lanes 0–3 from the low half's loads, 4–7 from the high half's), then
// nearestLoads' lanes outside `live` zeroed and 0 + texel for −0. Four-channel maps are
// what the image-space searches of the tir demo read (normal and depth in one texel):
// without this they left the wide kernel quad by quad at every step of the search.
template <int kRegs>
[[gnu::target("avx2")]] inline void nearestFetch4Avx2(const NearestFloat2D& n, const void* s, const void* t,
                                                      const void* live, void* x, void* y, void* z, void* w) {
    const bool shift = n.widthShift >= 0;
    const __m128i shiftCount = _mm_cvtsi32_si128(n.widthShift);
    const __m256i width = _mm256_set1_epi32(n.width);
    const float* d = &n.data4[0].x;
    const __m256 zero = _mm256_setzero_ps();
    for (int k = 0; k < kRegs; ++k) {
        const __m256i xi = nearestAxisAvx2(_mm256_loadu_ps(static_cast<const float*>(s) + 8 * k), n.axisS);
        const __m256i yi = nearestAxisAvx2(_mm256_loadu_ps(static_cast<const float*>(t) + 8 * k), n.axisT);
        const __m256i idx = _mm256_add_epi32(xi, shift ? _mm256_sll_epi32(yi, shiftCount) : _mm256_mullo_epi32(yi, width));
        const __m128i lo = _mm256_castsi256_si128(idx), hi = _mm256_extracti128_si256(idx, 1);
        const uint64_t p01 = uint64_t(_mm_cvtsi128_si64(lo)), p23 = uint64_t(_mm_extract_epi64(lo, 1));
        const uint64_t p45 = uint64_t(_mm_cvtsi128_si64(hi)), p67 = uint64_t(_mm_extract_epi64(hi, 1));
        const __m256 r0 = texelPairAvx2(d, uint32_t(p01), uint32_t(p45)), r1 = texelPairAvx2(d, p01 >> 32, p45 >> 32);
        const __m256 r2 = texelPairAvx2(d, uint32_t(p23), uint32_t(p67)), r3 = texelPairAvx2(d, p23 >> 32, p67 >> 32);
        const __m256 xy01 = _mm256_unpacklo_ps(r0, r1), zw01 = _mm256_unpackhi_ps(r0, r1);  // x0 x1 y0 y1 | x4 x5 y4 y5
        const __m256 xy23 = _mm256_unpacklo_ps(r2, r3), zw23 = _mm256_unpackhi_ps(r2, r3);
        const __m256 m = _mm256_loadu_ps(static_cast<const float*>(live) + 8 * k);
        const __m256 c[4] = {_mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(1, 0, 1, 0)),
                             _mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(3, 2, 3, 2)),
                             _mm256_shuffle_ps(zw01, zw23, _MM_SHUFFLE(1, 0, 1, 0)),
                             _mm256_shuffle_ps(zw01, zw23, _MM_SHUFFLE(3, 2, 3, 2))};
        void* const out[4] = {x, y, z, w};
        for (int j = 0; j < 4; ++j)
            _mm256_storeu_ps(static_cast<float*>(out[j]) + 8 * k, _mm256_add_ps(_mm256_and_ps(c[j], m), zero));
    }
}

// One axis of the bilinear footprint on eight lanes: tex::detail::axisFootprint under
// CLAMP_TO_EDGE with LINEAR — u = c·n (NaN → 0, clamped to ±2^22), ⌊u·2^8⌋ − ½·2^8 in
// 8-bit fixed point, i0 its floor over 2^8 (arithmetic shift), α its low 8 bits; texels i0
// and i0 + 1 clamped to [0, n − 1], weights 2^8 − α and α.
[[gnu::target("avx2"), gnu::always_inline]] inline void linearAxisAvx2(__m256 c, int n, __m256i& i0, __m256i& i1,
                                                                      __m256i& w0, __m256i& w1) {
    __m256 u = _mm256_mul_ps(c, _mm256_set1_ps(float(n)));
    u = _mm256_and_ps(u, _mm256_cmp_ps(u, u, _CMP_ORD_Q));  // NaN → 0
    u = _mm256_min_ps(_mm256_max_ps(u, _mm256_set1_ps(-4194304.0f)), _mm256_set1_ps(4194304.0f));
    const __m256i fixed = _mm256_sub_epi32(
        _mm256_cvttps_epi32(_mm256_round_ps(_mm256_mul_ps(u, _mm256_set1_ps(256.0f)), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC)),
        _mm256_set1_epi32(128));
    const __m256i i = _mm256_srai_epi32(fixed, 8), last = _mm256_set1_epi32(n - 1), zero = _mm256_setzero_si256();
    i0 = _mm256_min_epi32(_mm256_max_epi32(i, zero), last);
    i1 = _mm256_min_epi32(_mm256_max_epi32(_mm256_add_epi32(i, _mm256_set1_epi32(1)), zero), last);
    w1 = _mm256_and_si256(fixed, _mm256_set1_epi32(255));
    w0 = _mm256_sub_epi32(_mm256_set1_epi32(256), w1);
}

// The eight texels at `idx` as x, y, z, w registers (nearestFetch4Avx2's loads and transpose).
[[gnu::target("avx2"), gnu::always_inline]] inline void texels4Avx2(const float* d, __m256i idx, __m256 (&v)[4]) {
    const __m128i lo = _mm256_castsi256_si128(idx), hi = _mm256_extracti128_si256(idx, 1);
    const uint64_t p01 = uint64_t(_mm_cvtsi128_si64(lo)), p23 = uint64_t(_mm_extract_epi64(lo, 1));
    const uint64_t p45 = uint64_t(_mm_cvtsi128_si64(hi)), p67 = uint64_t(_mm_extract_epi64(hi, 1));
    const __m256 r0 = texelPairAvx2(d, uint32_t(p01), uint32_t(p45)), r1 = texelPairAvx2(d, p01 >> 32, p45 >> 32);
    const __m256 r2 = texelPairAvx2(d, uint32_t(p23), uint32_t(p67)), r3 = texelPairAvx2(d, p23 >> 32, p67 >> 32);
    const __m256 xy01 = _mm256_unpacklo_ps(r0, r1), zw01 = _mm256_unpackhi_ps(r0, r1);
    const __m256 xy23 = _mm256_unpacklo_ps(r2, r3), zw23 = _mm256_unpackhi_ps(r2, r3);
    v[0] = _mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(1, 0, 1, 0));
    v[1] = _mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(3, 2, 3, 2));
    v[2] = _mm256_shuffle_ps(zw01, zw23, _MM_SHUFFLE(1, 0, 1, 0));
    v[3] = _mm256_shuffle_ps(zw01, zw23, _MM_SHUFFLE(3, 2, 3, 2));
}

// The bilinear sum of register k of both float fetches below: the taps (x0, y0), (x1, y0),
// (x0, y1), (x1, y1) at row + x, each weight w_x·w_y/2^16 (exact in double, as is its
// product with a float texel), Σ weight·texel in double in that order from 0 on lanes 0–3
// and 4–7, rounded to float; lanes outside `live` zero.
[[gnu::target("avx2"), gnu::always_inline]] inline void bilinearSumAvx2(const float* d, __m256i row0, __m256i row1,
                                                                        __m256i x0, __m256i x1, __m256i wx0,
                                                                        __m256i wx1, __m256i wy0, __m256i wy1,
                                                                        const void* live, int k, void* x, void* y,
                                                                        void* z, void* w) {
    const __m256d scale = _mm256_set1_pd(1.0 / 65536.0);
    const __m256i idx[4] = {_mm256_add_epi32(row0, x0), _mm256_add_epi32(row0, x1), _mm256_add_epi32(row1, x0),
                            _mm256_add_epi32(row1, x1)};
    const __m256i wt[4] = {_mm256_mullo_epi32(wx0, wy0), _mm256_mullo_epi32(wx1, wy0), _mm256_mullo_epi32(wx0, wy1),
                           _mm256_mullo_epi32(wx1, wy1)};
    __m256d acc[4][2];
    for (int c = 0; c < 4; ++c) acc[c][0] = acc[c][1] = _mm256_setzero_pd();
    for (int tap = 0; tap < 4; ++tap) {
        __m256 v[4];
        texels4Avx2(d, idx[tap], v);
        const __m256d wlo = _mm256_mul_pd(_mm256_cvtepi32_pd(_mm256_castsi256_si128(wt[tap])), scale);
        const __m256d whi = _mm256_mul_pd(_mm256_cvtepi32_pd(_mm256_extracti128_si256(wt[tap], 1)), scale);
        for (int c = 0; c < 4; ++c) {
            acc[c][0] = _mm256_add_pd(acc[c][0], _mm256_mul_pd(wlo, _mm256_cvtps_pd(_mm256_castps256_ps128(v[c]))));
            acc[c][1] = _mm256_add_pd(acc[c][1], _mm256_mul_pd(whi, _mm256_cvtps_pd(_mm256_extractf128_ps(v[c], 1))));
        }
    }
    const __m256 m = _mm256_loadu_ps(static_cast<const float*>(live) + 8 * k);
    void* const out[4] = {x, y, z, w};
    for (int c = 0; c < 4; ++c) {
        const __m256 f = _mm256_set_m128(_mm256_cvtpd_ps(acc[c][1]), _mm256_cvtpd_ps(acc[c][0]));
        _mm256_storeu_ps(static_cast<float*>(out[c]) + 8 * k, _mm256_and_ps(f, m));
    }
}

// The bilinear float cube-map fetch (LinearFloatCube) of kRegs registers: what
// tex::programFetch's fast path computes lane by lane — the face and (s, t) of
// tex::detail::selectCubeFace (ties X before Y before Z, −0 and NaN as its compares take
// them, the face centre for a zero or NaN major axis), the footprint of linearAxisAvx2 on
// both axes, and Σ weight·texel over the taps (x0, y0), (x1, y0), (x0, y1), (x1, y1) in
// double, in that order from 0, each weight w_x·w_y/2^16 (exact, as is each product of a
// weight and a float texel in double); then rounded to float. Lanes outside `live` read
// zero. Every texel index is inside the level whatever the lane, so all are read without a
// branch.
template <int kRegs>
[[gnu::target("avx2")]] inline void linearCubeFetchAvx2(const LinearFloatCube& cube, const void* cx, const void* cy,
                                                        const void* cz, const void* live, void* x, void* y, void* z,
                                                        void* w) {
    const float* d = &cube.data[0].x;
    const __m256 sign = _mm256_set1_ps(-0.0f), zero = _mm256_setzero_ps(), half = _mm256_set1_ps(0.5f);
    const __m256 one = _mm256_set1_ps(1.0f);
    for (int k = 0; k < kRegs; ++k) {
        const __m256 rx = _mm256_loadu_ps(static_cast<const float*>(cx) + 8 * k);
        const __m256 ry = _mm256_loadu_ps(static_cast<const float*>(cy) + 8 * k);
        const __m256 rz = _mm256_loadu_ps(static_cast<const float*>(cz) + 8 * k);
        // ---- the face: selectCubeFace's branches as selects ----
        const __m256 ax = _mm256_andnot_ps(sign, rx), ay = _mm256_andnot_ps(sign, ry), az = _mm256_andnot_ps(sign, rz);
        const __m256 onX = _mm256_and_ps(_mm256_cmp_ps(ax, ay, _CMP_GE_OQ), _mm256_cmp_ps(ax, az, _CMP_GE_OQ));
        const __m256 onY = _mm256_andnot_ps(onX, _mm256_cmp_ps(ay, az, _CMP_GE_OQ));
        const __m256 posX = _mm256_cmp_ps(rx, zero, _CMP_GE_OQ), posY = _mm256_cmp_ps(ry, zero, _CMP_GE_OQ);
        const __m256 posZ = _mm256_cmp_ps(rz, zero, _CMP_GE_OQ);
        const __m256 nx = _mm256_xor_ps(rx, sign), ny = _mm256_xor_ps(ry, sign), nz = _mm256_xor_ps(rz, sign);
        // The table's (sc, tc, ma): ±X (∓z, −y, x), ±Y (x, ±z, y), ±Z (±x, −y, z).
        const __m256 sc = _mm256_blendv_ps(_mm256_blendv_ps(_mm256_blendv_ps(nx, rx, posZ), rx, onY),
                                           _mm256_blendv_ps(rz, nz, posX), onX);
        const __m256 tc = _mm256_blendv_ps(ny, _mm256_blendv_ps(nz, rz, posY), onY);
        const __m256 ma = _mm256_blendv_ps(_mm256_blendv_ps(rz, ry, onY), rx, onX);
        const __m256 faceF = _mm256_blendv_ps(
            _mm256_blendv_ps(_mm256_blendv_ps(_mm256_set1_ps(5.0f), _mm256_set1_ps(4.0f), posZ),
                             _mm256_blendv_ps(_mm256_set1_ps(3.0f), _mm256_set1_ps(2.0f), posY), onY),
            _mm256_blendv_ps(one, zero, posX), onX);
        const __m256i face = _mm256_cvttps_epi32(faceF);
        const __m256 a = _mm256_andnot_ps(sign, ma);
        const __m256 onFace = _mm256_cmp_ps(a, zero, _CMP_GT_OQ);
        const __m256 s = _mm256_blendv_ps(half, _mm256_mul_ps(_mm256_add_ps(_mm256_div_ps(sc, a), one), half), onFace);
        const __m256 t = _mm256_blendv_ps(half, _mm256_mul_ps(_mm256_add_ps(_mm256_div_ps(tc, a), one), half), onFace);
        // ---- the footprint: the four taps' indices and weights ----
        __m256i x0, x1, wx0, wx1, y0, y1, wy0, wy1;
        linearAxisAvx2(s, cube.size, x0, x1, wx0, wx1);
        linearAxisAvx2(t, cube.size, y0, y1, wy0, wy1);
        const __m256i base = _mm256_mullo_epi32(face, _mm256_set1_epi32(cube.faceTexels));
        const __m256i n = _mm256_set1_epi32(cube.size);
        const __m256i row0 = _mm256_add_epi32(base, _mm256_mullo_epi32(y0, n));
        const __m256i row1 = _mm256_add_epi32(base, _mm256_mullo_epi32(y1, n));
        bilinearSumAvx2(d, row0, row1, x0, x1, wx0, wx1, wy0, wy1, live, k, x, y, z, w);
    }
}

// The bilinear float 2D fetch (LinearFloat2D) of kRegs registers: linearCubeFetchAvx2
// without the face — the footprint of linearAxisAvx2 on s over the width and on t over the
// height (CLAMP_TO_EDGE), the taps (x0, y0), (x1, y0), (x0, y1), (x1, y1) at y·width + x,
// and Σ weight·texel in double in that order from 0, each weight w_x·w_y/2^16; then
// rounded to float. Lanes outside `live` read zero; every index is inside the level.
template <int kRegs>
[[gnu::target("avx2")]] inline void linear2DFetchAvx2(const LinearFloat2D& tex2d, const void* cs, const void* ct,
                                                      const void* live, void* x, void* y, void* z, void* w) {
    const float* d = &tex2d.data[0].x;
    const __m256i width = _mm256_set1_epi32(tex2d.width);
    for (int k = 0; k < kRegs; ++k) {
        const __m256 s = _mm256_loadu_ps(static_cast<const float*>(cs) + 8 * k);
        const __m256 t = _mm256_loadu_ps(static_cast<const float*>(ct) + 8 * k);
        __m256i x0, x1, wx0, wx1, y0, y1, wy0, wy1;
        linearAxisAvx2(s, tex2d.width, x0, x1, wx0, wx1);
        linearAxisAvx2(t, tex2d.height, y0, y1, wy0, wy1);
        const __m256i row0 = _mm256_mullo_epi32(y0, width), row1 = _mm256_mullo_epi32(y1, width);
        bilinearSumAvx2(d, row0, row1, x0, x1, wx0, wx1, wy0, wy1, live, k, x, y, z, w);
    }
}

// The point-sampled four-channel float cube-map fetch (NearestFloat2D with `cube` and
// data4) of kRegs registers: nearestCubeIndices on eight lanes — linearCubeFetchAvx2's face
// selection, which is its table lane for lane, then (s, t) to texels as nearestTexels
// without wrap and face·n² + y·n + x — the loads and transpose of texels4Avx2, and
// nearestLoads' 0 + texel for −0 and zero outside `live`. Every operation is the SSE code's,
// so every lane gets the bits QuadContext::sampleLevel gives it.
template <int kRegs>
[[gnu::target("avx2")]] inline void nearestCubeFetch4Avx2(const NearestFloat2D& n, const void* cx, const void* cy,
                                                          const void* cz, const void* live, void* x, void* y, void* z,
                                                          void* w) {
    const float* d = &n.data4[0].x;
    const __m256 sign = _mm256_set1_ps(-0.0f), zero = _mm256_setzero_ps(), half = _mm256_set1_ps(0.5f);
    const __m256 one = _mm256_set1_ps(1.0f);
    const __m256 scaleS = _mm256_set1_ps(float(n.width)), lastS = _mm256_set1_ps(float(n.width - 1));
    const __m256 scaleT = _mm256_set1_ps(float(n.height)), lastT = _mm256_set1_ps(float(n.height - 1));
    const __m256i faceTexels = _mm256_set1_epi32(int32_t(n.faceTexels)), width = _mm256_set1_epi32(n.width);
    for (int k = 0; k < kRegs; ++k) {
        const __m256 rx = _mm256_loadu_ps(static_cast<const float*>(cx) + 8 * k);
        const __m256 ry = _mm256_loadu_ps(static_cast<const float*>(cy) + 8 * k);
        const __m256 rz = _mm256_loadu_ps(static_cast<const float*>(cz) + 8 * k);
        const __m256 ax = _mm256_andnot_ps(sign, rx), ay = _mm256_andnot_ps(sign, ry), az = _mm256_andnot_ps(sign, rz);
        const __m256 onX = _mm256_and_ps(_mm256_cmp_ps(ax, ay, _CMP_GE_OQ), _mm256_cmp_ps(ax, az, _CMP_GE_OQ));
        const __m256 onY = _mm256_andnot_ps(onX, _mm256_cmp_ps(ay, az, _CMP_GE_OQ));
        const __m256 posX = _mm256_cmp_ps(rx, zero, _CMP_GE_OQ), posY = _mm256_cmp_ps(ry, zero, _CMP_GE_OQ);
        const __m256 posZ = _mm256_cmp_ps(rz, zero, _CMP_GE_OQ);
        const __m256 nx = _mm256_xor_ps(rx, sign), ny = _mm256_xor_ps(ry, sign), nz = _mm256_xor_ps(rz, sign);
        const __m256 sc = _mm256_blendv_ps(_mm256_blendv_ps(_mm256_blendv_ps(nx, rx, posZ), rx, onY),
                                           _mm256_blendv_ps(rz, nz, posX), onX);
        const __m256 tc = _mm256_blendv_ps(ny, _mm256_blendv_ps(nz, rz, posY), onY);
        const __m256 ma = _mm256_blendv_ps(_mm256_blendv_ps(rz, ry, onY), rx, onX);
        const __m256 faceF = _mm256_blendv_ps(
            _mm256_blendv_ps(_mm256_blendv_ps(_mm256_set1_ps(5.0f), _mm256_set1_ps(4.0f), posZ),
                             _mm256_blendv_ps(_mm256_set1_ps(3.0f), _mm256_set1_ps(2.0f), posY), onY),
            _mm256_blendv_ps(one, zero, posX), onX);
        const __m256i face = _mm256_cvttps_epi32(faceF);
        const __m256 a = _mm256_andnot_ps(sign, ma);
        const __m256 onFace = _mm256_cmp_ps(a, zero, _CMP_GT_OQ);
        const __m256 s = _mm256_blendv_ps(half, _mm256_mul_ps(_mm256_add_ps(_mm256_div_ps(sc, a), one), half), onFace);
        const __m256 t = _mm256_blendv_ps(half, _mm256_mul_ps(_mm256_add_ps(_mm256_div_ps(tc, a), one), half), onFace);
        const __m256i tx = _mm256_cvttps_epi32(_mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(s, scaleS), zero), lastS));
        const __m256i ty = _mm256_cvttps_epi32(_mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(t, scaleT), zero), lastT));
        const __m256i idx = _mm256_add_epi32(
            _mm256_add_epi32(_mm256_mullo_epi32(face, faceTexels), _mm256_mullo_epi32(ty, width)), tx);
        __m256 v[4];
        texels4Avx2(d, idx, v);
        const __m256 m = _mm256_loadu_ps(static_cast<const float*>(live) + 8 * k);
        void* const out[4] = {x, y, z, w};
        for (int j = 0; j < 4; ++j)
            _mm256_storeu_ps(static_cast<float*>(out[j]) + 8 * k, _mm256_and_ps(_mm256_add_ps(v[j], zero), m));
    }
}

// The four-channel fast fetches (nearestFetch4Avx2, linearCubeFetchAvx2) as the wide
// context calls them: out of line, their arguments copied into a thread's own storage on
// that branch only, as QuadByQuadSample's. Inlined beside the one-channel fetch at every
// call site, their code alone — never run — made binary_search's loop a fifth slower
// (3.3 -> 4.0 CPU-ms per frame at 1 thread).
template <int N>
struct FourChannelFetch {
    FloatW<N> x, y, z;
    MaskW<N> live;
    // Where the calls below write: a thread's own, so that the caller's result is a copy
    // and not a value zeroed (FloatW's default) and then overwritten through memory — a
    // `rep stos` at every fetch of the impostors' glass programs.
    Vec4W<N> out;
    [[RG_NOIPA]] static FourChannelFetch& storage() {
        static thread_local FourChannelFetch a;
        return a;
    }
    [[RG_NOIPA, gnu::target("avx2")]] void nearest(const NearestFloat2D& n, Vec4W<N>& out) const {
        nearestFetch4Avx2<FloatW<N>::kRegs>(n, x.r, y.r, live.r, out.x.r, out.y.r, out.z.r, out.w.r);
    }
    [[RG_NOIPA, gnu::target("avx2")]] void cube(const LinearFloatCube& c, Vec4W<N>& out) const {
        linearCubeFetchAvx2<FloatW<N>::kRegs>(c, x.r, y.r, z.r, live.r, out.x.r, out.y.r, out.z.r, out.w.r);
    }
    [[RG_NOIPA, gnu::target("avx2")]] void linear2D(const LinearFloat2D& t, Vec4W<N>& out) const {
        linear2DFetchAvx2<FloatW<N>::kRegs>(t, x.r, y.r, live.r, out.x.r, out.y.r, out.z.r, out.w.r);
    }
    // The point-sampled float cube map on all N quads in one call: four channels on eight
    // lanes at a time (nearestCubeFetch4Avx2), one channel through nearestCubeIndices and
    // nearestLoads over the quads, the SSE code QuadContext::sampleLevel runs on one quad;
    // every lane gets the same bits (the impostors' distance maps: 40-odd fetches per
    // fragment, which went quad by quad through the slow path before).
    [[RG_NOIPA, gnu::target("avx2")]] void nearestCube(const NearestFloat2D& n, Vec4W<N>& out) const {
        if (n.data4) {  // four channels: eight lanes at a time
            nearestCubeFetch4Avx2<FloatW<N>::kRegs>(n, x.r, y.r, z.r, live.r, out.x.r, out.y.r, out.z.r, out.w.r);
            return;
        }
        __m128 s[N], t[N], r[N], l[N];
        for (int i = 0; i < N; ++i) {
            s[i] = x.quad(i).v;
            t[i] = y.quad(i).v;
            r[i] = z.quad(i).v;
            l[i] = live.quad(i).v;
        }
        __m128i idx[N];
        __m128 ox[N], oy[N], oz[N], ow[N];
        nearestCubeIndices<N>(n, s, t, r, idx);
        nearestLoads<N>(n, idx, l, ox, oy, oz, ow);
        for (int i = 0; i < N; ++i) {
            out.x.setQuad(i, Float4(ox[i]));
            out.y.setQuad(i, Float4(oy[i]));
            out.z.setQuad(i, Float4(oz[i]));
            out.w.setQuad(i, Float4(ow[i]));
        }
    }
};

}  // namespace detail

// QuadGroupContext with wide lane types: the same interface and the same per-quad calls,
// the point-sampled fetch on all 4N lanes at once.
template <int N>
class QuadGroupWideContext {
  public:
    using Float = FloatW<N>;
    using Mask = MaskW<N>;
    using Vec3 = Vec3W<N>;
    using Vec4 = Vec4W<N>;
    static constexpr int kQuads = N;

    Mask active() const { return live_; }
    Vec4 varying(int k) const { return each([&](const QuadContext& c) { return c.varying(k); }); }
    Vec4 fragCoord() const { return each([](const QuadContext& c) { return c.fragCoord(); }); }
    // Without a mask every live lane fetches: the call is counted once (allFetches_) and
    // added to the live lanes when they change (discard) or the group ends, instead of a
    // per-lane count updated at every fetch.
    [[gnu::always_inline]] Vec4 sampleLevel(int unit, const Vec4& c, const Float& lod) {
        return sampleLevelLanes<true>(unit, c, lod, Mask::allLanes());
    }
    [[gnu::always_inline]] Vec4 sampleLevel(int unit, const Vec4& c, const Float& lod, const Mask& m) {
        return sampleLevelLanes<false>(unit, c, lod, m);
    }
    Vec4 sample(int unit, int k, const Mask& m = Mask::allLanes()) {
        const detail::BoundUnit& b = quads_[0].unit(unit);
        if (b.linear2D.valid() && quads_[0].setup_->path == Path::Fast) {
            // Bilinear without mipmaps: λ cannot change the result, so all lanes at once.
            const Mask live = countFetches<false>(m, 4);
            const Vec4 c = varying(k);
            FourArgs& a = FourArgs::storage();
            for (int r = 0; r < WideLanes<N>::kRegs; ++r) {
                a.x.r[r] = c.x.r[r];
                a.y.r[r] = c.y.r[r];
                a.live.r[r] = live.r[r];
            }
            a.linear2D(b.linear2D, a.out);
            return a.out;
        }
        Vec4 r;
        for (int i = 0; i < N; ++i) r.setQuad(i, quads_[size_t(i)].sample(unit, k, m.quad(i)));
        return r;
    }
    Float sampleCompare(int unit, const Vec4& c, const Float& ref, const Mask& m = Mask::allLanes()) {
        Float r;
        for (int i = 0; i < N; ++i)
            r.setQuad(i, quads_[size_t(i)].sampleCompare(unit, c.quad(i), ref.quad(i), m.quad(i)));
        return r;
    }
    void discard(const Mask& m) {
        flushAllFetches();
        for (int i = 0; i < N; ++i) {
            quads_[size_t(i)].discard(m.quad(i));
            live_.setQuad(i, quads_[size_t(i)].active());
        }
    }
    void output(int target, const Vec4& color, const Mask& m = Mask::allLanes()) {
        for (int i = 0; i < N; ++i) quads_[size_t(i)].output(target, color.quad(i), m.quad(i));
    }

    // ---- used by the pipeline --------------------------------------------------------------
    QuadContext& quad(int i) { return quads_[size_t(i)]; }
    // After the quads' begin: the group's lane masks. Before their finish: the fetches
    // counted here, added to the quads' own.
    void beginGroup() {
        for (int k = 0; k < Mask::kRegs; ++k)
            live_.setPair(k, quads_[size_t(2 * k)].active(), quads_[size_t(2 * k + 1)].active());
        fetches_ = Mask();
        allFetches_ = 0;
    }
    void endGroup() {
        flushAllFetches();
        for (int i = 0; i < N; ++i) {
            alignas(16) int32_t n[4];
            std::memcpy(n, reinterpret_cast<const char*>(fetches_.r) + 16 * i, 16);
            for (int l = 0; l < 4; ++l) quads_[size_t(i)].fetches_[size_t(l)] += uint32_t(n[l]);
        }
    }

  private:
    template <bool kAllLanes>
    [[gnu::always_inline]] Vec4 sampleLevelLanes(int unit, const Vec4& c, const Float& lod, const Mask& m) {
        using F = typename WideLanes<N>::F;
        using I = typename WideLanes<N>::I;
        constexpr int kRegs = WideLanes<N>::kRegs;
        const detail::BoundUnit& b = quads_[0].unit(unit);
        const detail::NearestFloat2D& n = b.nearest;
        const bool fast = quads_[0].setup_->path == Path::Fast;
        if (n.lanes4 && n.data1 && fast) [[likely]] {
            // The one-channel point fetch first and on its own: the image-space searches'
            // depth maps (binary_search's inner loop), whose chain of dependent fetches
            // slowed by half when a test for the four-channel case stood before it.
            const Mask live = countFetches<kAllLanes>(m, 1);
            Float t, one;
            detail::nearestFetchAvx2<kRegs>(n, c.x.r, c.y.r, live.r, t.r);
            for (int k = 0; k < kRegs; ++k) one.r[k] = reinterpret_cast<F>(reinterpret_cast<I>(F{} + 1.0f) & live.r[k]);
            return n.depth ? Vec4(t, t, t, one) : Vec4(t, Float(0.0f), Float(0.0f), one);
        }
        if (fast && (n.lanes4 || n.cube || b.cube.valid())) {  // four channels: one texel, or four taps
            const bool point = n.lanes4 || n.cube;
            const Mask live = countFetches<kAllLanes>(m, point ? 1 : 4);
            FourArgs& a = FourArgs::storage();
            for (int k = 0; k < kRegs; ++k) {
                a.x.r[k] = c.x.r[k];
                a.y.r[k] = c.y.r[k];
                a.z.r[k] = c.z.r[k];
                a.live.r[k] = live.r[k];
            }
            if (n.cube)
                a.nearestCube(n, a.out);
            else if (point)
                a.nearest(n, a.out);
            else
                a.cube(b.cube, a.out);
            return a.out;
        }
        // Copied on this branch only, into storage the compiler cannot move stores to (a
        // thread's own): the caller's temporaries are only read, so they stay in registers
        // on the fast paths.
        SlowArgs& a = SlowArgs::storage();
        for (int k = 0; k < kRegs; ++k) {  // register by register: no aggregate copy
            a.c.x.r[k] = c.x.r[k];
            a.c.y.r[k] = c.y.r[k];
            a.c.z.r[k] = c.z.r[k];
            a.c.w.r[k] = c.w.r[k];
            a.lod.r[k] = lod.r[k];
            a.m.r[k] = m.r[k];
        }
        return a.run(quads_, unit);
    }
    // The fast fetches' count, `taps` texels per fetching lane, and the lanes that fetch.
    template <bool kAllLanes>
    [[gnu::always_inline]] Mask countFetches(const Mask& m, int32_t taps) {
        if constexpr (kAllLanes) {
            allFetches_ += taps;
            return live_;
        } else {
            const Mask live = live_ & m;
            for (int k = 0; k < Mask::kRegs; ++k) fetches_.r[k] -= live.r[k] * taps;  // −taps per fetching lane
            return live;
        }
    }
    // The unmasked fetches since the last flush to every live lane's count.
    void flushAllFetches() {
        using I = typename WideLanes<N>::I;
        for (int k = 0; k < Mask::kRegs; ++k) fetches_.r[k] += live_.r[k] & (I{} + allFetches_);
        allFetches_ = 0;
    }
    // Quad by quad: filtered samplers other than the bilinear float cube map, non-power-of-two
    // WRAP, the reference path.
    using SlowArgs = detail::QuadByQuadSample<Vec4, Float, Mask>;
    using FourArgs = detail::FourChannelFetch<N>;
    template <class Fn>
    Vec4 each(Fn f) const {
        Vec4 r;
        for (int k = 0; k < Mask::kRegs; ++k) r.setPair(k, f(quads_[size_t(2 * k)]), f(quads_[size_t(2 * k + 1)]));
        return r;
    }
    std::array<QuadContext, N> quads_;
    Mask live_;     // the quads' active lanes
    Mask fetches_;  // the masked point-sampled fetches per lane since beginGroup
    int32_t allFetches_ = 0;  // unmasked point-sampled fetches not yet in fetches_
};

}  // namespace rg::raster

#pragma GCC diagnostic pop
