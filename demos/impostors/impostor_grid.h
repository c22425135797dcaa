// 002 §4.2, "mode A": multi-bounce ray tracing with refractor distance maps only. Each
// glass pixel refracts through its own object's refractor map (Figure 3); its reflected
// and exiting rays walk a uniform grid on the board's squares ("at most one piece in one
// square") to the first occupied square, search that square's object from outside (§4.1)
// and, on a hit, shade it one level deeper (reflection, and refraction through its own
// map) against the diffuse environment; without a hit, "an intersection point with the
// plane of the chessboard will be determined, ignoring further squares" — the board, or
// the sky past it. Lane-generic like the search (impostor_search.h).
#pragma once

#include <cstdint>

#include "impostor_shading.h"

namespace rg::impostors {

constexpr int kGridObjects = 40;  // objects a mode-A program knows (the §8 scene has 33)
constexpr int kGridMaps = 7;      // refractor maps it binds (six piece kinds and the sphere)
constexpr int kGridSize = 8;      // squares along each side of the board
// Units of the mode-A program: the refractor maps 0–6, then these.
constexpr int kGridUnitAlbedo = 7, kGridUnitLight = 8, kGridUnitLightMover = 9, kGridUnitSky = 10, kGridUnitCells = 11;

struct GridConstants {
    float eye[3] = {0, 0, 0};
    int32_t iterations = 8;
    int32_t self = 0;     // the shaded object's index in `frame`
    int32_t objects = 0;  // how many of `frame` are used
    ObjectFrame frame[kGridObjects];
    int32_t map[kGridObjects] = {};  // each object's refractor map (its unit)
    // The board's top face: x and z bounds, height, square size, and its uv as an affine
    // function of (x, z): u = uv[0]·x + uv[1]·z + uv[2], v = uv[3]·x + uv[4]·z + uv[5].
    float boardLo[2] = {-4, -4}, boardHi[2] = {4, 4};
    float boardY = 0, cell = 1;
    float uv[6] = {0.125f, 0, 0.5f, 0, 0.125f, 0.5f};
    float boardAlbedo[3] = {1, 1, 1};
    float maxHeight = 2;  // rays above every object's top, going up, leave the grid
    float ambient[3] = {0, 0, 0};
    int32_t lights = 0;
    float lightPos[2][3] = {};
    float lightIntensity[2][3] = {};
};

// ⌊v⌋ for v in [−1, kGridSize + 1), by compares (the lane types have no floor): −1 below 0.
template <class F>
F gridCell(const F& v) {
    F c(-1.0f);
    for (int k = 0; k <= kGridSize; ++k) c = select(v >= F(float(k)), F(float(k)), c);
    return c;
}

// The diffuse environment along a ray: the board's top face where the ray meets it
// (texture × light maps × raycore's lighting with n = +y), else the sky. `fetch(unit, c,
// live)` reads a unit at coordinates c (lod 0).
template <class F, class M, class FetchUnit>
Vec3L<F> boardOrSky(const GridConstants& g, const Vec3L<F>& o, const Vec3L<F>& d, const M& live, FetchUnit&& fetch) {
    const F t = (F(g.boardY) - o.y) / d.y;
    const Vec3L<F> p = o + d * t;
    const M onBoard = live & (d.y < F(0.0f)) & (t > F(0.0f)) & (p.x >= F(g.boardLo[0])) & (p.x <= F(g.boardHi[0])) &
                      (p.z >= F(g.boardLo[1])) & (p.z <= F(g.boardHi[1]));
    const M sky = andNot(live, onBoard);
    Vec3L<F> colour(F(0.0f), F(0.0f), F(0.0f));
    if (anyLane(onBoard)) {
        const F u = (p.x * F(g.uv[0]) + p.z * F(g.uv[1])) + F(g.uv[2]);
        const F v = (p.x * F(g.uv[3]) + p.z * F(g.uv[4])) + F(g.uv[5]);
        const Vec4L<F> c(u, v, F(0.0f), F(0.0f));
        const Vec4L<F> a = fetch(kGridUnitAlbedo, c, onBoard);
        const Vec4L<F> vs = fetch(kGridUnitLight, c, onBoard), vm = fetch(kGridUnitLightMover, c, onBoard);
        Vec3L<F> light = splat3<F>(g.ambient);
        for (int i = 0; i < g.lights && i < 2; ++i) {
            const Vec3L<F> l = normalize3(splat3<F>(g.lightPos[i]) - p);
            const F vis = i == 0 ? vs.x * vm.x : vs.y * vm.y;
            light = light + splat3<F>(g.lightIntensity[i]) * (max(l.y, F(0.0f)) * vis);
        }
        const Vec3L<F> board(a.x * F(g.boardAlbedo[0]) * light.x, a.y * F(g.boardAlbedo[1]) * light.y,
                             a.z * F(g.boardAlbedo[2]) * light.z);
        colour = select3(onBoard, board, colour);
    }
    if (anyLane(sky)) {
        const Vec4L<F> s = fetch(kGridUnitSky, Vec4L<F>(d.x, d.y, d.z, F(0.0f)), sky);
        colour = select3(sky, Vec3L<F>(s.x, s.y, s.z), colour);
    }
    return colour;
}

// The first occupied square along the ray's path over the board other than `self`'s
// (a 2D DDA over at most 2·kGridSize squares, read from the occupancy texture: the
// object's index, −1 for empty), or −1. Stops where the ray leaves the board or rises
// above every object.
template <class F, class M, class FetchUnit>
F firstOccupied(const GridConstants& g, const Vec3L<F>& o, const Vec3L<F>& d, const M& live, FetchUnit&& fetch) {
    const F inv = F(1.0f / g.cell);
    const F gx = (o.x - F(g.boardLo[0])) * inv, gz = (o.z - F(g.boardLo[1])) * inv;
    F cx = gridCell(gx), cz = gridCell(gz);
    const M posX = d.x > F(0.0f), posZ = d.z > F(0.0f);
    const F stepX = select(posX, F(1.0f), F(-1.0f)), stepZ = select(posZ, F(1.0f), F(-1.0f));
    // Ray parameters of the next square boundary in x and z, and between boundaries.
    F tMaxX = (select(posX, cx + F(1.0f), cx) - gx) * F(g.cell) / d.x;
    F tMaxZ = (select(posZ, cz + F(1.0f), cz) - gz) * F(g.cell) / d.z;
    const F tDeltaX = F(g.cell) / abs(d.x), tDeltaZ = F(g.cell) / abs(d.z);
    F found(-1.0f), t(0.0f);
    M active = live;
    const F last(float(kGridSize - 1));
    for (int step = 0; step < 2 * kGridSize && anyLane(active); ++step) {
        const M inside = (cx >= F(0.0f)) & (cx <= last) & (cz >= F(0.0f)) & (cz <= last);
        const M below = (o.y + d.y * t <= F(g.maxHeight)) | (d.y < F(0.0f));
        active = active & below;
        const M look = active & inside;
        if (anyLane(look)) {
            const F inv8 = F(1.0f / float(kGridSize));
            const Vec4L<F> cell =
                fetch(kGridUnitCells, Vec4L<F>((cx + F(0.5f)) * inv8, (cz + F(0.5f)) * inv8, F(0.0f), F(0.0f)), look);
            const M hit = look & (cell.x >= F(0.0f)) & (cell.x != F(float(g.self)));
            found = select(hit, cell.x, found);
            active = andNot(active, hit);
        }
        // Leaving the board for good: outside and moving away.
        const M gone = ((cx < F(0.0f)) & (d.x <= F(0.0f))) | ((cx > last) & (d.x >= F(0.0f))) |
                       ((cz < F(0.0f)) & (d.z <= F(0.0f))) | ((cz > last) & (d.z >= F(0.0f)));
        active = andNot(active, gone);
        const M useX = tMaxX < tMaxZ;
        t = select(useX, tMaxX, tMaxZ);
        cx = select(useX, cx + stepX, cx);
        tMaxX = select(useX, tMaxX + tDeltaX, tMaxX);
        cz = select(useX, cz, cz + stepZ);
        tMaxZ = select(useX, tMaxZ, tMaxZ + tDeltaZ);
    }
    return found;
}

// The radiance along a ray in mode A: the first occupied square's object, found in its
// refractor map from outside and shaded one level deeper against the board and sky (its
// reflection, and its refraction through its own map), else the board or the sky.
// `searches` counts the searches.
template <class F, class M, class FetchUnit>
Vec3L<F> gridRadiance(const GridConstants& g, const Vec3L<F>& o, const Vec3L<F>& d, const M& live, F& searches,
                      FetchUnit&& fetch) {
    const F j = firstOccupied(g, o, d, live, fetch);
    M hitAny = M();
    Vec3L<F> colour(F(0.0f), F(0.0f), F(0.0f));
    for (int k = 0; k < g.objects && k < kGridObjects; ++k) {
        const M mk = live & (j == F(float(k)));
        if (!anyLane(mk)) continue;
        const ObjectFrame& f = g.frame[k];
        const int unit = g.map[k];
        auto fetchMap = [&fetch, unit](const Vec3L<F>& dir, const M& m) {
            return fetch(unit, Vec4L<F>(dir.x, dir.y, dir.z, F(0.0f)), m);
        };
        const Vec3L<F> c = splat3<F>(f.centre);
        const OutsideHit<F, M> h = outsideSearch(mul3(f.toLocal, o - c), mul3(f.toLocal, d), f.boxLo, f.boxHi, f.epsilon,
                                                 g.iterations, mk, fetchMap);
        searches = select(h.boxHit, searches + F(1.0f), searches);
        const M use = mk & h.valid;
        if (!anyLane(use)) continue;
        const Vec3L<F> P = c + mulT3(f.toLocal, h.point), N = mulT3(f.toLocal, h.normal);
        Vec3L<F> here;
        if (f.mirror) {
            const Vec3L<F> r = reflect3(d, facing(normalize3(N), d));
            here = boardOrSky(g, P, r, use, fetch) * splat3<F>(f.reflectance);
        } else {
            const GlassPaths<F, M> p = tracePaths(f, g.iterations, P, N, d, use, fetchMap);
            const Vec3L<F> cr = boardOrSky(g, p.reflOrigin, p.reflDir, use, fetch);
            const Vec3L<F> ct = boardOrSky(g, p.exitOrigin, p.exitDir, use, fetch);
            here = cr * p.fresnel + (ct * p.transmit) * (F(1.0f) - p.fresnel);
            searches = select(use, searches + p.searches, searches);
        }
        colour = select3(use, here, colour);
        hitAny = hitAny | use;
    }
    const M rest = andNot(live, hitAny);
    if (anyLane(rest)) colour = select3(rest, boardOrSky(g, o, d, rest, fetch), colour);
    return colour;
}

}  // namespace rg::impostors
