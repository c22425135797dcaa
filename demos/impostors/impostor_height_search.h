// Dancsik & Minarik §6, "Refractor height maps", as lane arithmetic (one definition for a plain
// float, Float4 and the quad groups, like impostor_search.h; IEEE-exact operations only).
//
//   the map      the piece photographed by an orthographic camera perpendicular to its plane
//                of symmetry: per texel (s, t) of that plane the unit normal and the height
//                h ≥ 0 of the surface over it (impostor_height_maps.cpp). "As the piece is
//                symmetric, the height map describes the whole surface": the point (s, t, h)
//                is inside ⇔ |h| < h_map(s, t).
//   billboard    the map "bent on a billboard that always rotates towards the camera around
//                the axis perpendicular to the chessboard" (Figure 6) — for a secondary ray,
//                towards that ray's origin. Billboard axes: s horizontal in the plane, t the
//                vertical axis, h towards the origin.
//   segment      Figure 7, with d_plane the ray's distance to the billboard's plane and
//                d_near < d_far to the proxy's box:
//                  case 1   d_near < d_plane < d_far: [d_near, d_plane], in front
//                  case 2   d_plane ≥ d_far (or never): [d_near, d_far], in front
//                  case 3   d_plane ≤ d_near: [d_near, d_far], on one side of the plane;
//                           case 3a behind it, "reflected to the plane" (3b) before the search
//   search       a binary search on the segment (relief mapping, refs. [3], [4]); where case 1's
//                fails, "the ray has to be reflected to the plane of the billboard and the
//                valid domain … recalculated": [d_plane, d_far] mirrored, searched again, and
//                the point found "reflected to the plane of symmetry again" (with its normal).
//
// The paper gives no step count (Figure 8 marks 3 per search; [D] uses 8), no success test and
// no frame for the map's texture space; ours are in HeightFrame and heightSearch below.
#pragma once

#include <cstdint>

#include "impostor_search.h"

namespace rg::impostors {

// A refractor height map as the programs see it, in the refractor map's frame (the mesh's
// box centre at 0, ObjectFrame::toLocal): plain data of 4-byte fields (traces record
// program bytes).
struct HeightFrame {
    float axis[2] = {0, 0};        // (x, z) of the vertical axis the billboard turns about
    float sLo = -1, sHi = 1;       // the map's texture domain over the plane: s …
    float tLo = -1, tHi = 1;       // … and t (local y); texel row 0 at tHi
    float hMax = 1;                // the proxy's box: |h| ≤ hMax (beyond every stored height)
    int32_t steps = 8;             // binary-search steps per segment
};

// Figure 7's cases (the `segmentCase` of a search), for the histogram and the tests.
constexpr float kCase1 = 1.0f, kCase2 = 2.0f, kCase3 = 3.0f, kCase3a = 4.0f;

// A search's outcome: the point and the outward normal (the refractor map's frame), the ray
// parameter, whether a crossing was found, the case of the first segment and whether the
// mirrored retry ran.
template <class F, class M>
struct HeightHit {
    Vec3L<F> point, normal;
    F d;
    M found;
    F segmentCase;  // kCase1 … kCase3a; 0 where the ray missed the box
    M retried;      // case 1's front search failed and the mirrored segment was searched
};

// The billboard's axes for a ray from `o` (local frame): w horizontal from the axis towards
// o (the plane's normal, +h), b = w × up rotated so that (b, up, w) is right-handed as the
// map's (x, y, z) is — with w = +z, b = +x, the map's own orientation. On the axis itself
// (no horizontal direction) the map's own: w = +z.
template <class F>
struct Billboard {
    F wx, wz;  // +h
    F bx, bz;  // +s
    F ax, az;  // the axis
};
template <class F>
Billboard<F> billboardFacing(const HeightFrame& hf, const Vec3L<F>& o) {
    Billboard<F> bb;
    bb.ax = F(hf.axis[0]);
    bb.az = F(hf.axis[1]);
    const F x = o.x - bb.ax, z = o.z - bb.az;
    const F len2 = x * x + z * z;
    const auto ok = len2 > F(1e-12f);
    const F inv = F(1.0f) / sqrt(select(ok, len2, F(1.0f)));
    bb.wx = select(ok, x * inv, F(0.0f));
    bb.wz = select(ok, z * inv, F(1.0f));
    bb.bx = bb.wz;
    bb.bz = F(0.0f) - bb.wx;
    return bb;
}

// The map's texel at a billboard point (s, t) (texture coordinates u along s, v down from tHi).
template <class F>
F heightU(const HeightFrame& hf, const F& s) {
    return (s - F(hf.sLo)) * F(1.0f / (hf.sHi - hf.sLo));
}
template <class F>
F heightV(const HeightFrame& hf, const F& t) {
    return (F(hf.tHi) - t) * F(1.0f / (hf.tHi - hf.tLo));
}

// One binary search on [a, b] of the ray (s, t, h) = o + d·r in billboard coordinates, with
// σ = −1 for a segment reflected to the plane (h → −h). `wantInside`: an entry (a ray from
// outside looks for the first inside point) or an exit (a ray inside looks for outside).
// The end b is read first; each step reads the midpoint m and moves b to it where it has the
// wanted state, a otherwise. Found ⇔ b has the wanted state at the end (b only ever moves to
// such points), and the crossing then lies in [a, b]. The texel on the inside of the bracket
// (a for an exit, b for an entry; the segment's start is read once for it) carries the normal.
template <class F, class M>
struct Bisection {
    F a, b;
    M found;
    Vec4L<F> insideTexel;
};
template <class F, class M, class Fetch>
Bisection<F, M> bisect(const HeightFrame& hf, const F (&o)[3], const F (&r)[3], const F& sigma, const F& a0,
                       const F& b0, bool wantInside, const M& live, Fetch&& fetch) {
    // The state at ray parameter d: σ·h < h_map(s, t) is inside (an empty texel stores 0, so
    // nothing on the plane's valid side is inside it).
    auto read = [&](const F& d, const M& m, Vec4L<F>& texel) {
        const F s = o[0] + r[0] * d, t = o[1] + r[1] * d, h = (o[2] + r[2] * d) * sigma;
        texel = fetch(heightU(hf, s), heightV(hf, t), m);
        return live & (h < texel.w);
    };
    Bisection<F, M> bs;
    bs.a = a0;
    bs.b = b0;
    Vec4L<F> ta, tb;
    const M inB = read(b0, live, tb);
    read(a0, live, ta);  // its texel only: the normal where a never moves
    M bWanted = wantInside ? inB : andNot(live, inB);
    for (int i = 0; i < hf.steps; ++i) {
        const F m = F(0.5f) * (bs.a + bs.b);
        Vec4L<F> tm;
        const M in = read(m, live, tm);
        const M wanted = wantInside ? in : andNot(live, in);
        bs.b = select(wanted, m, bs.b);
        bs.a = select(wanted, bs.a, m);
        tb = select4(wanted, tm, tb);
        ta = select4(wanted, ta, tm);
        bWanted = bWanted | wanted;
    }
    bs.found = bWanted;
    bs.insideTexel = wantInside ? tb : ta;
    return bs;
}

// §6's search along the ray o + d·R (the refractor map's frame, R unit): the billboard facing o,
// Figure 7's segment, the binary search, the mirrored retry. `exit`: o is inside (a refracted
// ray's entry point on the surface) and the search looks for where the ray leaves.
template <class F, class M, class Fetch>
HeightHit<F, M> heightSearch(const HeightFrame& hf, const Vec3L<F>& o, const Vec3L<F>& R, bool exit, const M& live,
                             Fetch&& fetch) {
    HeightHit<F, M> hit;
    const Billboard<F> bb = billboardFacing(hf, o);
    // The ray in billboard coordinates (s, t, h): o's own h = its distance from the axis ≥ 0,
    // so the origin is always on the billboard's valid side.
    const F ox = o.x - bb.ax, oz = o.z - bb.az;
    const F os[3] = {ox * bb.bx + oz * bb.bz, o.y, ox * bb.wx + oz * bb.wz};
    const F rs[3] = {R.x * bb.bx + R.z * bb.bz, R.y, R.x * bb.wx + R.z * bb.wz};
    // The proxy's box: s and t the map's domain, |h| ≤ hMax.
    const float lo[3] = {hf.sLo, hf.tLo, -hf.hMax}, hi[3] = {hf.sHi, hf.tHi, hf.hMax};
    const BoxSpan<F, M> box = rayBox<F, M>(Vec3L<F>(os[0], os[1], os[2]), Vec3L<F>(rs[0], rs[1], rs[2]), lo, hi);
    const M inBox = live & box.hit;
    const F dNear = max(box.tNear, F(0.0f)), dFar = box.tFar;
    // d_plane: where h = 0 (NaN or ±∞ for a ray parallel to the plane: neither compare below
    // holds for NaN, so such a ray is case 2 or case 3 in front).
    const F dPlane = (F(0.0f) - os[2]) / rs[2];
    const M ahead = dPlane > F(0.0f);            // the ray meets the plane at all
    const M frontFirst = ahead & (dPlane > dNear);  // cases 1 and 2
    const M case1 = frontFirst & (dPlane < dFar);
    const M case3a = andNot(ahead, frontFirst);  // the plane crossed before the box: behind it
    hit.segmentCase = select(inBox, select(case1, F(kCase1), select(frontFirst, F(kCase2),
                                                                       select(case3a, F(kCase3a), F(kCase3)))),
                             F(0.0f));
    // The first segment: in front, [d_near, min(d_plane, d_far)] (cases 1, 2) or the box's
    // whole span (case 3), reflected to the plane where it lies behind it (3a → 3b).
    const F end1 = select(case1, dPlane, dFar);
    const F sigma1 = select(case3a, F(-1.0f), F(1.0f));
    const Bisection<F, M> first = bisect(hf, os, rs, sigma1, dNear, end1, !exit, inBox, fetch);
    // Case 1 without a crossing in front: the rest of the box behind the plane, reflected.
    const M retry = andNot(inBox & case1, first.found);
    hit.retried = retry;
    Bisection<F, M> second = first;
    if (anyLane(retry)) second = bisect(hf, os, rs, F(-1.0f), dPlane, dFar, !exit, retry, fetch);
    const F a = select(retry, second.a, first.a), b = select(retry, second.b, first.b);
    const Vec4L<F> tex = select4(retry, second.insideTexel, first.insideTexel);
    const F sigma = select(retry, F(-1.0f), sigma1);
    hit.found = inBox & ((retry & second.found) | andNot(first.found, retry));
    // The crossing: the bracket's middle. The point is computed on the ray itself, so it is
    // already "reflected to the plane of symmetry again"; the normal is: its h component
    // takes σ.
    hit.d = F(0.5f) * (a + b);
    hit.point = o + R * hit.d;
    const F ns = tex.x, nt = tex.y, nh = tex.z * sigma;
    hit.normal = Vec3L<F>(ns * bb.bx + nh * bb.wx, nt, ns * bb.bz + nh * bb.wz);
    return hit;
}

}  // namespace rg::impostors
