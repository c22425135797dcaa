// The photon-traced caustics reference (raycore/tracer_caustics.h).
#include "raycore/tracer_caustics.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "raycore/accel.h"
#include "raycore/fresnel.h"

namespace rg::ray {

namespace {

struct PhotonHit {
    double u = 0, v = 0;
    glm::dvec3 power{0.0};
};

struct Losses {
    int64_t objectHits = 0, inside = 0, interfaces = 0, upward = 0, offBoard = 0;
};

void shoot(const Scene& sc, const CausticTraceOptions& o, const PointLight& light, uint32_t object,
           std::vector<PhotonHit>& out, int64_t& shot, Losses& lost) {
    const Object& ob = sc.objects[object];
    const Material& mat = sc.materials[ob.material];
    if (mat.type != MaterialType::Glass && mat.type != MaterialType::Mirror) return;
    // The object alone (its own Embree scene): the photons pass through every other object,
    // the board included (a base standing on the board shares its plane, and a ray leaving
    // through it would otherwise meet the board first).
    const Scene alone = subScene(sc, {object});
    const Accel accel(alone);
    const Mesh wm = sc.worldMesh(object);
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const glm::vec3& p : wm.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const glm::vec3 L = light.position, centre = 0.5f * (lo + hi);
    if (glm::all(glm::greaterThanEqual(L, lo)) && glm::all(glm::lessThanEqual(L, hi))) return;
    // The framing of the emulated photon map (impostor_caustics.cpp).
    const glm::vec3 axis = glm::normalize(centre - L);
    const glm::vec3 up = std::fabs(axis.y) > 0.9f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
    const glm::mat4 view = glm::lookAt(L, centre, up);
    float tanMax = 0.0f;
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
        const glm::vec3 e = glm::vec3(view * glm::vec4(p, 1.0f));
        const float z = std::max(-e.z, 1e-4f);
        tanMax = std::max(tanMax, std::max(std::fabs(e.x), std::fabs(e.y)) / z);
    }
    tanMax *= 1.02f;
    const glm::mat3 toWorld = glm::transpose(glm::mat3(view));  // camera axes in world space
    const int n = o.photonsPerAxis;
    const double cell = 2.0 * double(tanMax) / n, a = cell * cell;
    const float f0 = FresnelNormalIncidence(mat.ior);
    const CausticBoard& b = o.board;
    // A photon leaving the object at p along d with the power I·w·factor (per channel)
    // meets the board plane, or is counted lost.
    auto land = [&](const glm::vec3& p, const glm::vec3& d, double w, const glm::dvec3& factor) {
        if (!(d.y < 0.0f)) {
            ++lost.upward;
            return;
        }
        // A photon leaving through a base that stands on the board lands where it leaves.
        const double tb = std::max((double(b.y) - double(p.y)) / double(d.y), 0.0);
        const double X = double(p.x) + double(d.x) * tb, Z = double(p.z) + double(d.z) * tb;
        if (X < b.lo.x || X > b.hi.x || Z < b.lo.y || Z > b.hi.y) {
            ++lost.offBoard;
            return;
        }
        PhotonHit ph;
        ph.u = (X * b.uv[0] + Z * b.uv[1]) + b.uv[2];
        ph.v = (X * b.uv[3] + Z * b.uv[4]) + b.uv[5];
        for (int c = 0; c < 3; ++c) ph.power[c] = double(light.intensity[c]) * w * factor[c];
        out.push_back(ph);
    };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            ++shot;
            const float x = float((i + 0.5) * cell - tanMax), y = float(tanMax - (j + 0.5) * cell);
            Ray r;
            r.origin = L;
            r.dir = glm::normalize(toWorld * glm::vec3(x, y, -1.0f));
            Hit h;
            const SurfacePoint s = accel.intersectSurface(r, h);
            if (!h.valid()) continue;
            ++lost.objectHits;
            const double cosT = double(glm::dot(r.dir, axis));
            const double dist = double(h.t);
            const double area = dist * dist * cosT * cosT * cosT * a;
            glm::vec3 nIn = glm::dot(r.dir, s.ns) < 0.0f ? s.ns : -s.ns;
            if (mat.type == MaterialType::Mirror) {
                // A mirror: one reflection at the hit, the mirror's reflectance the photon's power.
                land(s.p, reflectDir(r.dir, nIn), area, glm::dvec3(mirrorReflectance(mat, -glm::dot(r.dir, nIn))));
                continue;
            }
            // Entry: Schlick's transmittance, refraction 1 → n at the normal facing the ray.
            const double F = double(FresnelSchlick(-glm::dot(r.dir, nIn), f0));
            glm::vec3 d;
            if (!refractDir(r.dir, nIn, 1.0f / mat.ior, &d)) continue;
            glm::vec3 p = s.p;
            SurfacePoint cur = s;
            double length = 0.0;
            bool left = false, leaked = false;
            for (int k = 0; k < o.maxInterfaces && !left; ++k) {
                Ray in;
                // Off the surface by 10⁻⁴ of the point's magnitude along the geometric normal
                // (Accel::offsetOrigin's 10⁻⁵ of the object's extent alone leaves interior rays
                // re-meeting the triangle they start on).
                const float e = 1e-4f * (1.0f + std::max({std::fabs(cur.p.x), std::fabs(cur.p.y), std::fabs(cur.p.z)}));
                in.origin = cur.p + (glm::dot(d, cur.ng) >= 0.0f ? e : -e) * cur.ng;
                in.dir = d;
                Hit h2;
                const SurfacePoint s2 = accel.intersectSurface(in, h2);
                if (!h2.valid()) {  // a leak through the mesh: lost
                    ++lost.inside;
                    leaked = true;
                    break;
                }
                length += double(glm::length(s2.p - p));
                p = s2.p;
                cur = s2;
                const glm::vec3 nI = glm::dot(d, s2.ns) < 0.0f ? s2.ns : -s2.ns;
                glm::vec3 t;
                if (refractDir(d, nI, mat.ior, &t)) {
                    d = t;
                    left = true;
                } else {
                    d = reflectDir(d, nI);  // total internal reflection: still inside
                }
            }
            if (!left) {
                if (!leaked) ++lost.interfaces;
                continue;
            }
            glm::dvec3 absorbed;
            for (int c = 0; c < 3; ++c) absorbed[c] = std::pow(double(mat.transmittance[c]), length);
            land(p, d, (1.0 - F) * area, absorbed);
        }
}

}  // namespace

CausticTraceResult traceCausticLightMap(const Scene& sc, const CausticTraceOptions& o) {
    if (o.lightMapSize < 1 || o.photonsPerAxis < 1 || !(o.sigmaTexels > 0.0f))
        throw Error("caustics reference: light map " + std::to_string(o.lightMapSize) + ", photons per axis " +
                    std::to_string(o.photonsPerAxis) + ", σ " + std::to_string(o.sigmaTexels) + ": each must be positive");
    for (uint32_t obj : o.objects)
        if (obj >= sc.objects.size()) throw Error("caustics reference: object " + std::to_string(obj) + " does not exist");
    // (light, object) jobs, traced in parallel, splatted in job order.
    const size_t nJobs = sc.lights.size() * o.objects.size();
    std::vector<std::vector<PhotonHit>> hits(nJobs);
    std::vector<int64_t> shot(nJobs, 0);
    std::vector<Losses> lost(nJobs);
    tbb::parallel_for(size_t(0), nJobs, [&](size_t job) {
        const size_t l = job / o.objects.size(), k = job % o.objects.size();
        shoot(sc, o, sc.lights[l], o.objects[k], hits[job], shot[job], lost[job]);
    });
    const int M = o.lightMapSize;
    const CausticBoard& b = o.board;
    const double det = double(b.uv[0]) * double(b.uv[4]) - double(b.uv[1]) * double(b.uv[3]);
    const double texelWorld = 1.0 / (double(M) * double(M) * std::fabs(det));
    const double sigma = o.sigmaTexels, radius = 3.0 * sigma;
    const double kept = 1.0 - std::exp(-radius * radius / (2.0 * sigma * sigma));
    const double norm = 1.0 / (2.0 * std::numbers::pi * sigma * sigma * kept * texelWorld);
    std::vector<glm::dvec3> acc(size_t(M) * size_t(M), glm::dvec3(0.0));
    CausticTraceResult res;
    for (size_t job = 0; job < nJobs; ++job) {
        res.photons += shot[job];
        res.objectHits += lost[job].objectHits;
        res.lostInside += lost[job].inside;
        res.lostInterfaces += lost[job].interfaces;
        res.lostUpward += lost[job].upward;
        res.lostOffBoard += lost[job].offBoard;
        for (const PhotonHit& ph : hits[job]) {
            ++res.boardHits;
            res.boardPower += (ph.power.x + ph.power.y + ph.power.z) / 3.0;
            const double px = ph.u * M, py = ph.v * M;
            const int x0 = std::max(0, int(std::floor(px - radius))), x1 = std::min(M - 1, int(std::ceil(px + radius)));
            const int y0 = std::max(0, int(std::floor(py - radius))), y1 = std::min(M - 1, int(std::ceil(py + radius)));
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) {
                    const double dx = (x + 0.5) - px, dy = (y + 0.5) - py, r2 = dx * dx + dy * dy;
                    if (r2 > radius * radius) continue;
                    acc[size_t(y) * size_t(M) + size_t(x)] += ph.power * (norm * std::exp(-r2 / (2.0 * sigma * sigma)));
                }
        }
    }
    res.lightMap = Image(M, M, 3);
    for (int y = 0; y < M; ++y)
        for (int x = 0; x < M; ++x) res.lightMap.setRgb(x, y, glm::vec3(acc[size_t(y) * size_t(M) + size_t(x)]));
    return res;
}

}  // namespace rg::ray
