// The Whitted reference tracer: the full binary ray tree.
#include "raycore/tracer_whitted.h"

#include <cmath>

#include "raycore/fresnel.h"

namespace rg::ray {

glm::vec3 diffuseAlbedo(const Scene& scene, const SurfacePoint& s) {
    const Material& m = *s.material;
    glm::vec3 a = m.diffuse;
    if (m.diffuseTexture >= 0) a *= scene.textures[size_t(m.diffuseTexture)].eval(s.uv);
    return a;
}

glm::vec3 diffuseLighting(const Accel& accel, const SurfacePoint& s, glm::vec3 viewDir,
                          RayCounts& counts, bool shadows) {
    const Scene& scene = accel.scene();
    glm::vec3 albedo = diffuseAlbedo(scene, s);
    if (albedo == glm::vec3(0.0f)) return albedo;
    // Light the side the viewer sees (walls of the room are seen from inside, the floor
    // from above; meshes that are not closed are two-sided).
    glm::vec3 n = glm::dot(viewDir, s.ns) < 0.0f ? s.ns : -s.ns;
    glm::vec3 sideNg = glm::dot(viewDir, s.ng) < 0.0f ? s.ng : -s.ng;
    glm::vec3 e = scene.ambient;
    for (const PointLight& light : scene.lights) {
        glm::vec3 toLight = light.position - s.p;
        float dist = glm::length(toLight);
        if (dist <= 0.0f) continue;
        glm::vec3 l = toLight / dist;
        float cosTheta = glm::dot(n, l);
        if (cosTheta <= 0.0f || glm::dot(sideNg, l) <= 0.0f) continue;
        if (!shadows) {
            e += light.intensity * cosTheta;
            continue;
        }
        Ray shadow;
        SurfacePoint side = s;
        side.ng = sideNg;
        shadow.origin = accel.offsetOrigin(side, l);
        shadow.dir = l;
        shadow.tfar = dist * (1.0f - 1e-4f);
        counts.add(RayKind::Shadow);
        if (accel.occluded(shadow)) continue;
        // No distance fall-off: the papers' rooms are lit evenly, and a light without
        // fall-off keeps wall textures readable in every reflection.
        e += light.intensity * cosTheta;
    }
    return albedo * e;
}

glm::vec3 mirrorDirection(const SurfacePoint& s, glm::vec3 dir) {
    const glm::vec3 ngSide = s.frontFace ? s.ng : -s.ng;
    const glm::vec3 nsSide = s.frontFace ? s.ns : -s.ns;
    glm::vec3 r = reflectDir(dir, nsSide);
    if (glm::dot(r, ngSide) <= 0.0f) r = reflectDir(dir, ngSide);
    return r;
}

glm::vec3 whittedRadiance(const Accel& accel, const Ray& ray, int depth, int maxDepth,
                          RayCounts& counts) {
    Hit hit;
    const SurfacePoint s = accel.intersectSurface(ray, hit);
    return whittedShade(accel, ray, hit, s, depth, maxDepth, counts);
}

glm::vec3 whittedShade(const Accel& accel, const Ray& ray, const Hit& hit, int depth,
                       int maxDepth, RayCounts& counts) {
    return whittedShade(accel, ray, hit, accel.surface(ray, hit), depth, maxDepth, counts);
}

glm::vec3 whittedShade(const Accel& accel, const Ray& ray, const Hit& hit, const SurfacePoint& s,
                       int depth, int maxDepth, RayCounts& counts) {
    if (!hit.valid()) return accel.scene().environment.lookup(ray.dir);
    const Material& m = *s.material;
    glm::vec3 L = diffuseLighting(accel, s, ray.dir, counts);
    if (m.type == MaterialType::Diffuse || depth >= maxDepth) return L;

    // The normal on the side the ray arrives from.
    const glm::vec3 n = s.frontFace ? s.ns : -s.ns;
    const float cosI = std::max(0.0f, -glm::dot(ray.dir, n));
    auto child = [&](glm::vec3 dir, RayKind kind) {
        Ray r;
        r.dir = dir;
        r.origin = accel.offsetOrigin(s, dir);
        counts.add(kind);
        return whittedRadiance(accel, r, depth + 1, maxDepth, counts);
    };
    if (m.type == MaterialType::Mirror) {
        glm::vec3 F = mirrorReflectance(m, cosI);
        if (F != glm::vec3(0.0f)) L += F * child(mirrorDirection(s, ray.dir), RayKind::Reflection);
        return L;
    }
    // Glass: both children, weighted by F̂_R and F̂_T = 1 − F̂_R.
    const float etaI = s.frontFace ? 1.0f : m.ior, etaT = s.frontFace ? m.ior : 1.0f;
    float FR = FresnelDielectric(cosI, etaI, etaT);
    glm::vec3 t;
    if (!refractDir(ray.dir, n, etaI / etaT, &t)) FR = 1.0f;  // TIR: only the reflection
    glm::vec3 Lg(0.0f);
    if (FR > 0.0f) Lg += FR * child(mirrorDirection(s, ray.dir), RayKind::Reflection);
    if (FR < 1.0f) Lg += (1.0f - FR) * child(t, RayKind::Refraction);
    L += Lg;
    // Arriving at a back face means this segment ran inside the glass: attenuate what
    // leaves the hit towards the ray's origin by transmittance^thickness (000 §3, G).
    if (!s.frontFace) L *= transparencyAttenuation(m.transmittance, hit.t);
    return L;
}

Image renderWhitted(const Accel& accel, const Camera& camera, const RenderOptions& o) {
    Image img(o.width, o.height, 3);
    const int n = std::max(1, o.spp);
    const float inv = 1.0f / float(n * n);
    parallelRows(o, [&](int y, RayCounts& counts) {
        // The row's camera rays traced ahead, a chunk of pixels at a time (CameraRowRays).
        CameraRowRays row(accel, camera, o, y);
        for (int x = 0; x < o.width; ++x) {
            glm::vec3 sum(0.0f);
            const CameraRowRays::Samples px = row.pixel(x);
            for (size_t i = 0; i < row.perPixel(); ++i) {
                counts.add(RayKind::Primary);
                sum += whittedShade(accel, px.rays[i], px.hits[i], px.points[i], 0, o.maxDepth, counts);
            }
            img.setRgb(x, y, sum * inv);
        }
    });
    return img;
}

}  // namespace rg::ray
