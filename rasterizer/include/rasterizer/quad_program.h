// Quad programs: fragment programs that run the four pixels of a 2×2 quad at once, one
// SSE lane each — the way the G80 and llvmpipe run shaders (SIMD over pixels, a mask for
// the pixels still active), and the fast way to run a loop-heavy program on a CPU.
//
// A quad program is a fragment program (program.h) whose operator() takes a QuadContext:
//
//   struct Search {
//       static constexpr int kVaryings = 0;
//       static constexpr uint32_t kTargets = 1, kUnits = 1;
//       static constexpr bool kWritesDepth = false;       // quad programs cannot write depth
//       void operator()(QuadContext& q) const {
//           Float4 lo(0.0f), hi(1.0f);
//           for (int i = 0; i < 8; ++i) {
//               const Float4 mid = Float4(0.5f) * (lo + hi);
//               const Vec4x4 d = q.sampleLevel(0, ..., 0.0f);
//               const Mask4 above = mid > d.x;
//               hi = select(above, mid, hi);
//               lo = select(above, lo, mid);
//           }
//           q.output(0, Vec4x4(...));
//       }
//   };
//
// Every lane operation is the IEEE binary32 operation of the scalar C++ it replaces (SSE
// add, sub, mul, div, sqrt, min, max and compares are correctly rounded; no fused
// multiply-add), so a quad program computes exactly what the same program would pixel by
// pixel. The reference path runs a quad program with one lane active at a time, and the
// randomized tests compare the two (tests/programmable/).
#pragma once

#include <emmintrin.h>
#include <xmmintrin.h>

#include <array>
#include <cstdint>

#include <glm/vec4.hpp>

#include "rasterizer/program.h"

// A function the optimizer must leave whole (no cloning, no partial inlining, which would
// pull a cold path's argument copies into its hot caller); Clang has no noipa.
#if defined(__clang__)
#define RG_NOIPA gnu::noinline
#else
#define RG_NOIPA gnu::noipa
#endif

namespace rg::raster {

struct Mask4 {
    __m128 v;
    Mask4() : v(_mm_setzero_ps()) {}
    explicit Mask4(__m128 m) : v(m) {}
    static Mask4 fromBits(uint32_t bits) {  // lane i: all ones where bit i is set
        const __m128i bit = _mm_setr_epi32(1, 2, 4, 8);
        return Mask4(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(int(bits)), bit), bit)));
    }
    uint32_t bits() const { return uint32_t(_mm_movemask_ps(v)); }
    bool any() const { return bits() != 0; }
    bool all() const { return bits() == 15; }
    friend Mask4 operator&(Mask4 a, Mask4 b) { return Mask4(_mm_and_ps(a.v, b.v)); }
    friend Mask4 operator|(Mask4 a, Mask4 b) { return Mask4(_mm_or_ps(a.v, b.v)); }
    friend Mask4 operator^(Mask4 a, Mask4 b) { return Mask4(_mm_xor_ps(a.v, b.v)); }
    friend Mask4 andNot(Mask4 a, Mask4 b) { return Mask4(_mm_andnot_ps(b.v, a.v)); }  // a & ~b
};

struct Float4 {
    __m128 v;
    Float4() : v(_mm_setzero_ps()) {}
    Float4(float s) : v(_mm_set1_ps(s)) {}  // NOLINT: broadcasts like a scalar
    explicit Float4(__m128 x) : v(x) {}
    static Float4 lanes(float a, float b, float c, float d) { return Float4(_mm_setr_ps(a, b, c, d)); }
    float operator[](int i) const {
        alignas(16) float t[4];
        _mm_store_ps(t, v);
        return t[i];
    }
    friend Float4 operator+(Float4 a, Float4 b) { return Float4(_mm_add_ps(a.v, b.v)); }
    friend Float4 operator-(Float4 a, Float4 b) { return Float4(_mm_sub_ps(a.v, b.v)); }
    friend Float4 operator*(Float4 a, Float4 b) { return Float4(_mm_mul_ps(a.v, b.v)); }
    friend Float4 operator/(Float4 a, Float4 b) { return Float4(_mm_div_ps(a.v, b.v)); }
    friend Float4 operator-(Float4 a) { return Float4(_mm_xor_ps(a.v, _mm_set1_ps(-0.0f))); }
    Float4& operator+=(Float4 b) { return *this = *this + b; }
    Float4& operator-=(Float4 b) { return *this = *this - b; }
    Float4& operator*=(Float4 b) { return *this = *this * b; }
    friend Mask4 operator<(Float4 a, Float4 b) { return Mask4(_mm_cmplt_ps(a.v, b.v)); }
    friend Mask4 operator<=(Float4 a, Float4 b) { return Mask4(_mm_cmple_ps(a.v, b.v)); }
    friend Mask4 operator>(Float4 a, Float4 b) { return Mask4(_mm_cmpgt_ps(a.v, b.v)); }
    friend Mask4 operator>=(Float4 a, Float4 b) { return Mask4(_mm_cmpge_ps(a.v, b.v)); }
    friend Mask4 operator==(Float4 a, Float4 b) { return Mask4(_mm_cmpeq_ps(a.v, b.v)); }
    friend Mask4 operator!=(Float4 a, Float4 b) { return Mask4(_mm_cmpneq_ps(a.v, b.v)); }
};

// select(m, a, b): a where m, else b (the scalar `m ? a : b`).
inline Float4 select(Mask4 m, Float4 a, Float4 b) {
    return Float4(_mm_or_ps(_mm_and_ps(m.v, a.v), _mm_andnot_ps(m.v, b.v)));
}
// std::min(a, b) / std::max(a, b) of the scalar code: (b < a) ? b : a and (a < b) ? b : a,
// lane by lane, so NaN behaves as in the scalar expression.
inline Float4 min(Float4 a, Float4 b) { return select(b < a, b, a); }
inline Float4 max(Float4 a, Float4 b) { return select(a < b, b, a); }
inline Float4 sqrt(Float4 a) { return Float4(_mm_sqrt_ps(a.v)); }
inline Float4 abs(Float4 a) { return Float4(_mm_andnot_ps(_mm_set1_ps(-0.0f), a.v)); }

// Vectors of three and four components over any lane type F: Float4 (one quad), FloatQ<N>
// (N quads of Float4) and FloatW<N> (quad_program_wide.h). One definition, so a program's
// vector arithmetic is the same operations in the same order whichever context runs it.
// Members that only some lane types support (fromLanes, quad, setQuad, setPair) are
// templates' members, compiled only where used.
template <class F>
struct Vec3L {
    F x, y, z;
    Vec3L() = default;
    Vec3L(const F& a, const F& b, const F& c) : x(a), y(b), z(c) {}
    friend Vec3L operator+(const Vec3L& a, const Vec3L& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend Vec3L operator-(const Vec3L& a, const Vec3L& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend Vec3L operator*(const Vec3L& a, const F& s) { return {a.x * s, a.y * s, a.z * s}; }
    friend Vec3L operator*(const Vec3L& a, const Vec3L& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
};
// glm::dot's order: (x·x + y·y) + z·z.
template <class F>
F dot(const Vec3L<F>& a, const Vec3L<F>& b) {
    return (a.x * b.x + a.y * b.y) + a.z * b.z;
}
template <class M, class F>
Vec3L<F> select(const M& m, const Vec3L<F>& a, const Vec3L<F>& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}

template <class F>
struct Vec4L {
    F x, y, z, w;
    Vec4L() = default;
    Vec4L(const F& a, const F& b, const F& c, const F& d) : x(a), y(b), z(c), w(d) {}
    // Four per-pixel vectors (lane i = pixel i) as one vector of lanes (Float4).
    static Vec4L fromLanes(const std::array<glm::vec4, 4>& p) {
        return {F::lanes(p[0].x, p[1].x, p[2].x, p[3].x), F::lanes(p[0].y, p[1].y, p[2].y, p[3].y),
                F::lanes(p[0].z, p[1].z, p[2].z, p[3].z), F::lanes(p[0].w, p[1].w, p[2].w, p[3].w)};
    }
    Vec3L<F> xyz() const { return {x, y, z}; }
    glm::vec4 lane(int i) const { return {x[i], y[i], z[i], w[i]}; }
    // Quad i of a group (FloatQ, FloatW) as one Float4 vector, and back.
    auto quad(int i) const {
        using Q = decltype(x.quad(i));
        return Vec4L<Q>{x.quad(i), y.quad(i), z.quad(i), w.quad(i)};
    }
    template <class Q>
    void setQuad(int i, const Vec4L<Q>& v) {
        x.setQuad(i, v.x);
        y.setQuad(i, v.y);
        z.setQuad(i, v.z);
        w.setQuad(i, v.w);
    }
    // FloatW: register k from quads 2k and 2k + 1 (FloatW::setPair).
    template <class Q>
    void setPair(int k, const Vec4L<Q>& a, const Vec4L<Q>& b) {
        x.setPair(k, a.x, b.x);
        y.setPair(k, a.y, b.y);
        z.setPair(k, a.z, b.z);
        w.setPair(k, a.w, b.w);
    }
    friend Vec4L operator+(const Vec4L& a, const Vec4L& b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
    friend Vec4L operator-(const Vec4L& a, const Vec4L& b) { return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w}; }
    friend Vec4L operator*(const Vec4L& a, const F& s) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }
    friend Vec4L operator*(const Vec4L& a, const Vec4L& b) { return {a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w}; }
};
template <class M, class F>
Vec4L<F> select(const M& m, const Vec4L<F>& a, const Vec4L<F>& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z), select(m, a.w, b.w)};
}

using Vec3x4 = Vec3L<Float4>;
using Vec4x4 = Vec4L<Float4>;

namespace detail {

// The point-sampled fetch (NearestFloat2D) on N quads of four lanes at once, for a unit
// with `lanes4` set. The unit's branches (address modes, power-of-two width, format) are
// taken once for all N quads, so each quad's steps are straight-line code the core
// overlaps with the other quads'.

// detail::nearestTexel on 4N lanes, for WRAP on a power of two (n ≤ 2^22) or
// CLAMP_TO_EDGE: ⌊c·n⌋ with NaN → 0 and the clamp to ±2^22, then the address mode.
// NaN needs no compare of its own: MAXPS returns its second operand when either is NaN, so
// max(u, −2^22) maps NaN to −2^22 (for WRAP: a multiple of n, texel 0 as NaN → 0 gives)
// and max(u, 0) maps it to 0 (CLAMP_TO_EDGE). Clamping the float to [0, n − 1] before the
// floor equals clamping the floored integer, and truncation of a non-negative float is
// its floor.
template <int N>
[[gnu::always_inline]] inline void nearestTexels(const __m128 (&c)[N], int n, bool wrap, __m128i (&out)[N]) {
    const __m128 scale = _mm_set1_ps(float(n));
    if (!wrap) {
        const __m128 last = _mm_set1_ps(float(n - 1));
#pragma GCC unroll 8
        for (int i = 0; i < N; ++i)
            out[i] = _mm_cvttps_epi32(_mm_min_ps(_mm_max_ps(_mm_mul_ps(c[i], scale), _mm_setzero_ps()), last));
        return;
    }
    const __m128 lo = _mm_set1_ps(-4194304.0f), hi = _mm_set1_ps(4194304.0f);
    const __m128i wrapMask = _mm_set1_epi32(n - 1);
#pragma GCC unroll 8
    for (int i = 0; i < N; ++i) {
        const __m128 u = _mm_min_ps(_mm_max_ps(_mm_mul_ps(c[i], scale), lo), hi);
        const __m128i t = _mm_cvttps_epi32(u);
        // Truncation rounded a negative non-integer up: step down (the mask is −1 there).
        out[i] = _mm_and_si128(_mm_add_epi32(t, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(t), u))), wrapMask);
    }
}

// The texel indices y·width + x of NearestFloat2D::fetch at 4N lanes' (s, t).
template <int N>
[[gnu::always_inline]] inline void nearestIndices(const NearestFloat2D& n, const __m128 (&s)[N], const __m128 (&t)[N],
                           __m128i (&idx)[N]) {
    nearestTexels<N>(s, n.width, n.wrapS, idx);
    if (n.height == 1) return;
    __m128i y[N];
    nearestTexels<N>(t, n.height, n.wrapT, y);
    if (n.widthShift >= 0) {
        const __m128i shift = _mm_cvtsi32_si128(n.widthShift);
#pragma GCC unroll 8
        for (int i = 0; i < N; ++i) idx[i] = _mm_add_epi32(_mm_sll_epi32(y[i], shift), idx[i]);
        return;
    }
    // y·width without SSE4.1's PMULLD: even and odd lanes through PMULUDQ (the products are
    // below 2^31: the level's texel count).
    const __m128i w = _mm_set1_epi32(n.width);
    for (int i = 0; i < N; ++i) {
        const __m128i even = _mm_mul_epu32(y[i], w), odd = _mm_mul_epu32(_mm_srli_epi64(y[i], 32), w);
        const __m128i yw = _mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                                              _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0)));
        idx[i] = _mm_add_epi32(yw, idx[i]);
    }
}

// NearestFloat2D::fetchCube's texel indices at 4N lanes' directions (x, y, z): the face of
// tex::selectCubeFace — X where |x| ≥ |y| and |x| ≥ |z|, else Y where |y| ≥ |z|, else Z, the
// sign's face where the component is ≥ 0 (−0 included; NaN compares false as in the scalar
// code) — its (sc, tc, ma) row of the ARB_texture_cube_map table, s = (sc/|ma| + 1)·½ and
// t = (tc/|ma| + 1)·½ (the face centre where |ma| is not > 0), then the clamped texels of
// nearestTexels and face·n² + y·n + x.
template <int N>
[[gnu::always_inline]] inline void nearestCubeIndices(const NearestFloat2D& n, const __m128 (&x)[N],
                                                      const __m128 (&y)[N], const __m128 (&z)[N], __m128i (&idx)[N]) {
    const __m128 sign = _mm_set1_ps(-0.0f), zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f), half = _mm_set1_ps(0.5f);
    auto sel = [](__m128 m, __m128 a, __m128 b) { return _mm_or_ps(_mm_and_ps(m, a), _mm_andnot_ps(m, b)); };
    __m128 s[N], t[N];
    __m128i face[N];
#pragma GCC unroll 8
    for (int i = 0; i < N; ++i) {
        const __m128 ax = _mm_andnot_ps(sign, x[i]), ay = _mm_andnot_ps(sign, y[i]), az = _mm_andnot_ps(sign, z[i]);
        const __m128 isX = _mm_and_ps(_mm_cmpge_ps(ax, ay), _mm_cmpge_ps(ax, az));
        const __m128 isY = _mm_andnot_ps(isX, _mm_cmpge_ps(ay, az));
        const __m128 isZ = _mm_andnot_ps(_mm_or_ps(isX, isY), _mm_castsi128_ps(_mm_set1_epi32(-1)));
        const __m128 px = _mm_cmpge_ps(x[i], zero), py = _mm_cmpge_ps(y[i], zero), pz = _mm_cmpge_ps(z[i], zero);
        const __m128 nx = _mm_xor_ps(x[i], sign), ny = _mm_xor_ps(y[i], sign), nz = _mm_xor_ps(z[i], sign);
        // sc: X ±: −z / z; Y: x; Z ±: x / −x.   tc: X: −y; Y ±: z / −z; Z: −y.
        const __m128 sc = sel(isX, sel(px, nz, z[i]), sel(isY, x[i], sel(pz, x[i], nx)));
        const __m128 tc = sel(isY, sel(py, z[i], nz), ny);
        const __m128 ma = sel(isX, x[i], sel(isY, y[i], z[i]));
        const __m128 a = _mm_andnot_ps(sign, ma);
        const __m128 ok = _mm_cmpgt_ps(a, zero);
        s[i] = sel(ok, _mm_mul_ps(_mm_add_ps(_mm_div_ps(sc, a), one), half), half);
        t[i] = sel(ok, _mm_mul_ps(_mm_add_ps(_mm_div_ps(tc, a), one), half), half);
        // Face numbers (tex::CubeFace): +X 0, −X 1, +Y 2, −Y 3, +Z 4, −Z 5.
        const __m128i neg = _mm_castps_si128(sel(isX, _mm_andnot_ps(px, _mm_castsi128_ps(_mm_set1_epi32(1))),
                                                 sel(isY, _mm_andnot_ps(py, _mm_castsi128_ps(_mm_set1_epi32(1))),
                                                     _mm_andnot_ps(pz, _mm_castsi128_ps(_mm_set1_epi32(1))))));
        const __m128i axis = _mm_or_si128(_mm_and_si128(_mm_castps_si128(isY), _mm_set1_epi32(2)),
                                          _mm_and_si128(_mm_castps_si128(isZ), _mm_set1_epi32(4)));
        face[i] = _mm_add_epi32(axis, neg);
    }
    __m128i tx[N], ty[N];
    nearestTexels<N>(s, n.width, false, tx);
    nearestTexels<N>(t, n.height, false, ty);
    // face·n² + y·n + x, below 2^31 (six faces of the level); PMULUDQ on even and odd lanes
    // where the width is not a power of two.
    auto mul = [](__m128i v, int k) {
        const __m128i w = _mm_set1_epi32(k);
        const __m128i even = _mm_mul_epu32(v, w), odd = _mm_mul_epu32(_mm_srli_epi64(v, 32), w);
        return _mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                                  _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0)));
    };
#pragma GCC unroll 8
    for (int i = 0; i < N; ++i) {
        const __m128i row = n.widthShift >= 0 ? _mm_sll_epi32(ty[i], _mm_cvtsi32_si128(n.widthShift)) : mul(ty[i], n.width);
        idx[i] = _mm_add_epi32(_mm_add_epi32(mul(face[i], int(n.faceTexels)), row), tx[i]);
    }
}

// NearestFloat2D::fetch at the texel indices, lanes outside `live` zero. Every index is
// inside the level (addressing saw to it), so all four of a quad are read without a
// branch. The tap sum's 0 + texel turns −0 into +0.
template <int N>
[[gnu::always_inline]] inline void nearestLoads(const NearestFloat2D& n, const __m128i (&idx)[N],
                                                const __m128 (&live)[N], __m128 (&x)[N], __m128 (&y)[N],
                                                __m128 (&z)[N], __m128 (&w)[N]) {
    auto index = [](__m128i v, int lane) {
        switch (lane) {  // PSHUFD takes its lane as an immediate
            case 1: v = _mm_shuffle_epi32(v, 0x55); break;
            case 2: v = _mm_shuffle_epi32(v, 0xAA); break;
            case 3: v = _mm_shuffle_epi32(v, 0xFF); break;
            default: break;
        }
        return size_t(uint32_t(_mm_cvtsi128_si32(v)));
    };
    const __m128 zero = _mm_setzero_ps();
    if (n.data1) {
        const float* d = n.data1;
#pragma GCC unroll 8
        for (int i = 0; i < N; ++i) {
            const size_t i0 = index(idx[i], 0), i1 = index(idx[i], 1), i2 = index(idx[i], 2), i3 = index(idx[i], 3);
            x[i] = _mm_and_ps(_mm_add_ps(_mm_setr_ps(d[i0], d[i1], d[i2], d[i3]), zero), live[i]);
            y[i] = n.depth ? x[i] : zero;  // (d, d, d, 1) for depth, else (r, 0, 0, 1)
            z[i] = y[i];
            w[i] = _mm_and_ps(_mm_set1_ps(1.0f), live[i]);
        }
        return;
    }
    for (int i = 0; i < N; ++i) {
        __m128 t0 = _mm_loadu_ps(&n.data4[index(idx[i], 0)].x), t1 = _mm_loadu_ps(&n.data4[index(idx[i], 1)].x);
        __m128 t2 = _mm_loadu_ps(&n.data4[index(idx[i], 2)].x), t3 = _mm_loadu_ps(&n.data4[index(idx[i], 3)].x);
        _MM_TRANSPOSE4_PS(t0, t1, t2, t3);
        x[i] = _mm_and_ps(_mm_add_ps(t0, zero), live[i]);
        y[i] = _mm_and_ps(_mm_add_ps(t1, zero), live[i]);
        z[i] = _mm_and_ps(_mm_add_ps(t2, zero), live[i]);
        w[i] = _mm_and_ps(_mm_add_ps(t3, zero), live[i]);
    }
}

}  // namespace detail

template <int N>
class QuadGroupContext;
template <int N>
class QuadGroupWideContext;

// What a quad program sees: lane i is pixel i of the quad (x + (i & 1), y + (i >> 1)).
// active() are the lanes the program runs for (covered, past the early depth test, not
// discarded); other lanes compute along (their varyings are the planes' extrapolation) but
// fetch nothing and write nothing.
class QuadContext {
  public:
    // The lane types, so that a program written as a template on its context
    // (`template <class Q> void operator()(Q& q) const`, using `typename Q::Float`) runs on
    // one quad here and on a QuadGroupContext below.
    using Float = Float4;
    using Mask = Mask4;
    using Vec3 = Vec3x4;
    using Vec4 = Vec4x4;
    static constexpr int kQuads = 1;

    Mask4 active() const { return Mask4(live_); }
    Vec4x4 varying(int k) const { return Vec4x4::fromLanes(quad_->v[size_t(k)]); }
    // Pixel centres, window z and 1/w per lane (gl_FragCoord).
    const Vec4x4& fragCoord() const { return fragCoord_; }

    // textureLod / SampleLevel per active lane (texunit/program_fetch.h); inactive lanes
    // read zero. `m` narrows the lanes further, as divergent control flow does on the
    // hardware: a lane that has left a loop fetches (and counts) nothing.
    Vec4x4 sampleLevel(int unit, const Vec4x4& c, Float4 lod, Mask4 m = Mask4::fromBits(15)) {
        const detail::BoundUnit& b = this->unit(unit);
        if ((b.nearest.lanes4 || b.nearest.cube) && setup_->path == Path::Fast) {
            const __m128 s[1] = {c.x.v}, t[1] = {c.y.v};
            const __m128 live[1] = {liveLanes(m)};
            __m128i idx[1];
            __m128 x[1], y[1], z[1], w[1];
            if (b.nearest.cube) {
                const __m128 r[1] = {c.z.v};
                detail::nearestCubeIndices<1>(b.nearest, s, t, r, idx);
            } else {
                detail::nearestIndices<1>(b.nearest, s, t, idx);
            }
            detail::nearestLoads<1>(b.nearest, idx, live, x, y, z, w);
            return Vec4x4(Float4(x[0]), Float4(y[0]), Float4(z[0]), Float4(w[0]));
        }
        return sampleLevelLanes(b, c, lod, active_ & ~discarded_ & m.bits());
    }

    // Unit `unit` at varying `k` with λ from that varying over the quad (texture2D, Sample),
    // and the depth compare of level 0 (shadow2D, SampleCmp), per lane in `m`.
    Vec4x4 sample(int unit, int k, Mask4 m = Mask4::fromBits(15));
    Float4 sampleCompare(int unit, const Vec4x4& c, Float4 ref, Mask4 m = Mask4::fromBits(15));

    void discard(Mask4 m) {
        discarded_ |= m.bits() & active_;
        live_ = Mask4::fromBits(active_ & ~discarded_).v;
    }
    void output(int target, const Vec4x4& color, Mask4 m = Mask4::fromBits(15)) {
        if (target < 0 || target >= kMaxColorTargets || !((setup_->declaredTargets >> target) & 1u))
            undeclaredTarget(target);
        const uint32_t lanes = m.bits() & active_ & ~discarded_;
        if (lanes == 15)
            out_[size_t(target)] = color;
        else
            out_[size_t(target)] = select(Mask4::fromBits(lanes), color, out_[size_t(target)]);
        writtenLanes_[size_t(target)] |= lanes;
    }

    // ---- used by the pipeline --------------------------------------------------------------
    void begin(const FragmentContext::Setup& s, const detail::QuadVaryings* quad, uint32_t active,
               const Vec4x4& fragCoord) {
        setup_ = &s;
        quad_ = quad;
        active_ = active;
        discarded_ = 0;
        live_ = Mask4::fromBits(active).v;
        fragCoord_ = fragCoord;
        writtenLanes_ = {};
        fetches_ = {};
    }
    uint32_t runLanes() const { return active_; }
    uint32_t discardedLanes() const { return discarded_; }
    // Bit k: target k written by lane `lane`.
    uint32_t written(int lane) const {
        uint32_t w = 0;
        for (int k = 0; k < kMaxColorTargets; ++k) w |= ((writtenLanes_[size_t(k)] >> lane) & 1u) << k;
        return w;
    }
    uint32_t writtenLanes(int target) const { return writtenLanes_[size_t(target)]; }
    const Vec4x4& outQuad(int target) const { return out_[size_t(target)]; }
    std::array<glm::vec4, kMaxColorTargets> out(int lane) const {
        std::array<glm::vec4, kMaxColorTargets> o{};
        for (int k = 0; k < kMaxColorTargets; ++k) o[size_t(k)] = out_[size_t(k)].lane(lane);
        return o;
    }
    uint32_t fetches(int lane) const { return fetches_[size_t(lane)]; }
    __m128i fetchLanes() const { return _mm_load_si128(reinterpret_cast<const __m128i*>(fetches_.data())); }

  private:
    [[noreturn]] void undeclaredTarget(int target) const;
    [[noreturn]] void undeclaredUnit(int u) const;
    const detail::BoundUnit& unit(int u) const {
        if (u < 0 || u >= kMaxProgramUnits || !((setup_->declaredUnits >> u) & 1u)) undeclaredUnit(u);
        return (*setup_->units)[size_t(u)];
    }
    Vec4x4 sampleLevelLanes(const detail::BoundUnit& b, const Vec4x4& c, Float4 lod, uint32_t lanes);

    template <int>
    friend class QuadGroupContext;
    template <int>
    friend class QuadGroupWideContext;
    // The lanes of a point-sampled fetch: active and in `m`; each counts a fetch.
    __m128 liveLanes(Mask4 m) {
        const __m128 live = _mm_and_ps(live_, m.v);
        __m128i* count = reinterpret_cast<__m128i*>(fetches_.data());
        _mm_store_si128(count, _mm_sub_epi32(_mm_load_si128(count), _mm_castps_si128(live)));
        return live;
    }

    const FragmentContext::Setup* setup_ = nullptr;
    const detail::QuadVaryings* quad_ = nullptr;
    uint32_t active_ = 0, discarded_ = 0;
    __m128 live_ = _mm_setzero_ps();  // active_ & ~discarded_ as lane masks
    Vec4x4 fragCoord_;
    std::array<uint32_t, kMaxColorTargets> writtenLanes_{};  // per target, bit i: lane i
    alignas(16) std::array<uint32_t, 4> fetches_{};  // per lane; the fast fetch adds four at once
    std::array<Vec4x4, kMaxColorTargets> out_{};
};

// ---- quad groups ---------------------------------------------------------------------------
//
// N quads run side by side: every lane type holds N Float4 (quad i in q[i]) and every
// operation is the Float4 operation quad by quad, so lane j of quad i computes exactly what
// it computes when the quad runs alone. What it buys is latency: a search loop is one long
// chain of dependent steps per quad (coordinate, texel index, load, compare, select), and N
// independent chains interleaved keep the core busy while each waits — the way llvmpipe's
// 8-wide JIT code and the G80's warps hide the latency of a fetch.
//
// A program opts in by taking its context as a template parameter and naming its types
// through it (typename Q::Float, Q::Mask, Q::Vec3, Q::Vec4); it must treat lanes alike (no
// lane index, no horizontal operation other than a mask's any()/all() for loop exits —
// which with masked lanes give the same result as per quad). The reference path runs such
// a program one lane at a time on a QuadContext, so the differential tests cover it.

template <int N>
struct MaskQ {
    std::array<Mask4, N> q{};
    Mask4 quad(int i) const { return q[size_t(i)]; }
    static MaskQ allLanes() {
        MaskQ m;
        m.q.fill(Mask4::fromBits(15));
        return m;
    }
    static_assert(4 * N <= 64, "a group's lanes fit the 64 bits of bits()");
    uint64_t bits() const {  // bit 4i + j: lane j of quad i
        uint64_t b = 0;
        for (int i = 0; i < N; ++i) b |= uint64_t(q[size_t(i)].bits()) << (4 * i);
        return b;
    }
    bool any() const { return bits() != 0; }
    bool all() const { return bits() == ~uint64_t(0) >> (64 - 4 * N); }
    template <class Op>
    static MaskQ zip(const MaskQ& a, const MaskQ& b, Op op) {
        MaskQ r;
        for (int i = 0; i < N; ++i) r.q[size_t(i)] = op(a.q[size_t(i)], b.q[size_t(i)]);
        return r;
    }
    friend MaskQ operator&(const MaskQ& a, const MaskQ& b) { return zip(a, b, [](Mask4 x, Mask4 y) { return x & y; }); }
    friend MaskQ operator|(const MaskQ& a, const MaskQ& b) { return zip(a, b, [](Mask4 x, Mask4 y) { return x | y; }); }
    friend MaskQ operator^(const MaskQ& a, const MaskQ& b) { return zip(a, b, [](Mask4 x, Mask4 y) { return x ^ y; }); }
    friend MaskQ andNot(const MaskQ& a, const MaskQ& b) {
        return zip(a, b, [](Mask4 x, Mask4 y) { return andNot(x, y); });
    }
};

template <int N>
struct FloatQ {
    std::array<Float4, N> q{};
    FloatQ() = default;
    FloatQ(float s) { q.fill(Float4(s)); }  // NOLINT: broadcasts like a scalar
    float operator[](int i) const { return q[size_t(i >> 2)][i & 3]; }
    Float4 quad(int i) const { return q[size_t(i)]; }
    void setQuad(int i, Float4 f) { q[size_t(i)] = f; }
    template <class F>
    static FloatQ fromQuads(F f) {  // quad i: f(i)
        FloatQ r;
#pragma GCC unroll 8
        for (int i = 0; i < N; ++i) r.q[size_t(i)] = f(i);
        return r;
    }
    template <class Op>
    static FloatQ zip(const FloatQ& a, const FloatQ& b, Op op) {
        FloatQ r;
        for (int i = 0; i < N; ++i) r.q[size_t(i)] = op(a.q[size_t(i)], b.q[size_t(i)]);
        return r;
    }
    template <class Op>
    static MaskQ<N> compare(const FloatQ& a, const FloatQ& b, Op op) {
        MaskQ<N> r;
        for (int i = 0; i < N; ++i) r.q[size_t(i)] = op(a.q[size_t(i)], b.q[size_t(i)]);
        return r;
    }
    friend FloatQ operator+(const FloatQ& a, const FloatQ& b) { return zip(a, b, [](Float4 x, Float4 y) { return x + y; }); }
    friend FloatQ operator-(const FloatQ& a, const FloatQ& b) { return zip(a, b, [](Float4 x, Float4 y) { return x - y; }); }
    friend FloatQ operator*(const FloatQ& a, const FloatQ& b) { return zip(a, b, [](Float4 x, Float4 y) { return x * y; }); }
    friend FloatQ operator/(const FloatQ& a, const FloatQ& b) { return zip(a, b, [](Float4 x, Float4 y) { return x / y; }); }
    friend FloatQ operator-(const FloatQ& a) { return zip(a, a, [](Float4 x, Float4) { return -x; }); }
    FloatQ& operator+=(const FloatQ& b) { return *this = *this + b; }
    FloatQ& operator-=(const FloatQ& b) { return *this = *this - b; }
    FloatQ& operator*=(const FloatQ& b) { return *this = *this * b; }
    friend MaskQ<N> operator<(const FloatQ& a, const FloatQ& b) { return compare(a, b, [](Float4 x, Float4 y) { return x < y; }); }
    friend MaskQ<N> operator<=(const FloatQ& a, const FloatQ& b) { return compare(a, b, [](Float4 x, Float4 y) { return x <= y; }); }
    friend MaskQ<N> operator>(const FloatQ& a, const FloatQ& b) { return compare(a, b, [](Float4 x, Float4 y) { return x > y; }); }
    friend MaskQ<N> operator>=(const FloatQ& a, const FloatQ& b) { return compare(a, b, [](Float4 x, Float4 y) { return x >= y; }); }
    friend MaskQ<N> operator==(const FloatQ& a, const FloatQ& b) { return compare(a, b, [](Float4 x, Float4 y) { return x == y; }); }
    friend MaskQ<N> operator!=(const FloatQ& a, const FloatQ& b) { return compare(a, b, [](Float4 x, Float4 y) { return x != y; }); }
};

template <int N>
FloatQ<N> select(const MaskQ<N>& m, const FloatQ<N>& a, const FloatQ<N>& b) {
    FloatQ<N> r;
    for (int i = 0; i < N; ++i) r.q[size_t(i)] = select(m.q[size_t(i)], a.q[size_t(i)], b.q[size_t(i)]);
    return r;
}
template <int N>
FloatQ<N> min(const FloatQ<N>& a, const FloatQ<N>& b) {
    return FloatQ<N>::zip(a, b, [](Float4 x, Float4 y) { return min(x, y); });
}
template <int N>
FloatQ<N> max(const FloatQ<N>& a, const FloatQ<N>& b) {
    return FloatQ<N>::zip(a, b, [](Float4 x, Float4 y) { return max(x, y); });
}
template <int N>
FloatQ<N> sqrt(const FloatQ<N>& a) {
    return FloatQ<N>::zip(a, a, [](Float4 x, Float4) { return sqrt(x); });
}
template <int N>
FloatQ<N> abs(const FloatQ<N>& a) {
    return FloatQ<N>::zip(a, a, [](Float4 x, Float4) { return abs(x); });
}

template <int N>
using Vec3Q = Vec3L<FloatQ<N>>;
template <int N>
using Vec4Q = Vec4L<FloatQ<N>>;

namespace detail {

// The group contexts' (QuadGroupContext, QuadGroupWideContext) quad-by-quad sampleLevel:
// filtered samplers, non-power-of-two WRAP, the reference path. The caller copies its
// arguments into storage() on that branch only — storage the compiler cannot move stores
// to (a thread's own) — so that on the fast path the program's temporaries stay in
// registers; run() is kept out of line for the same reason.
template <class Vec4, class Float, class Mask>
struct QuadByQuadSample {
    Vec4 c;
    Float lod;
    Mask m;
    [[RG_NOIPA]] static QuadByQuadSample& storage() {
        static thread_local QuadByQuadSample a;
        return a;
    }
    template <size_t N>
    [[RG_NOIPA, gnu::cold]] Vec4 run(std::array<QuadContext, N>& quads, int unit) const {
        Vec4 r;
        for (int i = 0; i < int(N); ++i)
            r.setQuad(i, quads[size_t(i)].sampleLevel(unit, c.quad(i), lod.quad(i), m.quad(i)));
        return r;
    }
};

}  // namespace detail

// What a program sees of N quads: the QuadContext interface on 4N lanes, each call the
// QuadContext call of every quad (quad i: lanes 4i … 4i + 3).
template <int N>
class QuadGroupContext {
  public:
    using Float = FloatQ<N>;
    using Mask = MaskQ<N>;
    using Vec3 = Vec3Q<N>;
    using Vec4 = Vec4Q<N>;
    static constexpr int kQuads = N;

    Mask active() const {
        Mask m;
        for (int i = 0; i < N; ++i) m.q[size_t(i)] = quads_[size_t(i)].active();
        return m;
    }
    Vec4 varying(int k) const { return each([&](const QuadContext& c) { return c.varying(k); }); }
    Vec4 fragCoord() const { return each([](const QuadContext& c) { return c.fragCoord(); }); }
    // Inlined into the program whatever its size: the quads' chains interleave only there.
    [[gnu::always_inline]] Vec4 sampleLevel(int unit, const Vec4& c, const Float& lod, const Mask& m = Mask::allLanes()) {
        const detail::BoundUnit& b = quads_[0].unit(unit);
        if (!((b.nearest.lanes4 || b.nearest.cube) && quads_[0].setup_->path == Path::Fast)) [[unlikely]] {
            // Copied on this branch only, into storage the compiler cannot move stores
            // to (a thread's own): the caller's temporaries are only read, so they stay
            // in registers on the fast path.
            SlowArgs& a = SlowArgs::storage();
            for (int i = 0; i < N; ++i) {  // quad by quad: no aggregate copy
                a.c.setQuad(i, c.quad(i));
                a.lod.q[size_t(i)] = lod.q[size_t(i)];
                a.m.q[size_t(i)] = m.q[size_t(i)];
            }
            return a.run(quads_, unit);
        }
        __m128 s[N], t[N], live[N];
        for (int i = 0; i < N; ++i) {
            s[i] = c.x.q[size_t(i)].v;
            t[i] = c.y.q[size_t(i)].v;
            live[i] = quads_[size_t(i)].liveLanes(m.q[size_t(i)]);
        }
        __m128i idx[N];
        __m128 x[N], y[N], z[N], w[N];
        if (b.nearest.cube) {
            __m128 r[N];
            for (int i = 0; i < N; ++i) r[i] = c.z.q[size_t(i)].v;
            detail::nearestCubeIndices<N>(b.nearest, s, t, r, idx);
        } else {
            detail::nearestIndices<N>(b.nearest, s, t, idx);
        }
        detail::nearestLoads<N>(b.nearest, idx, live, x, y, z, w);
        auto lanes = [](const __m128(&v)[N]) { return FloatQ<N>::fromQuads([&](int i) { return Float4(v[i]); }); };
        return Vec4(lanes(x), lanes(y), lanes(z), lanes(w));
    }
    Vec4 sample(int unit, int k, const Mask& m = Mask::allLanes()) {
        Vec4 r;
        for (int i = 0; i < N; ++i) r.setQuad(i, quads_[size_t(i)].sample(unit, k, m.q[size_t(i)]));
        return r;
    }
    Float sampleCompare(int unit, const Vec4& c, const Float& ref, const Mask& m = Mask::allLanes()) {
        Float r;
        for (int i = 0; i < N; ++i)
            r.q[size_t(i)] = quads_[size_t(i)].sampleCompare(unit, c.quad(i), ref.q[size_t(i)], m.q[size_t(i)]);
        return r;
    }
    void discard(const Mask& m) {
        for (int i = 0; i < N; ++i) quads_[size_t(i)].discard(m.q[size_t(i)]);
    }
    void output(int target, const Vec4& color, const Mask& m = Mask::allLanes()) {
        for (int i = 0; i < N; ++i) quads_[size_t(i)].output(target, color.quad(i), m.q[size_t(i)]);
    }

    // ---- used by the pipeline --------------------------------------------------------------
    QuadContext& quad(int i) { return quads_[size_t(i)]; }
    void beginGroup() {}  // the quads keep their own lanes and counts
    void endGroup() {}

  private:
    using SlowArgs = detail::QuadByQuadSample<Vec4, Float, Mask>;
    template <class F>
    Vec4 each(F f) const {
        Vec4 r;
        for (int i = 0; i < N; ++i) r.setQuad(i, f(quads_[size_t(i)]));
        return r;
    }
    std::array<QuadContext, N> quads_;
};

}  // namespace rg::raster
