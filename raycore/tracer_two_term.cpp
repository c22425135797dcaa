// 000 §3: the greedy two-term ray-path model, and §4.3's confidence.
#include "raycore/tracer_two_term.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>

#include "raycore/fresnel.h"
#include "raycore/tracer_whitted.h"

namespace rg::ray {

namespace {

// What a path records as it goes: the full RayPath (vertices, events; the exit radiance
// when shading) or the run-time PathSummary (event bits only).
void beginPath(RayPath& p, PathEvent first, glm::vec3 F, const glm::vec3& at) {
    p.valid = true;
    p.F = F;
    p.G = glm::vec3(1.0f);
    p.events.push_back(first);
    p.vertices.push_back(at);
}
void beginPath(PathSummary& p, PathEvent first, glm::vec3 F, const glm::vec3&) {
    p.valid = true;
    p.F = F;
    p.G = glm::vec3(1.0f);
    p.length = 1;
    p.events = first == PathEvent::Refract ? 1u : 0u;
}
void addEvent(RayPath& p, PathEvent e, const glm::vec3& at) {
    p.events.push_back(e);
    p.vertices.push_back(at);
}
void addEvent(PathSummary& p, PathEvent e, const glm::vec3&) {
    if (p.length < kPathEventBits && e == PathEvent::Refract) p.events |= 1u << p.length;
    if (p.length < 255) ++p.length;
}
void setExit(RayPath& p, const Ray& ray, const Hit& hit) {
    p.exitRay = ray;
    p.exitHit = hit;
}
void setExit(PathSummary& p, const Ray& ray, const Hit&) { p.exitRay = ray; }

// Continues a path from surface point `s` of the lens object in direction `dir`: at every
// further interface of the same object, the child with the larger Fresnel coefficient.
// With `shadeExit` the radiance along the exit ray is traced on (Whitted); the run-time
// summary never shades.
template <class Path>
void followPath(const Accel& accel, const SurfacePoint& s, glm::vec3 dir, PathEvent first,
                glm::vec3 F, int maxDepth, bool shadeExit, RayCounts& counts, Path& path) {
    beginPath(path, first, F, s.p);
    Ray ray;
    ray.dir = dir;
    ray.origin = accel.offsetOrigin(s, dir);
    RayKind kind = first == PathEvent::Reflect ? RayKind::Reflection : RayKind::Refraction;
    int depth = 1;
    for (;;) {
        counts.add(kind);
        Hit hit;
        const SurfacePoint p = accel.intersectSurface(ray, hit);
        if (!hit.valid() || hit.object != s.object) {
            // Left the local object: R or T is the radiance along this exit ray.
            setExit(path, ray, hit);
            if constexpr (std::is_same_v<Path, RayPath>)
                if (shadeExit) path.radiance = whittedShade(accel, ray, hit, p, depth, maxDepth, counts);
            return;
        }
        const Material& m = *p.material;
        if (!p.frontFace && m.type == MaterialType::Glass)
            path.G *= transparencyAttenuation(m.transmittance, hit.t);
        if (depth >= maxDepth || m.type == MaterialType::Diffuse) {
            // The path ends inside the object (depth budget) or on a part that neither
            // reflects nor refracts: it contributes nothing.
            path.valid = false;
            setExit(path, ray, hit);
            return;
        }
        const glm::vec3 n = p.frontFace ? p.ns : -p.ns;
        const float cosI = std::max(0.0f, -glm::dot(ray.dir, n));
        glm::vec3 next;
        if (m.type == MaterialType::Mirror) {
            path.F *= mirrorReflectance(m, cosI);
            next = mirrorDirection(p, ray.dir);
            addEvent(path, PathEvent::Reflect, p.p);
            kind = RayKind::Reflection;
        } else {
            const float etaI = p.frontFace ? 1.0f : m.ior, etaT = p.frontFace ? m.ior : 1.0f;
            float FR = FresnelDielectric(cosI, etaI, etaT);
            glm::vec3 t;
            bool canRefract = refractDir(ray.dir, n, etaI / etaT, &t);
            if (!canRefract) FR = 1.0f;
            // Greedy: the child with the greater coefficient (ties go to reflection).
            if (FR >= 1.0f - FR) {
                path.F *= FR;
                next = mirrorDirection(p, ray.dir);
                addEvent(path, PathEvent::Reflect, p.p);
                kind = RayKind::Reflection;
            } else {
                path.F *= 1.0f - FR;
                next = t;
                addEvent(path, PathEvent::Refract, p.p);
                kind = RayKind::Refraction;
            }
        }
        ray.dir = next;
        ray.origin = accel.offsetOrigin(p, next);
        ++depth;
    }
}

// The two paths from the first hit `s` of a lens object (both for glass, the reflection
// for a mirror); the first segment's attenuation when the ray arrived from inside.
template <class Path>
void startPaths(const Accel& accel, glm::vec3 dir, const SurfacePoint& s, float hitT,
                int maxDepth, bool shadeExits, RayCounts& counts, Path& reflect, Path& refract) {
    const Material& m = *s.material;
    const glm::vec3 n = s.frontFace ? s.ns : -s.ns;
    const float cosI = std::max(0.0f, -glm::dot(dir, n));
    const glm::vec3 r = mirrorDirection(s, dir);
    if (m.type == MaterialType::Mirror) {
        followPath(accel, s, r, PathEvent::Reflect, mirrorReflectance(m, cosI), maxDepth,
                   shadeExits, counts, reflect);
        return;
    }
    const float etaI = s.frontFace ? 1.0f : m.ior, etaT = s.frontFace ? m.ior : 1.0f;
    float FR = FresnelDielectric(cosI, etaI, etaT);
    glm::vec3 t;
    bool canRefract = refractDir(dir, n, etaI / etaT, &t);
    if (!canRefract) FR = 1.0f;
    followPath(accel, s, r, PathEvent::Reflect, glm::vec3(FR), maxDepth, shadeExits, counts,
               reflect);
    if (canRefract)
        followPath(accel, s, t, PathEvent::Refract, glm::vec3(1.0f - FR), maxDepth, shadeExits,
                   counts, refract);
    // A first hit on a back face (camera inside the glass) attenuates both terms alike.
    if (!s.frontFace) {
        glm::vec3 g = transparencyAttenuation(m.transmittance, hitT);
        reflect.G *= g;
        refract.G *= g;
    }
}

}  // namespace

TwoTermSample traceTwoTerm(const Accel& accel, const Ray& primary, int maxDepth,
                           RayCounts& counts) {
    Hit hit;
    const SurfacePoint s = accel.intersectSurface(primary, hit);
    return traceTwoTerm(accel, primary, hit, s, maxDepth, counts);
}

TwoTermSample traceTwoTerm(const Accel& accel, const Ray& primary, const Hit& hit,
                           const SurfacePoint& s, int maxDepth, RayCounts& counts) {
    TwoTermSample out;
    if (!hit.valid()) {
        out.direct = accel.scene().environment.lookup(primary.dir);
        return out;
    }
    const Material& m = *s.material;
    if (m.type == MaterialType::Diffuse || maxDepth <= 0) {
        out.direct = whittedShade(accel, primary, hit, s, 0, maxDepth, counts);
        return out;
    }
    out.hitLens = true;
    out.lensObject = s.object;
    out.direct = diffuseLighting(accel, s, primary.dir, counts);
    startPaths(accel, primary.dir, s, hit.t, maxDepth, true, counts, out.reflect, out.refract);
    return out;
}

void traceLensHit(const Accel& accel, const Ray& incoming, const Hit& hit, const SurfacePoint& s,
                  int maxDepth, bool shadeExits, RayCounts& counts, RayPath& reflect,
                  RayPath& refract) {
    reflect = RayPath();
    refract = RayPath();
    if (!hit.valid() || maxDepth <= 0 || s.material->type == MaterialType::Diffuse) return;
    startPaths(accel, incoming.dir, s, hit.t, maxDepth, shadeExits, counts, reflect, refract);
}

LensPaths traceLensPaths(const Accel& local, glm::vec3 incomingDir, const SurfacePoint& start,
                         int maxDepth, RayCounts& counts) {
    LensPaths out;
    if (maxDepth <= 0 || !start.material || start.material->type == MaterialType::Diffuse)
        return out;
    startPaths(local, incomingDir, start, 0.0f, maxDepth, false, counts, out.reflect, out.refract);
    return out;
}

PathSummary summarise(const RayPath& path) {
    PathSummary s;
    s.valid = path.valid;
    s.F = path.F;
    s.G = path.G;
    s.exitRay = path.exitRay;
    if (path.events.empty()) return s;
    beginPath(s, path.events[0], path.F, glm::vec3(0.0f));
    s.valid = path.valid;
    for (size_t i = 1; i < path.events.size(); ++i) addEvent(s, path.events[i], glm::vec3(0.0f));
    return s;
}

float pathConfidence(const std::vector<glm::vec3>& dirs, float thetaCDegrees) {
    if (dirs.size() < 2) return 1.0f;
    float minCos = 1.0f;
    for (size_t i = 0; i < dirs.size(); ++i)
        for (size_t j = i + 1; j < dirs.size(); ++j)
            minCos = std::min(minCos, glm::dot(dirs[i], dirs[j]));
    const float thetaM = std::acos(std::clamp(minCos, -1.0f, 1.0f));
    const float thetaC = thetaCDegrees * std::numbers::pi_v<float> / 180.0f;
    const float m2 = std::min(thetaM * thetaM, thetaC * thetaC);
    return 1.0f - m2 / (thetaC * thetaC);
}

TwoTermImages renderTwoTerm(const Accel& accel, const Camera& camera, const RenderOptions& o) {
    TwoTermImages im;
    for (Image* i : {&im.reflectTerm, &im.refractTerm, &im.reflectFG, &im.refractFG,
                     &im.reflectF, &im.refractF, &im.reflectG, &im.refractG,
                     &im.reflectRadiance, &im.refractRadiance, &im.direct, &im.sum})
        *i = Image(o.width, o.height, 3);
    im.lensCoverage = Image(o.width, o.height, 1);
    im.reflectConfidence = Image(o.width, o.height, 1, 1.0f);
    im.refractConfidence = Image(o.width, o.height, 1, 1.0f);
    const int n = std::max(1, o.spp);
    const float inv = 1.0f / float(n * n);
    parallelRows(o, [&](int y, RayCounts& counts) {
        // The row's camera rays traced ahead, a chunk of pixels at a time (CameraRowRays).
        CameraRowRays row(accel, camera, o, y);
        std::vector<glm::vec3> dirsR, dirsT;
        for (int x = 0; x < o.width; ++x) {
            glm::vec3 termR(0.0f), termT(0.0f), fgR(0.0f), fgT(0.0f), radR(0.0f), radT(0.0f),
                direct(0.0f), fR(0.0f), fT(0.0f), gR(0.0f), gT(0.0f);
            dirsR.clear();
            dirsT.clear();
            int lensSamples = 0;
            const CameraRowRays::Samples px = row.pixel(x);
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    const size_t i = size_t(sy * n + sx);
                    counts.add(RayKind::Primary);
                    TwoTermSample s = traceTwoTerm(accel, px.rays[i], px.hits[i], px.points[i], o.maxDepth, counts);
                    direct += s.direct;
                    lensSamples += s.hitLens ? 1 : 0;
                    if (s.reflect.valid) {
                        glm::vec3 fg = s.reflect.F * s.reflect.G;
                        fgR += fg;
                        fR += s.reflect.F;
                        gR += s.reflect.G;
                        radR += s.reflect.radiance;
                        termR += s.reflect.radiance * fg;
                        dirsR.push_back(s.reflect.exitRay.dir);
                    }
                    if (s.refract.valid) {
                        glm::vec3 fg = s.refract.F * s.refract.G;
                        fgT += fg;
                        fT += s.refract.F;
                        gT += s.refract.G;
                        radT += s.refract.radiance;
                        termT += s.refract.radiance * fg;
                        dirsT.push_back(s.refract.exitRay.dir);
                    }
                }
            im.reflectTerm.setRgb(x, y, termR * inv);
            im.refractTerm.setRgb(x, y, termT * inv);
            im.reflectFG.setRgb(x, y, fgR * inv);
            im.refractFG.setRgb(x, y, fgT * inv);
            im.reflectF.setRgb(x, y, fR * inv);
            im.refractF.setRgb(x, y, fT * inv);
            if (!dirsR.empty()) im.reflectG.setRgb(x, y, gR / float(dirsR.size()));
            if (!dirsT.empty()) im.refractG.setRgb(x, y, gT / float(dirsT.size()));
            im.reflectRadiance.setRgb(x, y, radR * inv);
            im.refractRadiance.setRgb(x, y, radT * inv);
            im.direct.setRgb(x, y, direct * inv);
            im.sum.setRgb(x, y, (direct + termR + termT) * inv);
            im.lensCoverage.at(x, y, 0) = float(lensSamples) * inv;
            im.reflectConfidence.at(x, y, 0) = pathConfidence(dirsR);
            im.refractConfidence.at(x, y, 0) = pathConfidence(dirsT);
        }
    });
    return im;
}

}  // namespace rg::ray
