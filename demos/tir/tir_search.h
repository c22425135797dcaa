// The per-fragment algorithm of Davis & Wyman 2007 (004 §3), one definition for every lane
// type: a plain float (the scalar reference twin the tests run), Float4 (a quad), and the
// quad groups of the fast path (FloatQ, FloatW). Only IEEE-exact operations are used
// (+ − × ÷ √, compares, selects, min/max), so every lane type computes the same bits
// (rasterizer/quad_program.h). The arithmetic is written out in docs/hardware.md,
// "tir: the image-space search".
//
//   front fragment p, n ──refract──▶ T ─┬─▶ clip p+εT … frustum exit ─▶ binary search of the
//                                        │   back map (and the front map) ─▶ candidate hit,
//                                        │   its normal ─▶ refract out, or reflect (TIR) and
//                                        └── repeat, up to `bounces` segments
//   exit ray ──▶ binary search of the nearby-geometry map ─▶ its colour, else the environment
//
// Maps (RGBA16F, rendered from the eye): xyz the eye-space normal (back and front maps) or
// the colour (nearby map), w the linear depth −z_eye/far; 1 where nothing was drawn (the
// far plane, the clear value).
#pragma once

#include <cstdint>

#include "rasterizer/quad_program_math.h"

namespace rg::tir {

using raster::Vec3L;
using raster::Vec4L;
// The lane-generic arithmetic the refraction programs share (rasterizer/quad_program_math.h):
// the scalar lane type's overloads, the vector helpers, Snell's law with total internal
// reflection.
using namespace raster::lane_math;

// The units the final pass reads.
constexpr int kUnitBack = 0, kUnitFront = 1, kUnitNearby = 2, kUnitEnv = 3;

// Everything the search reads besides the maps: the fragment program's constants. Plain
// data, so a program's bytes are its constants (traces record them that way).
struct SearchConstants {
    // The projection, eye → clip (Direct3D: 0 ≤ z ≤ w): x_c = px·x, y_c = py·y,
    // z_c = pz·z + pw, w_c = −z; and 1/px, 1/py for the way back.
    float px = 1, py = 1, pz = -1, pw = 0;
    float invPx = 1, invPy = 1;
    float far = 100, invFar = 0.01f;  // linear depth = w_c / far
    float eta = 1.5f;                 // the refractor's index (air outside)
    float epsilon = 1e-3f;            // start offset along each ray (004 §3: "acne")
    float cosMiss = 0.9848078f;       // a candidate less aligned with the ray misses (10°)
    float minDistance2 = 1e-6f;       // a candidate nearer the ray's origin is no hit
    int32_t bounces = 3;              // segments inside the object searched (Table 1: 1–4)
    int32_t itersFirst = 8, itersLater = 5;  // 004 §4: "8 iterations … and 5 …"
    int32_t itersNearby = 8;
    int32_t frontAndBack = 0;         // also search the front map (Figure 11)
    int32_t searchNearby = 1;         // exit rays search the nearby map before the environment
    float eyeToWorld[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // rows: the view's rotation inverted
};

// Clip-space coordinates of a point (w = 1) or a direction (w = 0).
template <class F>
struct Clip {
    F x, y, z, w;
};
template <class F>
Clip<F> toClip(const SearchConstants& k, const Vec3L<F>& p) {
    return {p.x * F(k.px), p.y * F(k.py), p.z * F(k.pz) + F(k.pw), -p.z};
}
template <class F>
Clip<F> toClipDirection(const SearchConstants& k, const Vec3L<F>& d) {
    return {d.x * F(k.px), d.y * F(k.py), d.z * F(k.pz), -d.z};
}

// The ray s + t·d (clip space) leaves the view frustum (−w ≤ x, y ≤ w, 0 ≤ z ≤ w) at the
// least t where a plane's a + b·t turns negative (b < 0): 004 §3, Figure 3a, "clip the ray
// against the viewing frustum and use the clipping point as the endpoint".
template <class F>
F frustumExit(const Clip<F>& s, const Clip<F>& d) {
    F t(3.0e38f);
    auto plane = [&](const F& a, const F& b) { t = select(b < F(0.0f), min(t, -a / b), t); };
    plane(s.w + s.x, d.w + d.x);
    plane(s.w - s.x, d.w - d.x);
    plane(s.w + s.y, d.w + d.y);
    plane(s.w - s.y, d.w - d.y);
    plane(s.z, d.z);
    plane(s.w - s.z, d.w - d.z);
    return max(t, F(0.0f));
}

// Map coordinates of a clip-space point: u = ½ + ½·x/w, v = ½ − ½·y/w (row 0 at the top,
// the Direct3D viewport's y flip), the texel the rasterizer wrote that point's pixel into.
template <class F>
void mapCoords(const F& x, const F& y, const F& w, F& u, F& v) {
    const F inv = F(1.0f) / w;
    u = F(0.5f) + F(0.5f) * (x * inv);
    v = F(0.5f) - F(0.5f) * (y * inv);
}

// The eye-space point of map coordinates (u, v) at linear depth d: the inverse of toClip
// and mapCoords.
template <class F>
Vec3L<F> unproject(const SearchConstants& k, const F& u, const F& v, const F& d) {
    const F w = d * F(k.far);
    const F ndcX = u * F(2.0f) - F(1.0f), ndcY = F(1.0f) - v * F(2.0f);
    return {ndcX * w * F(k.invPx), ndcY * w * F(k.invPy), -w};
}

// The last probe of a search: its map coordinates and the texel read there.
template <class F>
struct Probe {
    F u, v;
    Vec4L<F> texel;
};

// 004 §3's binary search for the crossing of the segment s → e (clip space) with a map's
// surface, `iterations` halvings of the parameter. At the midpoint m: an empty texel (the
// far plane, d ≥ 1) moves the end to m; otherwise the end moves to m when m lies beyond
// the stored surface as seen along the ray — deeper than it for a ray going away from the
// eye (e.w > s.w), shallower for one coming back — and the start moves to m otherwise.
// (The paper states the two cases with eye-space z; this is the same rule in linear
// depth.) `fetch(u, v, live)` reads the map; lanes outside `live` fetch nothing.
template <class F, class M, class Fetch>
Probe<F> binarySearch(const SearchConstants& k, const Clip<F>& s, const Clip<F>& e, int iterations,
                      const M& live, Fetch&& fetch) {
    F lo(0.0f), hi(1.0f);
    const M away = e.w > s.w;
    Probe<F> p{F(0.0f), F(0.0f), {F(0.0f), F(0.0f), F(0.0f), F(1.0f)}};
    for (int i = 0; i < iterations; ++i) {
        const F mid = F(0.5f) * (lo + hi);
        const F mx = s.x + (e.x - s.x) * mid, my = s.y + (e.y - s.y) * mid;
        const F mw = s.w + (e.w - s.w) * mid;
        mapCoords(mx, my, mw, p.u, p.v);
        p.texel = fetch(p.u, p.v, live);
        const F depth = mw * F(k.invFar);
        const M crossed = (p.texel.w >= F(1.0f)) | (away & (depth > p.texel.w)) |
                          andNot(depth < p.texel.w, away);
        hi = select(crossed, mid, hi);
        lo = select(crossed, lo, mid);
    }
    return p;
}

// "we take the last projected midpoint value from the depth map as our intersection point
// candidate": the stored surface's point under the last probe, with the map's normal (or
// colour) there. Valid when the texel holds a surface, the point is not the ray's own
// origin, and it lies within the miss angle of the ray (004 §3, Figure 6).
template <class F, class M>
struct Candidate {
    Vec3L<F> point, value;  // value: the texel's xyz (a normal, or the nearby colour)
    F cosine;               // of the angle between the ray and origin → point
    M valid;
};
template <class F, class M>
Candidate<F, M> candidateOf(const SearchConstants& k, const Probe<F>& p, const Vec3L<F>& origin,
                            const Vec3L<F>& dir) {
    Candidate<F, M> c;
    c.point = unproject(k, p.u, p.v, p.texel.w);
    c.value = {p.texel.x, p.texel.y, p.texel.z};
    const Vec3L<F> to = c.point - origin;
    const F len2 = dot3(to, to);
    c.cosine = dot3(to, dir) / sqrt(len2);
    c.valid = (p.texel.w < F(1.0f)) & (len2 > F(k.minDistance2)) & (c.cosine >= F(k.cosMiss));
    return c;
}

// The state of a path after the refractor: where its last ray starts and goes, how many
// segments it took inside and how many total internal reflections.
template <class F, class M>
struct PathState {
    Vec3L<F> origin, dir;
    M inside;   // still inside the object when the bounce budget ran out
    F segments, reflections;
};

// What traceInside decided at one bounce, for the analysis of Figure 6 (reproduce_tir's
// front/back agreement with the ray tracer): the lanes still searching, both candidates'
// validity and which one was taken. Programs pass no observer; the empty one compiles away.
template <class F, class M>
struct BounceChoice {
    int bounce;
    M searching, backValid, frontValid, useFront;
};
struct NoBounceObserver {
    template <class C>
    void operator()(const C&) const {}
};

// The refraction at the front fragment and up to k.bounces searched segments (004 §3).
// `fetchBack(u, v, live)`, `fetchFront(…)` read the back and front maps.
template <class F, class M, class FetchBack, class FetchFront, class Observe = NoBounceObserver>
PathState<F, M> traceInside(const SearchConstants& k, const Vec3L<F>& p, const Vec3L<F>& nFront,
                            const M& live, FetchBack&& fetchBack, FetchFront&& fetchFront,
                            Observe&& observe = Observe{}) {
    PathState<F, M> st;
    const Vec3L<F> view = normalize3(p);  // the eye sits at the origin of eye space
    M tir;
    st.dir = refractOrReflect(view, facing(normalize3(nFront), view), 1.0f / k.eta, tir);
    st.origin = p;
    st.inside = live;
    st.segments = F(0.0f);
    st.reflections = F(0.0f);
    for (int b = 0; b < k.bounces; ++b) {
        if (!anyLane(st.inside)) break;
        const int iterations = b == 0 ? k.itersFirst : k.itersLater;
        const Clip<F> s = toClip(k, st.origin + st.dir * F(k.epsilon));
        const Clip<F> d = toClipDirection(k, st.dir);
        const F tEnd = frustumExit(s, d);
        const Clip<F> e{s.x + d.x * tEnd, s.y + d.y * tEnd, s.z + d.z * tEnd, s.w + d.w * tEnd};
        const Candidate<F, M> back =
            candidateOf<F, M>(k, binarySearch(k, s, e, iterations, st.inside, fetchBack), st.origin, st.dir);
        Candidate<F, M> hit = back;
        M useFront = andNot(back.valid, back.valid);  // all false (lane masks have no literal)
        M frontValid = useFront;
        if (k.frontAndBack) {
            // Figure 6: the candidate more closely aligned with the ray; the back one on a tie.
            const Candidate<F, M> front = candidateOf<F, M>(
                k, binarySearch(k, s, e, iterations, st.inside, fetchFront), st.origin, st.dir);
            useFront = andNot(front.valid, back.valid) | (front.valid & (front.cosine > back.cosine));
            frontValid = front.valid;
            hit.point = select3(useFront, front.point, back.point);
            hit.value = select3(useFront, front.value, back.value);
            hit.valid = back.valid | front.valid;
        }
        observe(BounceChoice<F, M>{b, st.inside, back.valid, frontValid, useFront});
        // Lanes whose candidates both miss are "done bouncing": their ray stays as it is.
        const M moved = st.inside & hit.valid;
        M reflects;
        const Vec3L<F> next = refractOrReflect(st.dir, facing(normalize3(hit.value), st.dir), k.eta, reflects);
        st.origin = select3(moved, hit.point, st.origin);
        st.dir = select3(moved, next, st.dir);
        st.segments = select(st.inside, st.segments + F(1.0f), st.segments);
        st.reflections = select(moved & reflects, st.reflections + F(1.0f), st.reflections);
        st.inside = moved & reflects;
    }
    return st;
}

// An eye-space direction in world space (the view's rotation inverted).
template <class F>
Vec3L<F> eyeToWorld(const SearchConstants& k, const Vec3L<F>& d) {
    return {(d.x * F(k.eyeToWorld[0]) + d.y * F(k.eyeToWorld[1])) + d.z * F(k.eyeToWorld[2]),
            (d.x * F(k.eyeToWorld[3]) + d.y * F(k.eyeToWorld[4])) + d.z * F(k.eyeToWorld[5]),
            (d.x * F(k.eyeToWorld[6]) + d.y * F(k.eyeToWorld[7])) + d.z * F(k.eyeToWorld[8])};
}

// The exit ray's colour: the nearby-geometry map where the search finds it, else the
// environment along the ray's world direction. `fetchNearby(u, v, live)` reads the nearby
// map, `fetchEnv(dirWorld, live)` the environment.
template <class F, class M, class FetchNearby, class FetchEnv>
Vec3L<F> exitColor(const SearchConstants& k, const Vec3L<F>& origin, const Vec3L<F>& dir, const M& live,
                   FetchNearby&& fetchNearby, FetchEnv&& fetchEnv) {
    Vec3L<F> color = fetchEnv(eyeToWorld(k, dir), live);
    if (k.searchNearby) {
        const Clip<F> s = toClip(k, origin + dir * F(k.epsilon));
        const Clip<F> d = toClipDirection(k, dir);
        const F tEnd = frustumExit(s, d);
        const Clip<F> e{s.x + d.x * tEnd, s.y + d.y * tEnd, s.z + d.z * tEnd, s.w + d.w * tEnd};
        const Candidate<F, M> near =
            candidateOf<F, M>(k, binarySearch(k, s, e, k.itersNearby, live, fetchNearby), origin, dir);
        color = select3(near.valid, near.value, color);
    }
    return color;
}

// acos as Cg's standard library evaluates it (a polynomial after Abramowitz & Stegun
// 4.4.45, |error| ≤ 6.7·10⁻⁵ rad): the G80 had no arc cosine instruction. Used by the
// Wyman 2005 baseline's θ_t/θ_i.
template <class F>
F acosCg(const F& x) {
    const auto negative = x < F(0.0f);
    const F a = abs(x);
    F r(-0.0187293f);
    r = r * a + F(0.0742610f);
    r = r * a - F(0.2121144f);
    r = r * a + F(1.5707288f);
    r = r * sqrt(F(1.0f) - a);
    return select(negative, F(3.14159265f) - r, r);
}

}  // namespace rg::tir
