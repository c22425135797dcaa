// 000 §3's greedy two-term ray-path model. Where a primary ray first strikes a reflective
// or refractive object (the local lens object) two paths start, one with the reflection
// and one with the refraction; each is continued, at every further interface of the same
// object, by the child with the larger Fresnel coefficient until it leaves the object.
// The pixel is  T·F_T·G_T + R·F_R·G_R  where R, T are the radiances along the exit rays
// (traced on with the Whitted reference), F the products of the Fresnel coefficients along
// the path and G the products of the transparency attenuations. The two terms come back as
// separate images, with their F·G products, the exit radiances and 000 §4.3's confidence.
#pragma once

#include <functional>
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

// A path as hybrid rendering needs it at run time (000 §5): no interface points, no
// radiance (the EMs supply it), fixed size. `events` holds the greedy choices as bits
// (bit i set: interface i was a refraction; bit 0 is the initial reflection or refraction).
struct PathSummary {
    bool valid = false;
    uint8_t length = 0;         // interfaces crossed: events.size() of the RayPath
    uint32_t events = 0;
    glm::vec3 F{0.0f}, G{1.0f};
    Ray exitRay;
    friend bool operator==(const PathSummary&, const PathSummary&) = default;
};
// Event bits kept: paths longer than this count their extra events in `length` only.
constexpr int kPathEventBits = 32;

struct LensPaths {
    PathSummary reflect, refract;  // refract.valid is false for mirrors and under TIR
};

// 000 §5: the two greedy paths through a vertex of a lens object, traced with the local
// geometry only. `start` stands for the first hit: the vertex position, its shading normal
// as ns and ng, the object's material and its index in `local`, frontFace true. The paths
// are those traceTwoTerm follows from a hit there (the same Fresnel choices and G), minus
// the exit radiance and the diffuse part, so a path ends when it leaves the object.
LensPaths traceLensPaths(const Accel& local, glm::vec3 incomingDir, const SurfacePoint& start,
                         int maxDepth, RayCounts& counts);

// The RayPath of traceTwoTerm summarised (the same validity, events, F, G and exit ray).
PathSummary summarise(const RayPath& path);

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

// traceTwoTerm's two paths from a lens-object hit `hit`/`s` of `incoming` (no direct part);
// without `shadeExits` the exit radiance is left at 0 (callers shading the environment
// themselves). A hit on a diffuse object gives two invalid paths.
void traceLensHit(const Accel& accel, const Ray& incoming, const Hit& hit, const SurfacePoint& s,
                  int maxDepth, bool shadeExits, RayCounts& counts, RayPath& reflect,
                  RayPath& refract);

struct TwoTermImages {
    Image reflectTerm, refractTerm;    // R·F_R·G_R and T·F_T·G_T (RGB, sample averages)
    Image reflectFG, refractFG;        // F_R·G_R and F_T·G_T
    Image reflectF, refractF;          // F_R, F_T alone (sample averages)
    Image reflectG, refractG;          // G_R, G_T alone (sample averages over valid paths)
    Image reflectRadiance, refractRadiance;  // R and T
    Image direct;                      // see TwoTermSample::direct
    Image sum;                         // direct + reflectTerm + refractTerm
    Image lensCoverage;                // 1 channel: fraction of samples whose primary ray
                                       // hit a reflective or refractive object
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

// 000 §4.1 for one lens object, as the layered-EM precompute needs it: for every sample of
// a supersampled image whose incoming ray reaches `lensObject`, the two greedy paths and,
// per exit ray, the environment it meets.
//
//  - Incoming continuation (Figure 4b): the incoming ray is continued through every other
//    object in front of the lens object, so occluded parts of it (the teapot behind the
//    cup) still make records; `occluded` says so. Off: only samples whose first hit is
//    the lens object.
//  - Outgoing continuation (Figure 4c): every front-facing intersection along the exit
//    ray with environmental geometry (any object but the lens object itself), nearest
//    first. Off: the exit ray's first intersection only.
//  - With `layerOfObject` (object → layer, −1 for none) only the first intersection of
//    each layer is kept (000 §4.1: "discard all but the first intersection of each
//    outgoing ray with that layer") and shaded: its colour is the radiance the ray tracer
//    sees along the exit ray at that point (Whitted, the path's depth). Empty: every hit is
//    kept, unshaded (the clustering pass). An exit ray meeting nothing records one hit on
//    object kNoHit at t = +∞ with the environment's radiance as its colour.
struct LensRecordOptions {
    uint32_t lensObject = kNoHit;
    bool incomingContinuation = true;
    bool outgoingContinuation = true;
    std::vector<int> layerOfObject;
};
struct LensHit {
    uint32_t object = kNoHit;
    int layer = -1;
    float t = 0.0f;
    glm::vec3 p{0.0f};
    glm::vec3 color{0.0f};
};
struct LensSampleRecord {
    int x = 0, sx = 0, sy = 0;
    bool occluded = false;
    PathSummary path[2];                 // 0 reflection, 1 refraction
    uint32_t firstHit[2] = {0, 0}, hitCount[2] = {0, 0};  // ranges of LensRecordRow::hits
};
// One image row's records, samples in (x, sy, sx) order.
struct LensRecordRow {
    int y = 0;
    std::vector<LensSampleRecord> samples;
    std::vector<LensHit> hits;
};
// Calls `row` once per image row with its records, possibly from several threads at once
// (each row once; the callee writes only that row's results).
void compileLensRecords(const Accel& accel, const Camera& camera, const RenderOptions& options,
                        const LensRecordOptions& lens,
                        const std::function<void(const LensRecordRow&)>& row);

}  // namespace rg::ray
