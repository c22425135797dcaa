// Shading a glass (or mirror) object with distance impostors, lane-generic like the search
// (impostor_search.h): 002 §3's depth-2 tracing (the refracted ray's exit found in the
// object's refractor distance map, the reflected and the exiting ray looked up in its
// environment distance impostor, Fresnel between them) and §5.2's moving object (the
// static object's two rays searched from outside in the mover's refractor map, and where
// one meets it nearer than the static environment, the three searches 5–7 of Figure 5 in
// the mover's own maps).
//
// Frames: an environment impostor is a cube map about the object's centre c with world
// axes; a refractor distance map is a cube map about the centre of the object's mesh in
// its model frame, so objects sharing a mesh (the chess pieces of one kind) share it, and
// `toLocal` turns world directions into that frame (a rotation).
#pragma once

#include <cstdint>

#include "impostor_search.h"

namespace rg::impostors {

// One glass or mirror object as the programs see it. Plain data of 4-byte fields (traces
// record program bytes).
struct ObjectFrame {
    float centre[3] = {0, 0, 0};                      // world: both maps' reference point
    float toLocal[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};   // world → the refractor map's frame (rows)
    float boxLo[3] = {-1, -1, -1}, boxHi[3] = {1, 1, 1};  // bounding box in that frame, about the centre
    float eta = 1.5f;                                 // index of refraction (air outside)
    float f0 = 0.04f;                                 // Schlick's F0 = ((η − 1)/(η + 1))²
    float absorption[3] = {0, 0, 0};                  // −ln(transmittance per unit length)
    float reflectance[3] = {0.9f, 0.9f, 0.9f};        // a mirror's
    float epsilon = 0.01f;                            // §4.1's validity distance (world units)
    int32_t mirror = 0;                               // 1: reflects only
    int32_t mirrorSchlick = 0;                        // 1: the mirror's reflectance is Schlick's F0
};

// The constants of a glass object's fragment program.
struct GlassConstants {
    float eye[3] = {0, 0, 0};   // where view rays start: the camera, or the reference point of
                                // the environment map being rendered
    int32_t iterations = 8;     // secant steps after l (002 §3 gives none; [D] uses 8)
    int32_t writeDistance = 0;  // w = |P − eye| (environment maps), else 1 (the frame)
    ObjectFrame self, mover;
};

// The two rays leaving a glass surface point after 002 §3's depth-2 tracing: the reflected
// ray, and the refracted ray after its exit from the object (found in the refractor map),
// with the Fresnel weight and the absorption along the inside segment.
template <class F, class M>
struct GlassPaths {
    Vec3L<F> reflOrigin, reflDir, exitOrigin, exitDir;
    F fresnel;
    Vec3L<F> transmit;  // transmittance^length, per channel
    F searches;         // refractor-map searches: 1, 2 where the exit reflected totally
};

// Refraction into the object at P (world) with normal N, seen along V (unit); the exit from
// the refractor map (`fetchRefr(dir, live)` in the map's frame); refraction out, or
// reflection under total internal reflection (then the environment along it, no second
// exit search).
template <class F, class M, class FetchRefr>
GlassPaths<F, M> tracePaths(const ObjectFrame& o, int iterations, const Vec3L<F>& P, const Vec3L<F>& Nraw,
                            const Vec3L<F>& V, const M& live, FetchRefr&& fetchRefr) {
    GlassPaths<F, M> g;
    const Vec3L<F> N = facing(normalize3(Nraw), V);
    const F cosI = -dot3(V, N);
    g.fresnel = fresnelSchlick(cosI, o.f0);
    g.reflOrigin = P;
    g.reflDir = reflect3(V, N);
    M tirIn;
    const Vec3L<F> T = refractOrReflect(V, N, 1.0f / o.eta, tirIn);
    const Vec3L<F> c = splat3<F>(o.centre);
    const Vec3L<F> xl = mul3(o.toLocal, P - c), Tl = mul3(o.toLocal, T);
    const SearchResult<F, M> s = secantSearch(xl, Tl, iterations, live, fetchRefr, /*seeded=*/true);
    const Vec3L<F> Q = c + mulT3(o.toLocal, s.point);
    const Vec3L<F> Nq = mulT3(o.toLocal, normalize3(Vec3L<F>(s.texel.x, s.texel.y, s.texel.z)));
    M tirOut;
    g.exitDir = refractOrReflect(T, facing(Nq, T), o.eta, tirOut);
    g.exitOrigin = Q;
    F length = s.d;
    g.searches = F(1.0f);
    // Total internal reflection at the exit: the reflected ray is still inside; one more
    // search of the refractor map finds where it leaves (the paper does not say; the
    // environment along the reflected ray would see the sky through the object's own
    // floor). A second total reflection leaves along its mirror direction.
    const M again = live & tirOut;
    if (anyLane(again)) {
        const SearchResult<F, M> s2 = secantSearch(mul3(o.toLocal, Q - c), mul3(o.toLocal, g.exitDir), iterations, again,
                                                   fetchRefr, /*seeded=*/true);
        const Vec3L<F> Q2 = c + mulT3(o.toLocal, s2.point);
        const Vec3L<F> N2 = mulT3(o.toLocal, normalize3(Vec3L<F>(s2.texel.x, s2.texel.y, s2.texel.z)));
        M tir2;
        const Vec3L<F> out2 = refractOrReflect(g.exitDir, facing(N2, g.exitDir), o.eta, tir2);
        g.exitOrigin = select3(again, Q2, g.exitOrigin);
        g.exitDir = select3(again, out2, g.exitDir);
        length = select(again, length + s2.d, length);
        g.searches = select(again, F(2.0f), g.searches);
    }
    g.transmit = {expNeg(F(o.absorption[0]) * length), expNeg(F(o.absorption[1]) * length),
                  expNeg(F(o.absorption[2]) * length)};
    return g;
}

// The environment distance impostor along a world ray: the radiance of the search's last
// texel and the hit's distance along the ray.
template <class F>
struct EnvSample {
    Vec3L<F> colour;
    F d;
};
template <class F, class M, class FetchEnv>
EnvSample<F> envLookup(const ObjectFrame& o, int iterations, const Vec3L<F>& origin, const Vec3L<F>& dir,
                       const M& live, FetchEnv&& fetchEnv) {
    const SearchResult<F, M> s = secantSearch(origin - splat3<F>(o.centre), dir, iterations, live, fetchEnv);
    return {Vec3L<F>(s.texel.x, s.texel.y, s.texel.z), s.d};
}

// Searches a shading takes, per lane (Figure 5's counts): 3 per glass object (refractor map,
// environment along the reflected and the exiting ray; 4 where the exit reflects totally),
// 1 per mirror.
template <class F>
struct Shaded {
    Vec3L<F> colour;
    F searches;
    F moverFlags;  // 1: the reflected ray met the mover, 2: the exiting ray did (sum)
    // The rays and their hit distances in the object's own environment (diagnostics).
    Vec3L<F> reflDir, exitOrigin, exitDir;
    F reflD, exitD;
    // The parts `colour` combines: the radiance along each ray, the Fresnel weight, the
    // absorption inside (a mirror: F = 1 and its reflectance in `transmit`).
    Vec3L<F> reflColour, exitColour, transmit;
    F fresnel;
};

// Glass: F·L_reflected + (1 − F)·transmit·L_exiting; a mirror: reflectance·L_reflected.
template <class F>
Vec3L<F> combine(const ObjectFrame& o, const Shaded<F>& s) {
    if (o.mirror) return s.reflColour * s.transmit;
    return s.reflColour * s.fresnel + (s.exitColour * s.transmit) * (F(1.0f) - s.fresnel);
}

// A glass or mirror object with its own maps: the colour of 002 §3 (§5's three searches).
template <class F, class M, class FetchEnv, class FetchRefr>
Shaded<F> shadeOwn(const ObjectFrame& o, int iterations, const Vec3L<F>& P, const Vec3L<F>& N, const Vec3L<F>& V,
                   const M& live, FetchEnv&& fetchEnv, FetchRefr&& fetchRefr) {
    Shaded<F> out;
    if (o.mirror) {
        const Vec3L<F> n = facing(normalize3(N), V);
        const Vec3L<F> r = reflect3(V, n);
        const EnvSample<F> e = envLookup(o, iterations, P, r, live, fetchEnv);
        out.reflColour = e.colour;
        out.exitColour = Vec3L<F>(F(0.0f), F(0.0f), F(0.0f));
        if (o.mirrorSchlick) {
            const F cosI = -dot3(V, n);
            out.transmit = {fresnelSchlick(cosI, o.reflectance[0]), fresnelSchlick(cosI, o.reflectance[1]),
                            fresnelSchlick(cosI, o.reflectance[2])};
        } else {
            out.transmit = splat3<F>(o.reflectance);
        }
        out.fresnel = F(1.0f);
        out.colour = combine(o, out);
        out.searches = F(1.0f);
        out.moverFlags = F(0.0f);
        out.reflDir = r;
        out.exitOrigin = P;
        out.exitDir = r;
        out.reflD = e.d;
        out.exitD = e.d;
        return out;
    }
    const GlassPaths<F, M> g = tracePaths(o, iterations, P, N, V, live, fetchRefr);
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

// A ray of a static object tested against the mover (§4.1 from outside, §5.2): where the
// mover's refractor map yields a valid hit nearer than `envD` (the static environment's hit
// along the ray), the mover's own shading there (Figure 5's searches 5–7) replaces
// `colour`, the radiance along that ray. `searches` counts the outside search (lanes meeting the mover's box) and the
// mover's shading.
template <class F, class M, class FetchEnv, class FetchRefr>
void throughMover(const ObjectFrame& m, int iterations, const Vec3L<F>& origin, const Vec3L<F>& dir, const F& envD,
                  const M& live, Vec3L<F>& colour, F& searches, F& flags, float flag, FetchEnv&& fetchMoverEnv,
                  FetchRefr&& fetchMoverRefr) {
    const Vec3L<F> c = splat3<F>(m.centre);
    const Vec3L<F> yl = mul3(m.toLocal, origin - c), Rl = mul3(m.toLocal, dir);
    const OutsideHit<F, M> h = outsideSearch(yl, Rl, m.boxLo, m.boxHi, m.epsilon, iterations, live, fetchMoverRefr);
    searches = select(h.boxHit, searches + F(1.0f), searches);
    const M use = h.valid & (h.t < envD);
    if (!anyLane(use)) return;
    const Vec3L<F> P = c + mulT3(m.toLocal, h.point);
    const Vec3L<F> N = mulT3(m.toLocal, h.normal);
    const Shaded<F> s = shadeOwn(m, iterations, P, N, dir, use, fetchMoverEnv, fetchMoverRefr);
    colour = select3(use, s.colour, colour);
    searches = select(use, searches + s.searches, searches);
    flags = select(use, flags + F(flag), flags);
}

}  // namespace rg::impostors
