// 000 §3's greedy two-term ray-path model. Where a primary ray first strikes a reflective
// or refractive object (the local lens object) two paths start, one with the reflection
// and one with the refraction; each is continued, at every further interface of the same
// object, by the child with the larger Fresnel coefficient until it leaves the object.
// The pixel is  T·F_T·G_T + R·F_R·G_R  where R, T are the radiances along the exit rays
// (traced on with the Whitted reference), F the products of the Fresnel coefficients along
// the path and G the products of the transparency attenuations. The two terms come back as
// separate images, with their F·G products, the exit radiances and 000 §4.3's confidence.
#pragma once

#include <vector>

#include "raycore/accel.h"
#include "raycore/image.h"
#include "raycore/render.h"

namespace rg::ray {

enum class PathEvent : uint8_t { Reflect, Refract };

// One path of the model for one incoming ray (a 000 §4.1 intersection record).
struct RayPath {
    bool valid = false;         // false: no lens object hit, or the path died (depth)
    glm::vec3 F{0.0f};          // product of Fresnel coefficients (per channel: mirrors
                                // may be coloured)
    glm::vec3 G{1.0f};          // product of transparency attenuations
    std::vector<PathEvent> events;    // first is the initial reflection or refraction
    std::vector<glm::vec3> vertices;  // interface points, in order
    Ray exitRay;                // the outgoing ray leaving the local object
    Hit exitHit;                // its first intersection (invalid: the environment)
    glm::vec3 radiance{0.0f};   // R or T: radiance along the exit ray
};

struct TwoTermSample {
    bool hitLens = false;          // the primary ray hit a reflective/refractive object
    uint32_t lensObject = kNoHit;
    glm::vec3 direct{0.0f};        // everything else: diffuse part, non-lens surfaces,
                                   // environment seen directly
    RayPath reflect, refract;      // refract.valid is false for mirrors
};

// Traces the model for one primary ray.
TwoTermSample traceTwoTerm(const Accel& accel, const Ray& primary, int maxDepth,
                           RayCounts& counts);
// The same for a primary ray already traced: `hit` and `s` are what
// accel.intersectSurface(primary, hit) gives (Accel::intersectSurfaces for many at once).
TwoTermSample traceTwoTerm(const Accel& accel, const Ray& primary, const Hit& hit,
                           const SurfacePoint& s, int maxDepth, RayCounts& counts);

struct TwoTermImages {
    Image reflectTerm, refractTerm;    // R·F_R·G_R and T·F_T·G_T (RGB, sample averages)
    Image reflectFG, refractFG;        // F_R·G_R and F_T·G_T
    Image reflectF, refractF;          // F_R, F_T alone (sample averages)
    Image reflectG, refractG;          // G_R, G_T alone (sample averages over valid paths)
    Image reflectRadiance, refractRadiance;  // R and T
    Image direct;                      // see TwoTermSample::direct
    Image sum;                         // direct + reflectTerm + refractTerm
    // 1 − min(θm², θc²)/θc², θm the largest angle between the exit rays of any two
    // samples of the pixel, θc = 5° (000 §4.3). 1 where fewer than two samples have a path.
    Image reflectConfidence, refractConfidence;  // 1 channel
};

constexpr float kConfidenceThresholdDegrees = 5.0f;
// The 000 §4.3 formula on a list of unit directions.
float pathConfidence(const std::vector<glm::vec3>& dirs,
                     float thetaCDegrees = kConfidenceThresholdDegrees);

TwoTermImages renderTwoTerm(const Accel& accel, const Camera& camera,
                            const RenderOptions& options);

// The intersection records of 000 §4.1 for every sample: pixel, sample, the two paths,
// and for each exit ray every front-facing intersection along it (continued through
// occluders), duplicates removed.
struct RayPathRecord {
    int x = 0, y = 0, sx = 0, sy = 0;
    int term = 0;                  // 0 reflection path, 1 refraction path
    RayPath path;
    std::vector<Hit> exitIntersections;
};
std::vector<RayPathRecord> compileRayPathRecords(const Accel& accel, const Camera& camera,
                                                 const RenderOptions& options);

}  // namespace rg::ray
