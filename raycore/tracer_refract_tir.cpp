// The refraction-and-TIR path tracer (tracer_refract_tir.h).
#include "raycore/tracer_refract_tir.h"

#include "raycore/fresnel.h"
#include "raycore/tracer_whitted.h"

namespace rg::ray {

namespace {

// What a ray outside the glass sees: a diffuse surface lit, the environment, or the glass
// again (reported through `s`).
glm::vec3 shadeOutside(const Accel& accel, const Ray& ray, const Hit& hit, const SurfacePoint& s,
                       const TirPathOptions& o, RayCounts& counts) {
    if (!hit.valid()) return accel.scene().environment.lookup(ray.dir);
    return diffuseLighting(accel, s, ray.dir, counts, o.shadows);
}

}  // namespace

TirPath traceTirPath(const Accel& accel, const Accel* withoutRefractor, const Ray& camera,
                     const TirPathOptions& o, RayCounts& counts) {
    TirPath path;
    Ray ray = camera;
    Hit hit;
    SurfacePoint s = accel.intersectSurface(ray, hit);
    path.hitRefractor = hit.valid() && hit.object == o.refractor;
    bool inside = false;
    // Each loop iteration handles one hit of the current ray with the refractor.
    while (hit.valid() && hit.object == o.refractor) {
        const float eta = s.material->ior;
        const glm::vec3 n = s.frontFace ? s.ns : -s.ns;  // against the ray
        if (inside && path.insideHits < 32) {
            // The facing as rasterization decides it: by winding, seen from the eye.
            if (glm::dot(s.ng, s.p - camera.origin) > 0.0f) path.backFacing |= 1u << path.insideHits;
            ++path.insideHits;
        }
        glm::vec3 t;
        if (!inside) {
            // Entering (or re-entering after an exit): refraction from air always exists.
            if (!refractDir(ray.dir, n, 1.0f / eta, &t)) t = reflectDir(ray.dir, n);
            inside = true;
        } else if (refractDir(ray.dir, n, eta, &t)) {
            inside = false;  // leaves the glass
        } else {
            t = reflectDir(ray.dir, n);  // total internal reflection: stays inside
            ++path.tirCount;
        }
        Ray next;
        next.dir = t;
        next.origin = accel.offsetOrigin(s, t);
        counts.add(inside ? RayKind::Refraction : RayKind::Continuation);
        if (inside) {
            if (path.segments >= o.maxSegments) {
                // The budget is spent inside the glass.
                if (o.leaveAfterBudget && withoutRefractor) {
                    Hit h2;
                    SurfacePoint s2 = withoutRefractor->intersectSurface(next, h2);
                    path.color = shadeOutside(*withoutRefractor, next, h2, s2, o, counts);
                } else if (o.leaveAfterBudget) {
                    path.color = accel.scene().environment.lookup(next.dir);  // nothing else there
                } else {
                    path.color = glm::vec3(0.0f);
                }
                return path;
            }
            ++path.segments;
        }
        ray = next;
        s = accel.intersectSurface(ray, hit);
    }
    path.color = shadeOutside(accel, ray, hit, s, o, counts);
    return path;
}

TirImages renderTirPaths(const Accel& accel, const Accel* withoutRefractor, const Camera& camera,
                         const RenderOptions& r, const TirPathOptions& o) {
    TirImages out{Image(r.width, r.height, 3), Image(r.width, r.height, 1),
                  Image(r.width, r.height, 1), Image(r.width, r.height, 1)};
    const int n = std::max(1, r.spp);
    const float inv = 1.0f / float(n * n);
    parallelRows(r, [&](int y, RayCounts& counts) {
        for (int x = 0; x < r.width; ++x) {
            glm::vec3 sum(0.0f);
            float onRefractor = 0, withTir = 0, segments = 0;
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    const glm::vec2 f = samplePosition(x, y, sx, sy, n);
                    counts.add(RayKind::Primary);
                    TirPath p = traceTirPath(accel, withoutRefractor,
                                             primaryRay(camera, r.width, r.height, f.x, f.y), o, counts);
                    sum += p.color;
                    onRefractor += p.hitRefractor ? 1.0f : 0.0f;
                    withTir += p.tirCount > 0 ? 1.0f : 0.0f;
                    segments += float(p.segments);
                }
            out.color.setRgb(x, y, sum * inv);
            out.refractor.at(x, y, 0) = onRefractor * inv;
            out.tir.at(x, y, 0) = withTir * inv;
            out.segments.at(x, y, 0) = segments * inv;
        }
    });
    return out;
}

}  // namespace rg::ray
