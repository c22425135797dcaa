// The Embree scene: one triangle geometry per object (geomID = object index), vertices
// transformed to world space once at build time. Robust mode (RTC_SCENE_FLAG_ROBUST) makes
// the triangle test watertight, so a ray through a shared edge or vertex hits at least one
// of the triangles around it — the all-intersections query then sees all of them through a
// context filter function and merges them.
#include "raycore/accel.h"

#include <emmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cmath>
#include <cstdio>
#include <mutex>

#include "core/error.h"
#include "accel_counting.h"

namespace rg::ray {

namespace {

void embreeError(void*, RTCError code, const char* message) {
    // Embree calls this from inside C code: never throw here; the build checks
    // rtcGetDeviceError afterwards and raises rg::Error.
    std::fprintf(stderr, "embree error %d: %s\n", int(code), message ? message : "");
}

// Written as three 16-byte stores: Embree loads (org, tnear), (dir, time) and (tfar, mask,
// id, flags) as 16-byte vectors straight after this, and a vector load over four separate
// 4-byte stores cannot be forwarded from the store buffer — it waits for them to retire.
// With field-by-field stores that stall cost about 25 ns per rtcIntersect1, a quarter of
// the traversal of a coherent ray (bench: primary_coherent/.../single).
void setRay(RTCRayHit& rh, const Ray& r) {
    static_assert(offsetof(RTCRay, org_x) == 0 && offsetof(RTCRay, tnear) == 12 &&
                  offsetof(RTCRay, dir_x) == 16 && offsetof(RTCRay, time) == 28 &&
                  offsetof(RTCRay, tfar) == 32 && offsetof(RTCRay, flags) == 44);
    _mm_store_ps(&rh.ray.org_x, _mm_setr_ps(r.origin.x, r.origin.y, r.origin.z, r.tnear));
    _mm_store_ps(&rh.ray.dir_x, _mm_setr_ps(r.dir.x, r.dir.y, r.dir.z, 0.0f));
    _mm_store_si128(reinterpret_cast<__m128i*>(&rh.ray.tfar),
                    _mm_setr_epi32(std::bit_cast<int>(r.tfar), -1 /* mask */, 0 /* id */, 0 /* flags */));
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

void setRay(RTCRay& ray, const Ray& r) {
    _mm_store_ps(&ray.org_x, _mm_setr_ps(r.origin.x, r.origin.y, r.origin.z, r.tnear));
    _mm_store_ps(&ray.dir_x, _mm_setr_ps(r.dir.x, r.dir.y, r.dir.z, 0.0f));
    _mm_store_si128(reinterpret_cast<__m128i*>(&ray.tfar),
                    _mm_setr_epi32(std::bit_cast<int>(r.tfar), -1, 0, 0));
}

// Embree's unnormalized Ng points to the side from which the vertices appear
// counter-clockwise, as our meshes wind seen from outside: it is the outward normal
// (checked by Accel.RayAtUnitSphereHitsAtTheKnownDistance).
inline glm::vec3 outwardNg(float x, float y, float z) { return {x, y, z}; }

// The Hit of a record rtcIntersect1 has just filled, every float read by a 4-byte load of
// its own. Embree writes tfar, Ng_x, Ng_y, Ng_z, u and v as separate 4-byte stores; left
// alone, GCC reads neighbours as 8-byte pairs ((tfar, mask), (Ng_x, Ng_y), (Ng_z, u)), and
// a load spanning two stores cannot be forwarded from the store buffer: it waits for both
// to retire (perf: a quarter of intersectSurface's samples; bench single/threads:1 ratio
// 0.80 -> 0.82). The empty asm takes each value in a register of its own, so the compiler
// cannot merge the loads; the values are the same.
inline Hit hitOfRecord(const RTCRayHit& rh) {
    float t = rh.ray.tfar, u = rh.hit.u, v = rh.hit.v;
    float nx = rh.hit.Ng_x, ny = rh.hit.Ng_y, nz = rh.hit.Ng_z;
    asm("" : "+x"(t), "+x"(u), "+x"(v), "+x"(nx), "+x"(ny), "+x"(nz));
    Hit h;
    h.t = t;
    h.u = u;
    h.v = v;
    h.object = rh.hit.geomID;
    h.triangle = rh.hit.primID;
    h.ng = outwardNg(nx, ny, nz);
    return h;
}

// `*out = h` as two 16-byte stores of registers, (t, u, v, object) and (triangle, ng): a
// plain copy assembled the Hit on the stack from 4- and 8-byte stores and read it back as
// 16-byte loads, which cannot be forwarded from the store buffer (perf: a sixth of
// intersectSurface's samples in the single-ray benchmark). The same bytes.
inline void storeHit(Hit& out, const Hit& h) {
    static_assert(offsetof(Hit, t) == 0 && offsetof(Hit, u) == 4 && offsetof(Hit, v) == 8 &&
                  offsetof(Hit, object) == 12 && offsetof(Hit, triangle) == 16 &&
                  offsetof(Hit, ng) == 20 && sizeof(Hit) == 32);
    float* dst = &out.t;
    _mm_storeu_ps(dst, _mm_setr_ps(h.t, h.u, h.v, std::bit_cast<float>(h.object)));
    _mm_storeu_ps(dst + 4, _mm_setr_ps(std::bit_cast<float>(h.triangle), h.ng.x, h.ng.y, h.ng.z));
}

struct CollectContext {
    RTCIntersectContext context;  // first member: Embree passes a pointer to it
    std::vector<Hit>* hits;
};

void collectFilter(const RTCFilterFunctionNArguments* args) {
    auto* c = reinterpret_cast<const CollectContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        Hit h;
        h.t = RTCRayN_tfar(args->ray, args->N, i);
        h.u = RTCHitN_u(args->hit, args->N, i);
        h.v = RTCHitN_v(args->hit, args->N, i);
        h.object = RTCHitN_geomID(args->hit, args->N, i);
        h.triangle = RTCHitN_primID(args->hit, args->N, i);
        h.ng = outwardNg(RTCHitN_Ng_x(args->hit, args->N, i), RTCHitN_Ng_y(args->hit, args->N, i),
                         RTCHitN_Ng_z(args->hit, args->N, i));
        c->hits->push_back(h);
        args->valid[i] = 0;  // reject, so traversal goes on to every other hit
    }
}

}  // namespace

RTCDevice embreeDevice() {
    static std::once_flag once;
    static RTCDevice device = nullptr;
    std::call_once(once, [] {
        device = rtcNewDevice(nullptr);
        if (!device) throw Error("embree: cannot create a device");
        rtcSetDeviceErrorFunction(device, embreeError, nullptr);
    });
    return device;
}

Accel::Accel(const Scene& scene, AccelOptions options) : scene_(scene) {
    validateScene(scene);
    RTCDevice device = embreeDevice();
    if (options.countTriangleTests) counter_ = detail::newTriangleTestCounter();
    rtcScene_ = rtcNewScene(device);
    rtcSetSceneFlags(rtcScene_, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(rtcScene_, RTC_BUILD_QUALITY_HIGH);
    geometries_.resize(scene.objects.size());
    Bounds all;
    for (uint32_t oi = 0; oi < scene.objects.size(); ++oi) {
        const Object& o = scene.objects[oi];
        Mesh m = scene.meshes[o.mesh];
        completeMesh(m);
        transformMesh(m, o.transform);
        Bounds b = computeBounds(m);
        all.lo = glm::min(all.lo, b.lo);
        all.hi = glm::max(all.hi, b.hi);
        if (counter_) {
            // The counting twin: the same triangles as a user geometry (accel_counting.cpp).
            countingMeshes_.push_back(
                std::make_unique<detail::CountingMesh>(m.positions, m.indices, counter_.get()));
            RTCGeometry g = detail::newCountingGeometry(device, *countingMeshes_.back());
            rtcCommitGeometry(g);
            rtcAttachGeometryByID(rtcScene_, g, oi);
            rtcReleaseGeometry(g);
        } else {
        RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.positions.size()));
        auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
            g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), m.triangleCount()));
        if (!vb || !ib) throw Error("embree: cannot allocate buffers for object '" + o.name + "'");
        for (size_t i = 0; i < m.positions.size(); ++i) {
            vb[3 * i] = m.positions[i].x;
            vb[3 * i + 1] = m.positions[i].y;
            vb[3 * i + 2] = m.positions[i].z;
        }
        std::copy(m.indices.begin(), m.indices.end(), ib);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(rtcScene_, g, oi);
        rtcReleaseGeometry(g);
        }
        Geometry& geo = geometries_[oi];
        if (records_.size() + m.triangleCount() > size_t(UINT32_MAX))
            throw Error("embree: the scene has more than 2^32 - 1 triangles");
        geo.base = uint32_t(records_.size());
        geo.material = &scene.materials[o.material];
        records_.resize(records_.size() + m.triangleCount());
        uint32_t part = 0;
        for (size_t t = 0; t < m.triangleCount(); ++t) {
            while (part + 1 < m.parts.size() && m.parts[part + 1].firstTriangle <= t) ++part;
            const uint32_t* tri = &m.indices[3 * t];
            TriangleRecord& rec = records_[geo.base + t];
            for (int k = 0; k < 3; ++k) {
                rec.normal[k] = m.normals[tri[k]];
                rec.uv[k] = m.uvs[tri[k]];
            }
            rec.part = part;
            // Unit face normals once here rather than a square root and a division per
            // hit; the same winding as Embree's Ng, (v1 − v0) × (v2 − v0).
            const glm::vec3& a = m.positions[tri[0]];
            glm::vec3 n = glm::cross(m.positions[tri[1]] - a, m.positions[tri[2]] - a);
            float len = glm::length(n);
            rec.faceNormal = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
        }
    }
    rtcCommitScene(rtcScene_);
    if (RTCError e = rtcGetDeviceError(device); e != RTC_ERROR_NONE)
        throw Error("embree: building the scene failed (error " + std::to_string(int(e)) + ")");
    float extent = glm::length(all.hi - all.lo);
    epsilon_ = 1e-5f * std::max(extent, 1.0f);
}

Accel::~Accel() {
    if (rtcScene_) rtcReleaseScene(rtcScene_);
}

Hit Accel::intersect(const Ray& ray) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(16) RTCRayHit rh;
    setRay(rh, ray);
    rtcIntersect1(rtcScene_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return Hit();
    return hitOfRecord(rh);
}

bool Accel::occluded(const Ray& ray) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(16) RTCRay r;
    setRay(r, ray);
    rtcOccluded1(rtcScene_, &ctx, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to −inf on a hit
}

namespace {

template <int N, class RayHitN, void (*IntersectN)(const int*, RTCScene, RTCIntersectContext*, RayHitN*)>
void intersectPacket(RTCScene scene, const Ray* rays, Hit* hits, int count) {
    alignas(64) RayHitN rh;
    alignas(64) int valid[N];
    for (int i = 0; i < N; ++i) {
        valid[i] = i < count ? -1 : 0;
        const Ray& r = rays[i < count ? i : 0];
        rh.ray.org_x[i] = r.origin.x;
        rh.ray.org_y[i] = r.origin.y;
        rh.ray.org_z[i] = r.origin.z;
        rh.ray.dir_x[i] = r.dir.x;
        rh.ray.dir_y[i] = r.dir.y;
        rh.ray.dir_z[i] = r.dir.z;
        rh.ray.tnear[i] = r.tnear;
        rh.ray.tfar[i] = r.tfar;
        rh.ray.time[i] = 0.0f;
        rh.ray.mask[i] = ~0u;
        rh.ray.id[i] = unsigned(i);
        rh.ray.flags[i] = 0;
        rh.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    IntersectN(valid, scene, &ctx, &rh);
    for (int i = 0; i < count; ++i) {
        Hit h;
        if (rh.hit.geomID[i] != RTC_INVALID_GEOMETRY_ID) {
            h.t = rh.ray.tfar[i];
            h.u = rh.hit.u[i];
            h.v = rh.hit.v[i];
            h.object = rh.hit.geomID[i];
            h.triangle = rh.hit.primID[i];
            h.ng = outwardNg(rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]);
        }
        hits[i] = h;
    }
}

}  // namespace

void Accel::intersect8(const Ray* rays, Hit* hits, int count) const {
    intersectPacket<8, RTCRayHit8, rtcIntersect8>(rtcScene_, rays, hits, std::min(count, 8));
}
void Accel::intersect16(const Ray* rays, Hit* hits, int count) const {
    intersectPacket<16, RTCRayHit16, rtcIntersect16>(rtcScene_, rays, hits, std::min(count, 16));
}

namespace {

Hit hitOf(const RTCRayHit& rh) {
    return rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? hitOfRecord(rh) : Hit();
}

constexpr size_t kStreamBatch = 256;

// rtcIntersect1M over batches of kStreamBatch rays; done(records, begin, n) after each.
template <class Done>
void traceStream(RTCScene scene, const Ray* rays, size_t count, bool coherent, Done&& done) {
    alignas(16) RTCRayHit rh[kStreamBatch];
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    for (size_t begin = 0; begin < count; begin += kStreamBatch) {
        const size_t n = std::min(kStreamBatch, count - begin);
        for (size_t i = 0; i < n; ++i) setRay(rh[i], rays[begin + i]);
        rtcIntersect1M(scene, &ctx, rh, unsigned(n), sizeof(RTCRayHit));
        done(static_cast<const RTCRayHit*>(rh), begin, n);
    }
}

}  // namespace

void Accel::intersectStream(const Ray* rays, Hit* hits, size_t count, bool coherent) const {
    traceStream(rtcScene_, rays, count, coherent, [&](const RTCRayHit* rh, size_t begin, size_t n) {
        for (size_t i = 0; i < n; ++i) hits[begin + i] = hitOf(rh[i]);
    });
}

void Accel::intersectStreamSurfaces(const Ray* rays, SurfacePoint* out, size_t count,
                                    bool coherent) const {
    static const bool avx2 = avx2Available();
    traceStream(rtcScene_, rays, count, coherent, [&](const RTCRayHit* rh, size_t begin, size_t n) {
        if (avx2) {
            resolveStreamAvx2(rh, out + begin, n, true);
        } else {
            Hit hits[kStreamBatch];
            for (size_t i = 0; i < n; ++i) hits[i] = hitOf(rh[i]);
            surfacesSse2(rays + begin, hits, out + begin, n);
        }
    });
}

// Why groups: one ray at a time (intersectSurface) resolve() costs about 12 ns after a
// primary ray's ~91 ns of traversal, and a secondary ray that hits the teapot waits for
// its record from beyond L2. Here the record's two cache lines are requested the moment
// Embree names the triangle and are in L1 by the time the group is resolved (16 rays of
// traversal later), and the resolve runs on eight lanes (resolveStreamAvx2). Measured
// (in-process A/B, thread CPU time, minimum of 40 interleaved rounds, ns per ray,
// primary / secondary): bare rtcIntersect1 loop 104.5 / 139.5; intersectSurface per ray
// 111.8 / 156.1; groups without the prefetch 98.8 / 136.3; with it 97.8 / 132.6.
// A group of 16: 1.3 KB of records that stay in L1, and enough traversal between a
// prefetch and its use.
void Accel::intersectSurfaces(const Ray* rays, SurfacePoint* out, size_t count, Hit* hits) const {
    static const bool avx2 = avx2Available();
    alignas(16) RTCRayHit rh[kSurfaceGroup];
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t begin = 0; begin < count; begin += kSurfaceGroup) {
        const size_t n = std::min(kSurfaceGroup, count - begin);
        for (size_t i = 0; i < n; ++i) {
            setRay(rh[i], rays[begin + i]);
            rtcIntersect1(rtcScene_, &ctx, &rh[i]);
            prefetchRecord(rh[i]);
        }
        Hit group[kSurfaceGroup];
        Hit* h = hits ? hits + begin : group;
        if (hits || !avx2)
            for (size_t i = 0; i < n; ++i) h[i] = hitOf(rh[i]);
        if (avx2)
            resolveStreamAvx2(rh, out + begin, n, false);
        else
            surfacesSse2(rays + begin, h, out + begin, n);
    }
}

// Every field written once, in a single aggregate: a `SurfacePoint s;` filled in
// afterwards zeroes the 72 bytes first, and the compiler keeps those stores.
__attribute__((always_inline)) inline SurfacePoint Accel::resolve(
    const glm::vec3& origin, const glm::vec3& dir, float t, float u, float v, uint32_t object,
    uint32_t triangle) const {
    const Geometry& geo = geometries_[object];
    const TriangleRecord& ts = records_[geo.base + triangle];
    const float b0 = 1.0f - u - v;
    const glm::vec3 p = origin + t * dir;
    const glm::vec3 ng = ts.faceNormal;
    glm::vec3 ns = b0 * ts.normal[0] + u * ts.normal[1] + v * ts.normal[2];
    const float lenNs = glm::length(ns);
    // One division, then multiplies: divss dominated this function's profile.
    ns = lenNs > 0.0f ? ns * (1.0f / lenNs) : ng;
    // Interpolated normals of a badly wound or inconsistent mesh may face the other way;
    // shading then follows the geometry.
    if (glm::dot(ns, ng) < 0.0f) ns = -ns;
    const glm::vec2 uv = b0 * ts.uv[0] + u * ts.uv[1] + v * ts.uv[2];
    return SurfacePoint{.p = p,
                        .ng = ng,
                        .ns = ns,
                        .uv = uv,
                        .frontFace = glm::dot(dir, ng) < 0.0f,
                        .object = object,
                        .part = ts.part,
                        .triangle = triangle,
                        .material = geo.material};
}

SurfacePoint Accel::surface(const Ray& ray, const Hit& hit) const {
    if (!hit.valid()) return SurfacePoint();
    return resolve(ray.origin, ray.dir, hit.t, hit.u, hit.v, hit.object, hit.triangle);
}

// The floats intersect() would copy into the Hit (tfar, u, v) go to resolve() directly.
//
// Where a single ray's time goes (bench .../single/threads:1, same-binary A/B, medians,
// primary / secondary): bare Embree about 90 / 122 ns; this call with resolve() replaced
// by constant stores 96 / 130, by the record's rows stored raw 98 / 135, by ns, its length
// and 1 / length only 103 / 137; as written 109 / 148. So the cost is resolve()'s ~50
// floating-point operations behind Embree's result, sharing the core with the next ray's
// traversal: 96 addps (eight chains of 12) in their place cost as much, 96 nops a quarter.
// Tried without gain: resolve() on SSE registers (40% fewer instructions), branches for
// its two selects, dropping the square root and division (to time them), vzeroupper after
// Embree, a 2 MB-aligned MADV_HUGEPAGE copy of records_, the Hit copied through integer
// registers (slower). Only the record's cache miss is worth something (2 / 8 ns with the
// record forced into L1). Prefetching it, or resolving each candidate, from an
// intersection filter is not the same bytes: Embree's filter loop goes on to the other
// hits of the leaf at the accepted distance and keeps the last of equal-t hits, where the
// plain path keeps the first (a shared edge's ties).
//
// Measured again with an in-process A/B (each variant behind a switch in one binary, the
// bench's rays and loop, thread CPU time, minimum of 60-80 interleaved rounds per quarter
// of the rays; spread 0.5-1 ns where the bench's is 3-5 ns), ns per ray, primary /
// secondary: as written 107.5 / 143; no resolve (Hit still stored) 94 / 129; the record
// read from one L1-resident line, address chain kept, 105.5 / 135. The secondary rays
// hit the room's 12 triangles 90% of the time and a random teapot triangle 10% of the
// time (its records are 3.2 MB), and those records come from beyond L2: that is the
// 6-9 ns. The interpolated normal never needs the flip or the fallback on these rays (0
// of 614,400), so no branch mispredicts either. Tried, none worth its code:
// - a 64-byte line-aligned record (normals, face normal, part) with the uvs in a 32-byte
//   side array: no change (an 80-byte record's two lines arrive together);
// - records_ on transparent huge pages (AnonHugePages confirmed): no change;
// - the prefetch from a context filter made the same bytes by redoing, without the
//   filter, every ray whose filter saw a tie (equal t after an accept): same bytes on
//   1.8 M rays of six scenes, but +6.5 / +6 ns — the filter call costs more than the miss;
// - resolve() on SSE rows (unaligned row loads at 0/12/24 floats, the SurfacePoint as
//   four 16-byte row stores through bit_cast, a quarter fewer FP operations and no
//   default-initialisation stores): -0..-2 / -1.5..-4 ns, and in retroglass bench
//   (four alternated rounds, --repetitions 5, medians) 8.92 vs 8.94 M rays/s primary, 6.69 vs 6.69
//   secondary: nothing measurable; on top of it, the square root and division removed
//   -0.8 / -0.9 (latency is not the cost), the context initialised once -0, setRay's rows
//   from two loads -0, the Hit copied as four 8-byte integer words -0.5 / -1.5, as eight
//   4-byte words +3.5; storing only the row holding ns.x -2 / -2.
// So the ~12 ns (primary) of resolve() follows neither its latency nor its count of FP
// operations; of what is known, only the secondary rays' record misses are left.
//
// What did help is not resolving one ray at a time: callers holding many rays (a row of
// camera rays) use intersectSurfaces, which prefetches each record the moment Embree
// names its triangle and resolves 16 hits on the SIMD kernels (measurements there). This
// call stays for rays whose point is needed before the next ray exists (the recursion of
// the tracers).
__attribute__((always_inline)) inline SurfacePoint Accel::traceAndResolve(const Ray& ray,
                                                                         Hit* hitOut) const {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    alignas(16) RTCRayHit rh;
    setRay(rh, ray);
    rtcIntersect1(rtcScene_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
        if (hitOut) *hitOut = Hit();
        return SurfacePoint();
    }
    const Hit h = hitOfRecord(rh);  // without hitOut, only its ng goes unused
    if (hitOut) storeHit(*hitOut, h);
    return resolve(ray.origin, ray.dir, h.t, h.u, h.v, h.object, h.triangle);
}

SurfacePoint Accel::intersectSurface(const Ray& ray) const { return traceAndResolve(ray, nullptr); }

SurfacePoint Accel::intersectSurface(const Ray& ray, Hit& hit) const {
    return traceAndResolve(ray, &hit);
}

void Accel::surfaces(const Ray* rays, const Hit* hits, SurfacePoint* out, size_t n) const {
    static const bool avx2 = avx2Available();
    if (avx2)
        surfacesAvx2(rays, hits, out, n);
    else
        surfacesSse2(rays, hits, out, n);
}

void Accel::surfacesSse2(const Ray* rays, const Hit* hits, SurfacePoint* out, size_t n) const {
    // Lane for lane the operations of surface(), in its order (glm evaluates a + b + c as
    // (a + b) + c and dot(a, b) as (a.x·b.x + a.y·b.y) + a.z·b.z); SSE's sqrt, division and
    // arithmetic round like the scalar instructions, and negation is the same sign flip.
    const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.0f);
    const __m128 sign = _mm_set1_ps(-0.0f);
    auto add = [](__m128 a, __m128 b) { return _mm_add_ps(a, b); };
    auto mul = [](__m128 a, __m128 b) { return _mm_mul_ps(a, b); };
    auto dot = [&](const __m128* a, const __m128* b) {
        return add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2]));
    };
    // Lanes without a hit (misses, the end of a partial group) read these harmless values.
    static const Hit noHit{};
    static const Ray noRay{};
    static const TriangleRecord noShading{};
    alignas(16) static const float noNormal[4] = {0.0f, 1.0f, 0.0f, 0.0f};
    // The inputs are read as 16-byte rows and transposed, four hits at a time, so that each
    // register holds one field of four hits:
    //   Hit             t u v ·            (the first 16 bytes)
    //   Ray             ox oy oz dx | dy dz tnear tfar
    //   face normal     x y z ·            (TriangleRecord's fifth row)
    //   TriangleRecord  n0 n1 n2 (9 floats) uv0 uv1 uv2 (6) part — four rows
    static_assert(offsetof(Hit, t) == 0 && offsetof(Hit, u) == 4 && offsetof(Hit, v) == 8);
    static_assert(offsetof(Ray, origin) == 0 && offsetof(Ray, dir) == 12 && sizeof(Ray) == 32);
    static_assert(offsetof(TriangleRecord, uv) == 36 && offsetof(TriangleRecord, part) == 60 &&
                  offsetof(TriangleRecord, faceNormal) == 64);
    for (size_t base = 0; base < n; base += 4) {
        const size_t m = std::min<size_t>(4, n - base);
        const Hit* h[4];
        const Ray* r[4];
        const TriangleRecord* ts[4];
        const float* g[4];
        for (size_t l = 0; l < 4; ++l) {
            const bool valid = l < m && hits[base + l].valid();
            h[l] = valid ? &hits[base + l] : &noHit;
            r[l] = valid ? &rays[base + l] : &noRay;
            ts[l] = valid ? &record(h[l]->object, h[l]->triangle) : &noShading;
            g[l] = valid ? &ts[l]->faceNormal.x : noNormal;
        }
        __m128 hit[4], ray0[4], ray1[4], ng[4], tri[4][4];
        for (int l = 0; l < 4; ++l) {
            hit[l] = _mm_loadu_ps(&h[l]->t);
            ray0[l] = _mm_loadu_ps(&r[l]->origin.x);
            ray1[l] = _mm_loadu_ps(&r[l]->origin.x + 4);
            ng[l] = _mm_loadu_ps(g[l]);
            for (int row = 0; row < 4; ++row)
                tri[row][l] = _mm_load_ps(reinterpret_cast<const float*>(ts[l]) + 4 * row);
        }
        _MM_TRANSPOSE4_PS(hit[0], hit[1], hit[2], hit[3]);
        _MM_TRANSPOSE4_PS(ray0[0], ray0[1], ray0[2], ray0[3]);
        _MM_TRANSPOSE4_PS(ray1[0], ray1[1], ray1[2], ray1[3]);
        _MM_TRANSPOSE4_PS(ng[0], ng[1], ng[2], ng[3]);
        for (int row = 0; row < 4; ++row) _MM_TRANSPOSE4_PS(tri[row][0], tri[row][1], tri[row][2], tri[row][3]);
        auto field = [&](int f) { return tri[f / 4][f % 4]; };  // float f of TriangleRecord
        const __m128 T = hit[0], U = hit[1], V = hit[2];
        const __m128 b0 = _mm_sub_ps(_mm_sub_ps(one, U), V);
        const __m128 O[3] = {ray0[0], ray0[1], ray0[2]};
        __m128 P[3], G[3] = {ng[0], ng[1], ng[2]}, D[3] = {ray0[3], ray1[0], ray1[1]}, NS[3], UV[2];
        for (int c = 0; c < 3; ++c) {
            P[c] = add(O[c], mul(T, D[c]));
            NS[c] = add(add(mul(b0, field(c)), mul(U, field(3 + c))), mul(V, field(6 + c)));
        }
        for (int c = 0; c < 2; ++c)
            UV[c] = add(add(mul(b0, field(9 + c)), mul(U, field(11 + c))), mul(V, field(13 + c)));
        const __m128 len = _mm_sqrt_ps(dot(NS, NS));
        const __m128 inv = _mm_div_ps(one, len);
        const __m128 positive = _mm_cmpgt_ps(len, zero);  // false for NaN, as in surface()
        for (int c = 0; c < 3; ++c)
            NS[c] = _mm_or_ps(_mm_and_ps(positive, mul(NS[c], inv)), _mm_andnot_ps(positive, G[c]));
        const __m128 flip = _mm_and_ps(_mm_cmplt_ps(dot(NS, G), zero), sign);
        for (int c = 0; c < 3; ++c) NS[c] = _mm_xor_ps(NS[c], flip);
        const int front = _mm_movemask_ps(_mm_cmplt_ps(dot(D, G), zero));
        alignas(16) float p[3][4], ns[3][4], st[2][4];
        for (int c = 0; c < 3; ++c) {
            _mm_store_ps(p[c], P[c]);
            _mm_store_ps(ns[c], NS[c]);
        }
        for (int c = 0; c < 2; ++c) _mm_store_ps(st[c], UV[c]);
        for (size_t l = 0; l < m; ++l) {
            SurfacePoint& s = out[base + l];
            if (h[l] == &noHit) {
                s = SurfacePoint();
                continue;
            }
            s.p = {p[0][l], p[1][l], p[2][l]};
            s.ng = {g[l][0], g[l][1], g[l][2]};
            s.ns = {ns[0][l], ns[1][l], ns[2][l]};
            s.uv = {st[0][l], st[1][l]};
            s.frontFace = (front >> l) & 1;
            s.object = h[l]->object;
            s.triangle = h[l]->triangle;
            s.part = ts[l]->part;
            s.material = geometries_[h[l]->object].material;
        }
    }
}

glm::vec3 Accel::offsetOrigin(const SurfacePoint& s, glm::vec3 dir) const {
    float e = epsilon_ * (1.0f + std::max({std::abs(s.p.x), std::abs(s.p.y), std::abs(s.p.z)}));
    return s.p + (glm::dot(dir, s.ng) >= 0.0f ? e : -e) * s.ng;
}

std::vector<Hit> Accel::allTriangleHits(const Ray& ray) const {
    if (counter_)
        throw Error("embree: the counting twin of a scene answers closest-hit and occlusion "
                    "queries only (allIntersections needs the watertight triangle kernels)");
    std::vector<Hit> hits;
    CollectContext c;
    rtcInitIntersectContext(&c.context);
    c.context.filter = collectFilter;
    c.hits = &hits;
    RTCRayHit rh;
    setRay(rh, ray);
    rtcIntersect1(rtcScene_, &c.context, &rh);
    // Order by (t, object, triangle) — a total order, so the result does not depend on the
    // traversal order; then drop repeated reports of one triangle.
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
        if (a.t != b.t) return a.t < b.t;
        if (a.object != b.object) return a.object < b.object;
        return a.triangle < b.triangle;
    });
    std::vector<Hit> unique;
    for (const Hit& h : hits) {
        bool seen = false;
        for (const Hit& u : unique)
            if (u.object == h.object && u.triangle == h.triangle) seen = true;
        if (!seen) unique.push_back(h);
    }
    return unique;
}

std::vector<Hit> Accel::allIntersections(const Ray& ray, bool frontFacingOnly) const {
    std::vector<Hit> tri = allTriangleHits(ray);
    std::vector<Hit> out;
    for (const Hit& h : tri) {
        bool front = glm::dot(ray.dir, h.ng) < 0.0f;
        if (frontFacingOnly && !front) continue;
        // A hit on a shared edge or vertex: the same surface of the same object at (nearly)
        // the same distance, facing the same way. Keep the first (smallest t, object,
        // triangle), so the choice is deterministic.
        bool duplicate = false;
        for (auto it = out.rbegin(); it != out.rend(); ++it) {
            if (h.t - it->t > 1e-5f * std::max(1.0f, h.t)) break;
            if (it->object == h.object && (glm::dot(ray.dir, it->ng) < 0.0f) == front)
                duplicate = true;
        }
        if (!duplicate) out.push_back(h);
    }
    return out;
}

}  // namespace rg::ray
