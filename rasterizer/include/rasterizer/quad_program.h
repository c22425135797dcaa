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

namespace rg::raster {

struct Mask4 {
    __m128 v;
    Mask4() : v(_mm_setzero_ps()) {}
    explicit Mask4(__m128 m) : v(m) {}
    static Mask4 fromBits(uint32_t bits) {
        return Mask4(_mm_castsi128_ps(_mm_set_epi32(bits & 8 ? -1 : 0, bits & 4 ? -1 : 0,
                                                    bits & 2 ? -1 : 0, bits & 1 ? -1 : 0)));
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

struct Vec3x4 {
    Float4 x, y, z;
    Vec3x4() = default;
    Vec3x4(Float4 a, Float4 b, Float4 c) : x(a), y(b), z(c) {}
    friend Vec3x4 operator+(const Vec3x4& a, const Vec3x4& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
    friend Vec3x4 operator-(const Vec3x4& a, const Vec3x4& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
    friend Vec3x4 operator*(const Vec3x4& a, Float4 s) { return {a.x * s, a.y * s, a.z * s}; }
    friend Vec3x4 operator*(const Vec3x4& a, const Vec3x4& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
};
// glm::dot's order: (x·x + y·y) + z·z.
inline Float4 dot(const Vec3x4& a, const Vec3x4& b) { return (a.x * b.x + a.y * b.y) + a.z * b.z; }
inline Vec3x4 select(Mask4 m, const Vec3x4& a, const Vec3x4& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}

struct Vec4x4 {
    Float4 x, y, z, w;
    Vec4x4() = default;
    Vec4x4(Float4 a, Float4 b, Float4 c, Float4 d) : x(a), y(b), z(c), w(d) {}
    // Four per-pixel vectors (lane i = pixel i) as one vector of lanes.
    static Vec4x4 fromLanes(const std::array<glm::vec4, 4>& p) {
        return {Float4::lanes(p[0].x, p[1].x, p[2].x, p[3].x), Float4::lanes(p[0].y, p[1].y, p[2].y, p[3].y),
                Float4::lanes(p[0].z, p[1].z, p[2].z, p[3].z), Float4::lanes(p[0].w, p[1].w, p[2].w, p[3].w)};
    }
    Vec3x4 xyz() const { return {x, y, z}; }
    glm::vec4 lane(int i) const { return {x[i], y[i], z[i], w[i]}; }
    friend Vec4x4 operator+(const Vec4x4& a, const Vec4x4& b) {
        return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w};
    }
    friend Vec4x4 operator-(const Vec4x4& a, const Vec4x4& b) {
        return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w};
    }
    friend Vec4x4 operator*(const Vec4x4& a, Float4 s) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }
    friend Vec4x4 operator*(const Vec4x4& a, const Vec4x4& b) {
        return {a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w};
    }
};
inline Vec4x4 select(Mask4 m, const Vec4x4& a, const Vec4x4& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z), select(m, a.w, b.w)};
}

// What a quad program sees: lane i is pixel i of the quad (x + (i & 1), y + (i >> 1)).
// active() are the lanes the program runs for (covered, past the early depth test, not
// discarded); other lanes compute along (their varyings are the planes' extrapolation) but
// fetch nothing and write nothing.
class QuadContext {
  public:
    Mask4 active() const { return Mask4::fromBits(active_ & ~discarded_); }
    Vec4x4 varying(int k) const { return Vec4x4::fromLanes(quad_->v[size_t(k)]); }
    // Pixel centres, window z and 1/w per lane (gl_FragCoord).
    const Vec4x4& fragCoord() const { return fragCoord_; }

    // textureLod / SampleLevel per active lane (texunit/program_fetch.h); inactive lanes
    // read zero. `m` narrows the lanes further, as divergent control flow does on the
    // hardware: a lane that has left a loop fetches (and counts) nothing.
    Vec4x4 sampleLevel(int unit, const Vec4x4& c, Float4 lod, Mask4 m = Mask4::fromBits(15)) {
        const detail::BoundUnit& b = this->unit(unit);
        const uint32_t lanes = active_ & ~discarded_ & m.bits();
        Vec4x4 r;
        if (b.nearest.valid() && setup_->path == Path::Fast && fetchNearest4(b.nearest, c, lanes, r)) return r;
        return sampleLevelLanes(b, c, lod, lanes);
    }

    // Unit `unit` at varying `k` with λ from that varying over the quad (texture2D, Sample),
    // and the depth compare of level 0 (shadow2D, SampleCmp), per lane in `m`.
    Vec4x4 sample(int unit, int k, Mask4 m = Mask4::fromBits(15));
    Float4 sampleCompare(int unit, const Vec4x4& c, Float4 ref, Mask4 m = Mask4::fromBits(15));

    void discard(Mask4 m) { discarded_ |= m.bits() & active_; }
    void output(int target, const Vec4x4& color, Mask4 m = Mask4::fromBits(15)) {
        if (target < 0 || target >= kMaxColorTargets || !((setup_->declaredTargets >> target) & 1u))
            undeclaredTarget(target);
        const uint32_t lanes = m.bits() & active_ & ~discarded_;
        const Mask4 w = Mask4::fromBits(lanes);
        out_[size_t(target)] = select(w, color, out_[size_t(target)]);
        writtenLanes_[size_t(target)] |= lanes;
    }

    // ---- used by the pipeline --------------------------------------------------------------
    void begin(const FragmentContext::Setup& s, const detail::QuadVaryings* quad, uint32_t active,
               const Vec4x4& fragCoord) {
        setup_ = &s;
        quad_ = quad;
        active_ = active;
        discarded_ = 0;
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

  private:
    [[noreturn]] void undeclaredTarget(int target) const;
    [[noreturn]] void undeclaredUnit(int u) const;
    const detail::BoundUnit& unit(int u) const {
        if (u < 0 || u >= kMaxProgramUnits || !((setup_->declaredUnits >> u) & 1u)) undeclaredUnit(u);
        return (*setup_->units)[size_t(u)];
    }
    Vec4x4 sampleLevelLanes(const detail::BoundUnit& b, const Vec4x4& c, Float4 lod, uint32_t lanes);

    // detail::nearestTexel on four lanes: ⌊c·n⌋ (NaN → 0, clamped to ±2^22), then WRAP (a
    // power-of-two mask) or CLAMP_TO_EDGE. Clamping the float to [0, n − 1] before the floor
    // equals clamping the floored integer. Non-power-of-two WRAP: false (lane by lane).
    static bool nearestTexels4(__m128 c, int n, bool wrap, __m128i& out) {
        if (wrap && (n & (n - 1)) != 0) return false;
        __m128 u = _mm_mul_ps(c, _mm_set1_ps(float(n)));
        u = _mm_and_ps(u, _mm_cmpord_ps(u, u));  // NaN → 0
        if (wrap)
            u = _mm_max_ps(_mm_min_ps(u, _mm_set1_ps(4194304.0f)), _mm_set1_ps(-4194304.0f));
        else
            u = _mm_max_ps(_mm_min_ps(u, _mm_set1_ps(float(n - 1))), _mm_setzero_ps());
        __m128i i = _mm_cvttps_epi32(u);
        // Truncation rounded a negative non-integer up: step down (the mask is −1 there).
        i = _mm_add_epi32(i, _mm_castps_si128(_mm_cmpgt_ps(_mm_cvtepi32_ps(i), u)));
        if (wrap) i = _mm_and_si128(i, _mm_set1_epi32(n - 1));
        out = i;
        return true;
    }
    // Point sampling (detail::NearestFloat2D) of the four lanes; inactive lanes read zero.
    // Every lane's texel is inside the level (addressing saw to it), so all four are read
    // and the inactive ones zeroed afterwards, without a branch per lane.
    bool fetchNearest4(const detail::NearestFloat2D& n, const Vec4x4& c, uint32_t lanes, Vec4x4& r) {
        __m128i xi, yi = _mm_setzero_si128();
        if (!nearestTexels4(c.x.v, n.width, n.wrapS, xi)) return false;
        if (n.height != 1 && !nearestTexels4(c.y.v, n.height, n.wrapT, yi)) return false;
        alignas(16) int32_t xs[4], ys[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(xs), xi);
        _mm_store_si128(reinterpret_cast<__m128i*>(ys), yi);
        size_t idx[4];
        for (int i = 0; i < 4; ++i) idx[i] = size_t(ys[i]) * size_t(n.width) + size_t(xs[i]);
        const __m128 live = Mask4::fromBits(lanes).v;
        for (int i = 0; i < 4; ++i) fetches_[size_t(i)] += (lanes >> i) & 1u;
        const __m128 z = _mm_setzero_ps();
        if (n.data1) {
            // The tap sum's 0 + texel: −0 becomes +0.
            const Float4 v(_mm_and_ps(
                _mm_add_ps(_mm_setr_ps(n.data1[idx[0]], n.data1[idx[1]], n.data1[idx[2]], n.data1[idx[3]]), z),
                live));
            const Float4 one(_mm_and_ps(_mm_set1_ps(1.0f), live));
            r = n.depth ? Vec4x4(v, v, v, one) : Vec4x4(v, Float4(0.0f), Float4(0.0f), one);
            return true;
        }
        __m128 t0 = _mm_loadu_ps(&n.data4[idx[0]].x), t1 = _mm_loadu_ps(&n.data4[idx[1]].x);
        __m128 t2 = _mm_loadu_ps(&n.data4[idx[2]].x), t3 = _mm_loadu_ps(&n.data4[idx[3]].x);
        _MM_TRANSPOSE4_PS(t0, t1, t2, t3);
        r = Vec4x4(Float4(_mm_and_ps(_mm_add_ps(t0, z), live)), Float4(_mm_and_ps(_mm_add_ps(t1, z), live)),
                   Float4(_mm_and_ps(_mm_add_ps(t2, z), live)), Float4(_mm_and_ps(_mm_add_ps(t3, z), live)));
        return true;
    }

    const FragmentContext::Setup* setup_ = nullptr;
    const detail::QuadVaryings* quad_ = nullptr;
    uint32_t active_ = 0, discarded_ = 0;
    Vec4x4 fragCoord_;
    std::array<uint32_t, kMaxColorTargets> writtenLanes_{};  // per target, bit i: lane i
    std::array<uint32_t, 4> fetches_{};
    std::array<Vec4x4, kMaxColorTargets> out_{};
};

}  // namespace rg::raster
