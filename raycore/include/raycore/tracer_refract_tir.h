// The reference of Davis & Wyman 2007 (004 §4, Figures 1 and 8): a ray tracer that follows
// one path through a glass object — refraction where Snell's law allows it, reflection
// only under total internal reflection (no Fresnel split, no partial reflection, no
// absorption) — "reflected rays are not traced besides totally internally reflected
// rays". Diffuse surfaces are lit as the rasterized nearby-geometry pass lights them:
// albedo·(ambient + Σ I·max(0, n·l)), optionally without shadows (the image-space method
// has none). Rays that leave the scene read the environment.
#pragma once

#include "raycore/accel.h"
#include "raycore/image.h"
#include "raycore/render.h"

namespace rg::ray {

struct TirPathOptions {
    uint32_t refractor = kNoHit;  // the glass object the paths run through (Scene::objects)
    int maxSegments = 10;         // segments inside the glass a path may take (004: depth 10)
    // After maxSegments, the path leaves along its current direction as if the glass were
    // not there (traced in `withoutRefractor`): what the image-space method does when its
    // bounces are spent ("after we have bounced a sufficient number of times … quit"), so
    // at maxSegments = B it is the exact answer to the truncated problem, and at 10 the
    // paper's depth-10 reference ends a path trapped by TIR the same way. False: such a
    // path is black.
    bool leaveAfterBudget = true;
    bool shadows = false;
};

// What one camera sample's path did.
struct TirPath {
    glm::vec3 color{0.0f};
    bool hitRefractor = false;  // the camera ray's first hit is the refractor
    int segments = 0;           // segments inside the glass
    int tirCount = 0;           // total internal reflections along the path
    // The hits that end the segments inside the glass, in order (at most 32 recorded): bit
    // i of `backFacing` is set when the i-th lies on a triangle that faces away from the
    // camera ray's origin (the eye), as the rasterizer's back-facing map holds it (004 §3,
    // Figure 6: which of the two depth maps holds the true exit).
    int insideHits = 0;
    uint32_t backFacing = 0;
};

// One path. `withoutRefractor` is the same scene without the refractor; null when that
// scene is empty (the path then meets only the environment).
TirPath traceTirPath(const Accel& accel, const Accel* withoutRefractor, const Ray& ray,
                     const TirPathOptions& options, RayCounts& counts);

struct TirImages {
    Image color;       // RGB, the n×n samples averaged
    Image refractor;   // 1 channel: fraction of samples whose camera ray hits the refractor
    Image tir;         // 1 channel: fraction of samples whose path has a TIR
    Image segments;    // 1 channel: mean segments inside the glass
};
TirImages renderTirPaths(const Accel& accel, const Accel* withoutRefractor, const Camera& camera,
                         const RenderOptions& render, const TirPathOptions& options);

}  // namespace rg::ray
