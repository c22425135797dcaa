// The reference: Whitted's ray tracer with the full binary ray tree to a given depth.
// Every glass interface spawns both children weighted by the exact Fresnel coefficients
// F̂_R and F̂_T = 1 − F̂_R (only the reflected child, with weight 1, under total internal
// reflection); mirrors spawn a reflected child weighted by their reflectance; diffuse
// surfaces take point lights with shadow rays plus ambient. Radiance leaving a glass
// volume is attenuated by transmittance^thickness (000 §3).
#pragma once

#include "raycore/accel.h"
#include "raycore/image.h"
#include "raycore/render.h"

namespace rg::ray {

// Radiance along one ray; depth is the number of interfaces already crossed.
glm::vec3 whittedRadiance(const Accel& accel, const Ray& ray, int depth, int maxDepth,
                          RayCounts& counts);
// The same, the first intersection already found (hit may be invalid: environment).
glm::vec3 whittedShade(const Accel& accel, const Ray& ray, const Hit& hit, int depth,
                       int maxDepth, RayCounts& counts);
// The same, the hit already resolved: `s` is accel.surface(ray, hit) (or what
// intersectSurface / intersectSurfaces gave with `hit`, the same point bit for bit).
glm::vec3 whittedShade(const Accel& accel, const Ray& ray, const Hit& hit, const SurfacePoint& s,
                       int depth, int maxDepth, RayCounts& counts);

// Direct lighting of the diffuse part at a surface point: albedo·(ambient + Σ visible
// light intensity·max(0, n·l)); every light counts as visible when !shadows.
glm::vec3 diffuseLighting(const Accel& accel, const SurfacePoint& s, glm::vec3 viewDir,
                          RayCounts& counts, bool shadows = true);
glm::vec3 diffuseAlbedo(const Scene& scene, const SurfacePoint& s);

// The mirror direction at a surface point for a ray arriving along `dir`, about the
// shading normal — unless that would send the ray below the geometric surface (possible
// near silhouettes, where interpolated normals lean away from the flat triangle); then
// about the geometric normal, so a convex mirror never reflects into itself.
glm::vec3 mirrorDirection(const SurfacePoint& s, glm::vec3 dir);

// An RGB image, the n×n samples of each pixel averaged with equal weights.
Image renderWhitted(const Accel& accel, const Camera& camera, const RenderOptions& options);

}  // namespace rg::ray
