// A glass object shaded with its refractor height map (002 §6) for the exit of the refracted
// ray instead of the refractor distance map (impostor_shading.h's tracePaths): "If we do have
// the intersection point, we have to follow the refracted ray direction. The normal vector is
// known at the intersection point since the refractor height map contains it, so the
// refraction direction can be calculated." The environment lookups along the reflected and
// the exiting ray, Fresnel and absorption are impostor_shading.h's own.
//
// Written beside tracePaths/shadeOwn rather than into them so that the distance-map programs
// (impostor_programs.cpp, minutes of compiling, and their golden hashes) stay as they are; the
// two differ only in the exit search.
#pragma once

#include "impostor_height_search.h"
#include "impostor_shading.h"

namespace rg::impostors {

// Where the height-map exit search finds no crossing (the bisection's ends both inside: a ray
// leaving through a part the front half does not show), the ray leaves unbent at the end of
// its segment. Counted in `unfound` (diagnostics).
template <class F, class M>
struct HeightPaths {
    GlassPaths<F, M> paths;
    M exitTir;   // the first exit reflected totally (a second search ran)
    M unfound;   // a search found no crossing
    F segmentCase;
    M retried;
};

// tracePaths with the exit from the height map `fetchHeight(u, v, live)` (the refractor map's
// frame, ObjectFrame::toLocal). Total internal reflection at the exit: one more height-map
// search from the exit point along the reflected ray, the billboard turned to face it; a second
// total reflection leaves along its mirror direction (as tracePaths does).
template <class F, class M, class FetchHeight>
HeightPaths<F, M> tracePathsHeight(const ObjectFrame& o, const HeightFrame& hf, const Vec3L<F>& P,
                                   const Vec3L<F>& Nraw, const Vec3L<F>& V, const M& live, FetchHeight&& fetchHeight) {
    HeightPaths<F, M> hp;
    GlassPaths<F, M>& g = hp.paths;
    const Vec3L<F> N = facing(normalize3(Nraw), V);
    const F cosI = -dot3(V, N);
    g.fresnel = fresnelSchlick(cosI, o.f0);
    g.reflOrigin = P;
    g.reflDir = reflect3(V, N);
    M tirIn;
    const Vec3L<F> T = refractOrReflect(V, N, 1.0f / o.eta, tirIn);
    const Vec3L<F> c = splat3<F>(o.centre);
    const Vec3L<F> xl = mul3(o.toLocal, P - c), Tl = mul3(o.toLocal, T);
    const HeightHit<F, M> h = heightSearch(hf, xl, Tl, /*exit=*/true, live, fetchHeight);
    hp.segmentCase = h.segmentCase;
    hp.retried = h.retried;
    hp.unfound = andNot(live, h.found);
    const Vec3L<F> Q = c + mulT3(o.toLocal, h.point);
    const Vec3L<F> Nq = mulT3(o.toLocal, normalize3(h.normal));
    M tirOut;
    const Vec3L<F> out = refractOrReflect(T, facing(Nq, T), o.eta, tirOut);
    tirOut = tirOut & h.found;
    g.exitDir = select3(h.found, out, T);
    g.exitOrigin = Q;
    F length = h.d;
    g.searches = F(1.0f);
    const M again = live & tirOut;
    hp.exitTir = again;
    if (anyLane(again)) {
        const Vec3L<F> ql = h.point, dl = mul3(o.toLocal, g.exitDir);
        const HeightHit<F, M> h2 = heightSearch(hf, ql, dl, /*exit=*/true, again, fetchHeight);
        const Vec3L<F> Q2 = c + mulT3(o.toLocal, h2.point);
        const Vec3L<F> N2 = mulT3(o.toLocal, normalize3(h2.normal));
        M tir2;
        const Vec3L<F> out2 = refractOrReflect(g.exitDir, facing(N2, g.exitDir), o.eta, tir2);
        g.exitOrigin = select3(again, Q2, g.exitOrigin);
        g.exitDir = select3(again & h2.found, out2, g.exitDir);
        length = select(again, length + h2.d, length);
        g.searches = select(again, F(2.0f), g.searches);
        hp.unfound = hp.unfound | andNot(again, h2.found);
    }
    g.transmit = {expNeg(F(o.absorption[0]) * length), expNeg(F(o.absorption[1]) * length),
                  expNeg(F(o.absorption[2]) * length)};
    return hp;
}

// shadeOwn for a glass object with the height-map exit (mirrors have no exit: shadeOwn).
template <class F, class M, class FetchEnv, class FetchHeight>
Shaded<F> shadeOwnHeight(const ObjectFrame& o, const HeightFrame& hf, int iterations, const Vec3L<F>& P,
                         const Vec3L<F>& N, const Vec3L<F>& V, const M& live, FetchEnv&& fetchEnv,
                         FetchHeight&& fetchHeight) {
    Shaded<F> out;
    const GlassPaths<F, M> g = tracePathsHeight(o, hf, P, N, V, live, fetchHeight).paths;
    const EnvSample<F> er = envLookup(o, iterations, g.reflOrigin, g.reflDir, live, fetchEnv);
    const EnvSample<F> et = envLookup(o, iterations, g.exitOrigin, g.exitDir, live, fetchEnv);
    out.reflColour = er.colour;
    out.exitColour = et.colour;
    out.transmit = g.transmit;
    out.fresnel = g.fresnel;
    out.colour = combine(o, out);
    out.searches = g.searches + F(2.0f);
    out.moverFlags = F(0.0f);
    out.reflDir = g.reflDir;
    out.exitOrigin = g.exitOrigin;
    out.exitDir = g.exitDir;
    out.reflD = er.d;
    out.exitD = et.d;
    return out;
}

// throughMover (impostor_shading.h) with the mover's refractor height map: "In the algorithm
// described in 5.2, the refractor distance map can be replaced by the refractor height map.
// Search can be executed from an outer point and the calculation of multiple refractions is
// possible as well." The entry search from the ray's origin (the billboard turned to face it)
// replaces §4.1's outside search and its ε test (the bisection says itself whether it found
// a crossing); where it meets the mover nearer than `envD`, the mover's own shading there —
// a mirror's reflection (shadeOwn), or glass with its height-map exit (shadeOwnHeight) —
// replaces `colour`.
template <class F, class M, class FetchEnv, class FetchRefr, class FetchHeight>
void throughMoverHeight(const ObjectFrame& m, const HeightFrame& hm, int iterations, const Vec3L<F>& origin,
                        const Vec3L<F>& dir, const F& envD, const M& live, Vec3L<F>& colour, F& searches, F& flags,
                        float flag, FetchEnv&& fetchMoverEnv, FetchRefr&& fetchMoverRefr, FetchHeight&& fetchMoverHeight) {
    const Vec3L<F> c = splat3<F>(m.centre);
    const Vec3L<F> yl = mul3(m.toLocal, origin - c), Rl = mul3(m.toLocal, dir);
    const HeightHit<F, M> h = heightSearch(hm, yl, Rl, /*exit=*/false, live, fetchMoverHeight);
    searches = select(live & (h.segmentCase > F(0.0f)), searches + F(1.0f), searches);
    const M use = h.found & (h.d < envD);
    if (!anyLane(use)) return;
    const Vec3L<F> P = c + mulT3(m.toLocal, h.point);
    const Vec3L<F> N = mulT3(m.toLocal, normalize3(h.normal));
    const Shaded<F> s = m.mirror ? shadeOwn(m, iterations, P, N, dir, use, fetchMoverEnv, fetchMoverRefr)
                                 : shadeOwnHeight(m, hm, iterations, P, N, dir, use, fetchMoverEnv, fetchMoverHeight);
    colour = select3(use, s.colour, colour);
    searches = select(use, searches + s.searches, searches);
    flags = select(use, flags + F(flag), flags);
}

}  // namespace rg::impostors
