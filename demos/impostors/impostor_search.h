// The per-fragment arithmetic of Dancsik & Minarik (002 §3, §4.1, §4.2), one definition for
// every lane type: a plain float (the scalar twin the tests run), Float4 (a quad) and the
// quad groups of the fast path (FloatQ, FloatW). Only IEEE-exact operations are used
// (+ − × ÷ √, compares, selects, min/max), so every lane type computes the same bits
// (rasterizer/quad_program.h). docs/hardware.md, "impostors: the secant search", writes the
// steps out.
//
//   distance impostor: a cube map seen from a reference point o (o = 0 in the map's frame),
//   texel = (rgb or normal, distance of the surface seen along that direction)
//
//   ray x + d·R ─▶ r = the texel along R ─▶ p: the plane through r ⟂ R ─▶ p' ─▶ l on the
//   line r–p' ─▶ iterations: the line through the surface points of the last undershoot
//   and the last overshoot (r, "the ideal point at infinity", until an overshoot is seen;
//   x's own surface point until an undershoot is) ─▶ the last point and its texel
#pragma once

#include <cstdint>

#include "rasterizer/quad_program_math.h"

namespace rg::impostors {

using raster::Vec3L;
using raster::Vec4L;
// The lane-generic arithmetic the refraction programs share (rasterizer/quad_program_math.h):
// the scalar lane type's overloads, the vector helpers, Snell's law with total internal
// reflection.
using namespace raster::lane_math;

// A 3×3 matrix of constants (rows) times a vector: (m₀·x + m₁·y) + m₂·z per row.
template <class F>
Vec3L<F> mul3(const float (&m)[9], const Vec3L<F>& v) {
    return {(v.x * F(m[0]) + v.y * F(m[1])) + v.z * F(m[2]), (v.x * F(m[3]) + v.y * F(m[4])) + v.z * F(m[5]),
            (v.x * F(m[6]) + v.y * F(m[7])) + v.z * F(m[8])};
}
// Its transpose times a vector (the inverse of a rotation).
template <class F>
Vec3L<F> mulT3(const float (&m)[9], const Vec3L<F>& v) {
    return {(v.x * F(m[0]) + v.y * F(m[3])) + v.z * F(m[6]), (v.x * F(m[1]) + v.y * F(m[4])) + v.z * F(m[7]),
            (v.x * F(m[2]) + v.y * F(m[5])) + v.z * F(m[8])};
}
template <class F>
Vec3L<F> splat3(const float (&v)[3]) {
    return {F(v[0]), F(v[1]), F(v[2])};
}

// The mirror direction d + n·2cos (n against d, cos = −d·n).
template <class F>
Vec3L<F> reflect3(const Vec3L<F>& d, const Vec3L<F>& n) {
    return d + n * (F(2.0f) * -dot3(d, n));
}

// 002 §3's "approximation of the Fresnel function": Schlick's F0 + (1 − F0)(1 − cos)⁵,
// F0 = ((η − 1)/(η + 1))².
template <class F>
F fresnelSchlick(const F& cosI, float f0) {
    const F m = F(1.0f) - min(max(cosI, F(0.0f)), F(1.0f));
    const F m2 = m * m;
    return F(f0) + F(1.0f - f0) * (m2 * m2 * m);
}

// e^(−z) for z ≥ 0 from + − × only (the G80's EX2 is not emulated bit for bit; this is the
// program's own arithmetic): the Taylor polynomial of degree 4 at w = min(z, 16)/16, then
// squared four times (e^(−z) = (e^(−z/16))¹⁶); relative error below 10⁻⁵ for z ≤ 2 (a glass
// chess piece: z ≤ 0.5), 2 % at the clamp.
template <class F>
F expNeg(const F& z) {
    const F w = min(max(z, F(0.0f)), F(16.0f)) * F(0.0625f);
    F e = F(1.0f) - w * (F(1.0f) - w * (F(0.5f) - w * (F(1.0f / 6.0f) - w * F(1.0f / 24.0f))));
    e = e * e;
    e = e * e;
    e = e * e;
    return e * e;
}

// ---- the secant search (002 §3, after Szirmay-Kalos et al. 2005) ---------------------------

// The result of a search: the last point on the ray (x + d·R, the map's frame) and the
// texel read along its direction (rgb or normal; w the stored distance), and whether the
// lane ever saw an undershoot and an overshoot (a bracketed root).
template <class F, class M>
struct SearchResult {
    Vec3L<F> point;
    F d;
    Vec4L<F> texel;
    M bracketed;
};

// The accuracy ratio of 002 Figure 1 for a ray point y and the distance w stored along its
// direction: a = |y|/|y'| = |y|/w; < 1 an undershoot (y in front of the surface), > 1 an
// overshoot, 1 a hit. (An empty texel, w = 0, is an overshoot: +∞.)
template <class F>
F distanceRatio(const Vec3L<F>& y, const F& stored) {
    return length3(y) / stored;
}

// One step of the search: the ray parameter where the ray meets the line through the last
// undershoot (dU, aU) and the last overshoot (dO, aO) in the plane of the ray and o —
// with the ratio a linear along the ray between them, as it is for a planar surface:
// d = dU + (dO − dU)·(1 − aU)/(aO − aU), always within the bracket. Lanes with aO = aU keep
// `fallback`; the result is clamped to d ≥ 0 (max(0, d) also maps NaN to 0).
template <class F>
F secantStep(const F& dU, const F& aU, const F& dO, const F& aO, const F& fallback) {
    const F den = aO - aU;
    const F d = dU + (dO - dU) * ((F(1.0f) - aU) / den);
    return max(F(0.0f), select(den != F(0.0f), d, fallback));
}

// The step towards "the ideal point at infinity", "surely an overshooting point" whose
// surface point is r: the ray meets the line through r (|r| along R) and the sample's own
// surface point y' = y/a where d = d_y + |r|·(1 − a) (002 Figure 2: l from r and p').
template <class F>
F stepTowardsInfinity(const F& dy, const F& ay, const F& rl) {
    return max(F(0.0f), dy + rl * (F(1.0f) - ay));
}

// 002 §3 and Figure 2, after Szirmay-Kalos et al. 2005. `fetch(dir, live)` reads the map
// along a direction of its frame (lanes outside `live` read nothing).
//
//   r    the texel along R (classical environment mapping), |r| its distance
//   p    "assume that the environment surface at point r is perpendicular to R":
//        d_p = |r| − x·R
//   l    "on the line defined by r and p'": d_l = d_p + |r|·(1 − a_p)
//   then `iterations` times: the last undershoot and the last overshoot seen (with no
//        overshoot yet, the ideal point at infinity: the step through r; with no undershoot
//        yet, "we can use x": d = 0 at its own ratio, read once) give the next point.
//
// A search reads 3 + iterations texels (one more where x is read).
//
// `seeded`: x is not inside the surface but on it (a refracted ray's entry point in the
// refractor map, Figure 3: x is a root itself, ratio 1, and "use x" would stop there) or
// outside it (§4.1: the far point of the refractor's box). The undershoot is then seeded
// with the ray's point nearest the reference point, read first (one more texel) — inside
// the refractor wherever the ray crosses its middle — and an overshoot before the last
// undershoot (in front of the refractor's far side) is no bracket for the root sought, the
// last crossing from inside to outside, and is ignored.
template <class F, class M, class Fetch>
SearchResult<F, M> secantSearch(const Vec3L<F>& x, const Vec3L<F>& R, int iterations, const M& live, Fetch&& fetch,
                                bool seeded = false) {
    SearchResult<F, M> res;
    const F xR = dot3(x, R);
    // The brackets: the last undershoot (dU, aU) and the last overshoot (dO, aO).
    M hasUnder = M(), hasOver = M();
    F dU(0.0f), aU(0.0f), dO(0.0f), aO(0.0f);
    if (seeded) {
        const F dc = max(F(0.0f), -xR);
        const Vec3L<F> c = x + R * dc;
        const F ac = distanceRatio(c, fetch(c, live).w);
        hasUnder = live & (ac < F(1.0f));
        dU = dc;
        aU = ac;
    }
    // r: classical environment mapping's texel along R; its distance |r|.
    const F rl = fetch(R, live).w;
    // p: the plane through r perpendicular to R.
    const F dp = max(F(0.0f), rl - xR);
    const Vec3L<F> p = x + R * dp;
    const F ap = distanceRatio(p, fetch(p, live).w);
    auto classify = [&](const F& d, const F& a) {
        const M under = live & (a < F(1.0f));
        M over = andNot(live, under);
        if (seeded) over = andNot(over, hasUnder & (d < dU));
        dU = select(under, d, dU);
        aU = select(under, a, aU);
        dO = select(over, d, dO);
        aO = select(over, a, aO);
        hasUnder = hasUnder | under;
        hasOver = hasOver | over;
    };
    classify(dp, ap);
    // l: on the line through r and p'.
    F d = stepTowardsInfinity(dp, ap, rl);
    Vec3L<F> y = x + R * d;
    Vec4L<F> t = fetch(y, live);
    M xRead = M();
    for (int i = 0; i < iterations; ++i) {
        classify(d, distanceRatio(y, t.w));
        // No undershoot yet: x itself at its own ratio (read once).
        const M needX = andNot(andNot(live, hasUnder), xRead);
        if (anyLane(needX)) {
            const F ax = distanceRatio(x, fetch(x, needX).w);
            dU = select(needX, F(0.0f), dU);
            aU = select(needX, ax, aU);
            xRead = xRead | needX;
        }
        d = select(hasOver, secantStep(dU, aU, dO, aO, d), stepTowardsInfinity(dU, aU, rl));
        y = x + R * d;
        t = fetch(y, live);
    }
    res.point = y;
    res.d = d;
    res.texel = t;
    res.bracketed = hasUnder & hasOver;
    return res;
}

// ---- the search from outside (002 §4.1, Figure 4) ------------------------------------------

// The slab test of the ray y + t·R against the box [lo, hi] (the map's frame): entry and
// exit parameters; hit where tFar ≥ max(tNear, 0). Directions with a zero component get
// ±∞ from the division, which the slabs handle (no NaN: the origin is never on a slab
// plane in that component with R = 0 unless it is inside it, where (lo − y)·∞ is ±∞).
template <class F, class M>
struct BoxSpan {
    F tNear, tFar;
    M hit;
};
template <class F, class M>
BoxSpan<F, M> rayBox(const Vec3L<F>& y, const Vec3L<F>& R, const float (&lo)[3], const float (&hi)[3]) {
    BoxSpan<F, M> s;
    const F ix = F(1.0f) / R.x, iy = F(1.0f) / R.y, iz = F(1.0f) / R.z;
    const F ax = (F(lo[0]) - y.x) * ix, bx = (F(hi[0]) - y.x) * ix;
    const F ay = (F(lo[1]) - y.y) * iy, by = (F(hi[1]) - y.y) * iy;
    const F az = (F(lo[2]) - y.z) * iz, bz = (F(hi[2]) - y.z) * iz;
    s.tNear = max(max(min(ax, bx), min(ay, by)), min(az, bz));
    s.tFar = min(min(max(ax, bx), max(ay, by)), max(az, bz));
    s.hit = s.tFar >= max(s.tNear, F(0.0f));
    return s;
}

// A hit of a ray with a refractor found by searching its distance map from outside: the
// point and the normal (both in the map's frame), the ray parameter, whether it is valid.
template <class F, class M>
struct OutsideHit {
    Vec3L<F> point, normal;
    F t;
    M valid;
    M boxHit;  // the ray met the bounding box (a search ran)
};

// 002 §4.1: "we will use a ray starting from the farthest intersection point [with the
// bounding box] but opposite to the direction of the ray"; the point found is "invalid
// when it is farther from the ray than a given small epsilon" — the stored surface point
// along the found direction against the ray's line. Lanes that miss the box fetch nothing.
template <class F, class M, class Fetch>
OutsideHit<F, M> outsideSearch(const Vec3L<F>& y, const Vec3L<F>& R, const float (&lo)[3], const float (&hi)[3],
                               float epsilon, int iterations, const M& live, Fetch&& fetch) {
    OutsideHit<F, M> h;
    const BoxSpan<F, M> box = rayBox<F, M>(y, R, lo, hi);
    h.boxHit = live & box.hit;
    h.valid = h.boxHit;
    h.t = F(0.0f);
    h.point = y;
    h.normal = R;
    if (!anyLane(h.boxHit)) return h;
    const Vec3L<F> x = y + R * box.tFar;
    const Vec3L<F> back = R * F(-1.0f);
    const SearchResult<F, M> s = secantSearch(x, back, iterations, h.boxHit, fetch, true);
    // The stored surface point along the found direction, and its distance from the ray.
    const Vec3L<F> surface = normalize3(s.point) * s.texel.w;
    const Vec3L<F> rel = surface - y;
    const F along = dot3(rel, R);
    const Vec3L<F> off = rel - R * along;
    h.t = select(h.boxHit, box.tFar - s.d, F(0.0f));
    h.point = s.point;
    h.normal = normalize3(Vec3L<F>(s.texel.x, s.texel.y, s.texel.z));
    h.valid = h.boxHit & (dot3(off, off) <= F(epsilon * epsilon)) & (h.t >= F(0.0f));
    return h;
}

}  // namespace rg::impostors
