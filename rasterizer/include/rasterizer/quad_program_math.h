// The arithmetic a program writes once for every lane type: a plain float and bool (the
// scalar reference twin the tests run), Float4 and Mask4 (one quad, quad_program.h) and the
// quad groups (FloatQ, FloatW). The scalar overloads stand beside the lane types' own, so
// that `select(m, a, b)`, `min`, `max`, `sqrt`, `abs`, `andNot` and `anyLane` name the same
// operation whichever type a program is instantiated with; the vector helpers and Snell's
// law below are written in those terms only.
//
// Every operation is IEEE-exact (+ − × ÷ √, compares, selects, min/max as std::min and
// std::max order them), so every lane type computes the same bits. They live in a namespace
// of their own, which a program's namespace takes in whole (`using namespace
// raster::lane_math;`, demos/tir/tir_search.h, demos/impostors/impostor_search.h): a call
// with plain floats finds the scalar overloads there, a call with lane types finds theirs
// in rg::raster by argument-dependent lookup.
#pragma once

#include <cmath>

#include "rasterizer/quad_program.h"

namespace rg::raster::lane_math {

// ---- the scalar lane type: overloads beside Float4's and Mask4's ------------------------
inline float select(bool m, float a, float b) { return m ? a : b; }
inline float min(float a, float b) { return (b < a) ? b : a; }  // std::min's order
inline float max(float a, float b) { return (a < b) ? b : a; }
inline float sqrt(float a) { return std::sqrt(a); }
inline float abs(float a) { return std::fabs(a); }
inline bool andNot(bool a, bool b) { return a && !b; }
inline bool anyLane(bool m) { return m; }
template <class M>
bool anyLane(const M& m) {
    return m.any();
}

// ---- vectors over any lane type -----------------------------------------------------------
template <class M, class F>
Vec3L<F> select3(const M& m, const Vec3L<F>& a, const Vec3L<F>& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z)};
}
template <class M, class F>
Vec4L<F> select4(const M& m, const Vec4L<F>& a, const Vec4L<F>& b) {
    return {select(m, a.x, b.x), select(m, a.y, b.y), select(m, a.z, b.z), select(m, a.w, b.w)};
}
template <class F>
F dot3(const Vec3L<F>& a, const Vec3L<F>& b) {
    return (a.x * b.x + a.y * b.y) + a.z * b.z;  // glm::dot's order
}
template <class F>
F length3(const Vec3L<F>& v) {
    return sqrt(dot3(v, v));
}
template <class F>
Vec3L<F> normalize3(const Vec3L<F>& v) {
    const F inv = F(1.0f) / sqrt(dot3(v, v));
    return v * inv;
}

// ---- refraction, as the programs of the refraction papers share it -------------------------

// The normal of a surface turned against the direction d (the ray).
template <class F>
Vec3L<F> facing(const Vec3L<F>& n, const Vec3L<F>& d) {
    const auto away = dot3(n, d) > F(0.0f);
    return select3(away, n * F(-1.0f), n);
}

// Snell's law with the normal n against d (dot(d, n) < 0) and eta = η_i/η_t, as raycore's
// refractDir writes it: k = 1 − η²(1 − cos²); total internal reflection (`tir`) where
// k < 0 — θ_i above the critical angle sin⁻¹(η_t/η_i), Davis & Wyman 2007 Figure 4 — and
// there the mirror direction d + 2cos·n.
template <class F, class M>
Vec3L<F> refractOrReflect(const Vec3L<F>& d, const Vec3L<F>& n, float eta, M& tir) {
    const F cosI = -dot3(d, n);
    const F k = F(1.0f) - F(eta * eta) * (F(1.0f) - cosI * cosI);
    tir = k < F(0.0f);
    const Vec3L<F> t = normalize3(d * F(eta) + n * (F(eta) * cosI - sqrt(max(k, F(0.0f)))));
    const Vec3L<F> r = d + n * (F(2.0f) * cosI);
    return select3(tir, r, t);
}

}  // namespace rg::raster::lane_math
