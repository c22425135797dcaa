// The Embree 3 acceleration structure of a Scene: one triangle geometry per object, in
// world space, built in robust mode so rays aimed exactly at shared edges and vertices
// never slip through (the all-intersections query relies on it).
#pragma once

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <vector>

#include "raycore/camera.h"
#include "raycore/scene.h"

namespace rg::ray {

constexpr uint32_t kNoHit = ~0u;

// What Embree reports, before shading.
struct Hit {
    float t = 0.0f;
    float u = 0.0f, v = 0.0f;        // barycentrics: p = (1−u−v)·p0 + u·p1 + v·p2
    uint32_t object = kNoHit;        // Scene::objects index (Embree geomID)
    uint32_t triangle = kNoHit;      // triangle of the object's mesh (Embree primID)
    glm::vec3 ng{0.0f};              // geometric normal, not normalized
    bool valid() const { return object != kNoHit; }
};

// How an Accel is built. countTriangleTests makes the counting twin of 000 §6's table
// ("triangle intersection tests", hits and misses alike): every object becomes an Embree
// user geometry whose intersection callback tests one triangle (Möller–Trumbore, float)
// and counts it, so the same queries through the same BVH builder report how many
// ray/triangle tests they cost. Embree's own triangle kernels have no counter. The twin is
// for counting only: it is several times slower, is never timed, and its hits may differ
// from the watertight kernels' in the last bit (allIntersections is refused on it).
struct AccelOptions {
    bool countTriangleTests = false;
};

namespace detail {
struct CountingMesh;
struct TriangleTestCounter;
}  // namespace detail

// A hit resolved to surface quantities.
struct SurfacePoint {
    glm::vec3 p{0.0f};
    glm::vec3 ng{0.0f};        // unit geometric normal, as the mesh winds it
    glm::vec3 ns{0.0f};        // unit interpolated shading normal, same side as ng
    glm::vec2 uv{0.0f};
    bool frontFace = true;     // the ray arrived against ng (from outside)
    uint32_t object = kNoHit, part = 0, triangle = kNoHit;
    const Material* material = nullptr;
};

// Built once per scene (validateScene first: bad scenes raise rg::Error before Embree sees
// them); the scene must outlive it. All queries are const and thread-safe.
class Accel {
  public:
    explicit Accel(const Scene& scene, AccelOptions options = {});
    ~Accel();
    Accel(const Accel&) = delete;
    Accel& operator=(const Accel&) = delete;

    const Scene& scene() const { return scene_; }
    RTCScene embreeScene() const { return rtcScene_; }
    // A scale for self-intersection offsets: 1e-4 of the scene's bounding extent (well
    // above float error at the hit, well below any feature of the built-in scenes).
    float epsilon() const { return epsilon_; }

    Hit intersect(const Ray& ray) const;
    bool occluded(const Ray& ray) const;

    // The counting twin (AccelOptions::countTriangleTests): triangle tests since the build
    // or the last reset, summed over every thread that queried it. 0 on a plain Accel.
    bool counting() const { return counter_ != nullptr; }
    uint64_t triangleTests() const;
    void resetTriangleTests() const;
    // Packets of 8 or 16 (Embree's SIMD ray layouts), for coherent primary rays.
    void intersect8(const Ray* rays, Hit* hits, int count) const;
    void intersect16(const Ray* rays, Hit* hits, int count) const;
    // A stream of any length (rtcIntersect1M): Embree regroups the rays itself; `coherent`
    // tells it the rays start together and point alike (camera rays), so it traces them as
    // packets.
    void intersectStream(const Ray* rays, Hit* hits, size_t count, bool coherent) const;
    // intersectStream, then surfaces() of its hits, in one pass: each batch's hits are
    // resolved straight from Embree's ray records (no Hit array between the two), with the
    // same values bit for bit (tests/raycore/test_accel.cpp). Misses give SurfacePoint().
    void intersectStreamSurfaces(const Ray* rays, SurfacePoint* out, size_t count, bool coherent) const;

    // intersectSurface() of `count` rays into out[0..count): each ray traversed on its own
    // (rtcIntersect1, the query intersect() makes), the hits resolved together in groups of
    // kSurfaceGroup straight from Embree's records. The same points bit for bit
    // (tests/raycore/test_accel.cpp), and `hits`, when given, gets intersect()'s Hit of
    // each ray. For callers holding many rays at once (a row of camera rays): a hit's
    // triangle record is prefetched as soon as Embree returns, so it arrives while the
    // next rays are traversed, and the group is resolved on eight SIMD lanes instead of
    // one ray at a time.
    void intersectSurfaces(const Ray* rays, SurfacePoint* out, size_t count, Hit* hits = nullptr) const;
    static constexpr size_t kSurfaceGroup = 16;

    SurfacePoint surface(const Ray& ray, const Hit& hit) const;
    // intersect() then surface() in one call, resolved straight from Embree's ray record
    // (no Hit between them): the same SurfacePoint bit for bit (tests/raycore/test_accel.cpp);
    // a miss gives SurfacePoint(). The second form also sets `hit` to what intersect()
    // returns, for callers that pass the Hit on.
    SurfacePoint intersectSurface(const Ray& ray) const;
    SurfacePoint intersectSurface(const Ray& ray, Hit& hit) const;
    // surface() of n hits at once, for streams and packets: the same values bit for bit
    // (tests/raycore/test_accel.cpp), four hits to the SSE lanes, so that four normals'
    // square roots and divisions overlap instead of following one another.
    void surfaces(const Ray* rays, const Hit* hits, SurfacePoint* out, size_t n) const;
    // The two kernels behind surfaces(), public so that the tests hold each to surface():
    // SSE2 (four hits a register) always; AVX2 (eight, raycore/accel_surfaces_avx2.cpp)
    // only where avx2Available() — the CPU has it and RETROGLASS_NO_AVX2 is not set —
    // which is when surfaces() takes it.
    void surfacesSse2(const Ray* rays, const Hit* hits, SurfacePoint* out, size_t n) const;
    void surfacesAvx2(const Ray* rays, const Hit* hits, SurfacePoint* out, size_t n) const;
    static bool avx2Available();

    // Every intersection along the ray in [tnear, tfar], nearest first, duplicates removed:
    // a ray through a shared edge or vertex meets every triangle around it at the same t
    // and is reported once per surface there (hits within 1e-5·t of each other on the same
    // object are one). frontFacingOnly keeps hits arriving against ng.
    std::vector<Hit> allIntersections(const Ray& ray, bool frontFacingOnly) const;
    // The same before duplicate removal (every triangle the filter saw), for tests.
    std::vector<Hit> allTriangleHits(const Ray& ray) const;

    // Offsets a ray origin off the surface on the side `dir` goes to.
    glm::vec3 offsetOrigin(const SurfacePoint& s, glm::vec3 dir) const;

  private:
    // Everything resolving a hit reads about its triangle, in one record: the three vertex
    // normals and uvs, the part and the unit face normal (world space, the winding of
    // Embree's Ng), 80 bytes. All objects' records lie in one array, object after object,
    // so a hit's record is records_[geometries_[object].base + triangle]: one dependent
    // load chain and two adjacent cache lines, where a vector per object had the shading
    // line and a face-normal line apart from it. The batch kernels read each record as
    // five 16-byte rows (the last: face normal, pad).
    struct alignas(16) TriangleRecord {
        glm::vec3 normal[3];
        glm::vec2 uv[3];
        uint32_t part;
        glm::vec3 faceNormal;
        uint32_t pad = 0;
    };
    static_assert(sizeof(TriangleRecord) == 80);
    struct Geometry {
        uint32_t base = 0;  // its first triangle's index in records_
        const Material* material = nullptr;
    };
    // The record of triangle `triangle` of object `object`.
    const TriangleRecord& record(uint32_t object, uint32_t triangle) const {
        return records_[geometries_[object].base + triangle];
    }
    // Requests the record of the hit Embree has written into rh (none on a miss). A
    // 16-byte-aligned 80-byte record spans exactly two cache lines: its first and last
    // byte name both.
    void prefetchRecord(const RTCRayHit& rh) const {
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return;
        const char* rec = reinterpret_cast<const char*>(&record(rh.hit.geomID, rh.hit.primID));
        __builtin_prefetch(rec);
        __builtin_prefetch(rec + sizeof(TriangleRecord) - 1);
    }
    // surface()'s arithmetic for a hit on (object, triangle), shared by surface() and
    // intersectSurface() so that both do the same operations in the same order.
    SurfacePoint resolve(const glm::vec3& origin, const glm::vec3& dir, float t, float u, float v,
                         uint32_t object, uint32_t triangle) const;
    // Both intersectSurface(): hitOut (may be null) gets intersect()'s Hit.
    SurfacePoint traceAndResolve(const Ray& ray, Hit* hitOut) const;
    // intersectStreamSurfaces' AVX2 kernel: surfaces() of n records Embree has filled.
    // prefetchAhead: request the records of hits 32 ahead before each group of eight.
    void resolveStreamAvx2(const RTCRayHit* rh, SurfacePoint* out, size_t n, bool prefetchAhead) const;
    const Scene& scene_;
    RTCScene rtcScene_ = nullptr;
    // The counting twin's triangles (one per object, the callbacks' user data) and its
    // per-thread counters (raycore/accel_counting.cpp); empty and null on a plain Accel.
    std::vector<std::unique_ptr<detail::CountingMesh>> countingMeshes_;
    std::unique_ptr<detail::TriangleTestCounter> counter_;
    std::vector<TriangleRecord> records_;
    std::vector<Geometry> geometries_;  // per object (Embree geomID)
    float epsilon_ = 1e-4f;
};

// The process-wide Embree device (created on first use, error callback raising rg::Error).
RTCDevice embreeDevice();

}  // namespace rg::ray
