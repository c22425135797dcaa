// The counting twin of an Accel: the triangle tests of 000 §6's table. Embree builds its
// BVH over the triangles' boxes as it does for its own triangle geometry, and calls
// countingIntersect / countingOccluded once per triangle a traversal reaches, which is the
// definition of a test (a hit or a miss). Only the count is wanted, so the test is a plain
// float Möller–Trumbore; the plain Accel's watertight kernels stay the timed ones.
#include "accel_counting.h"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "raycore/accel.h"

namespace rg::ray::detail {

uint64_t TriangleTestCounter::total() const {
    uint64_t n = 0;
    for (uint64_t c : perThread) n += c;
    return n;
}

void TriangleTestCounter::reset() {
    for (uint64_t& c : perThread) c = 0;
}

std::unique_ptr<TriangleTestCounter> newTriangleTestCounter() {
    return std::make_unique<TriangleTestCounter>();
}

bool intersectTriangle(const glm::vec3& org, const glm::vec3& dir, float tnear, float tfar,
                       const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, float& t,
                       float& u, float& v) {
    const glm::vec3 e1 = p1 - p0, e2 = p2 - p0;
    const glm::vec3 pv = glm::cross(dir, e2);
    const float det = glm::dot(e1, pv);
    if (det == 0.0f || !std::isfinite(det)) return false;
    const float inv = 1.0f / det;
    const glm::vec3 tv = org - p0;
    u = glm::dot(tv, pv) * inv;
    if (u < 0.0f || u > 1.0f) return false;
    const glm::vec3 qv = glm::cross(tv, e1);
    v = glm::dot(dir, qv) * inv;
    if (v < 0.0f || u + v > 1.0f) return false;
    t = glm::dot(e2, qv) * inv;
    return t >= tnear && t <= tfar;
}

namespace {

void countingBounds(const RTCBoundsFunctionArguments* args) {
    const auto* m = static_cast<const CountingMesh*>(args->geometryUserPtr);
    const uint32_t* tri = &m->indices[3 * size_t(args->primID)];
    glm::vec3 lo = m->positions[tri[0]], hi = lo;
    for (int k = 1; k < 3; ++k) {
        lo = glm::min(lo, m->positions[tri[k]]);
        hi = glm::max(hi, m->positions[tri[k]]);
    }
    RTCBounds* b = args->bounds_o;
    b->lower_x = lo.x, b->lower_y = lo.y, b->lower_z = lo.z;
    b->upper_x = hi.x, b->upper_y = hi.y, b->upper_z = hi.z;
}

void countingIntersect(const RTCIntersectFunctionNArguments* args) {
    const auto* m = static_cast<const CountingMesh*>(args->geometryUserPtr);
    const uint32_t* tri = &m->indices[3 * size_t(args->primID)];
    const glm::vec3 &p0 = m->positions[tri[0]], &p1 = m->positions[tri[1]],
                    &p2 = m->positions[tri[2]];
    const unsigned N = args->N;
    RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, N);
    RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, N);
    uint64_t tests = 0;
    for (unsigned i = 0; i < N; ++i) {
        if (args->valid[i] != -1) continue;
        ++tests;
        const glm::vec3 org(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i),
                            RTCRayN_org_z(ray, N, i));
        const glm::vec3 dir(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i),
                            RTCRayN_dir_z(ray, N, i));
        float t, u, v;
        if (!intersectTriangle(org, dir, RTCRayN_tnear(ray, N, i), RTCRayN_tfar(ray, N, i), p0,
                               p1, p2, t, u, v))
            continue;
        const glm::vec3 ng = glm::cross(p1 - p0, p2 - p0);  // Embree's Ng winding
        RTCRayN_tfar(ray, N, i) = t;
        RTCHitN_u(hit, N, i) = u;
        RTCHitN_v(hit, N, i) = v;
        RTCHitN_Ng_x(hit, N, i) = ng.x;
        RTCHitN_Ng_y(hit, N, i) = ng.y;
        RTCHitN_Ng_z(hit, N, i) = ng.z;
        RTCHitN_primID(hit, N, i) = args->primID;
        RTCHitN_geomID(hit, N, i) = args->geomID;
        RTCHitN_instID(hit, N, i, 0) = args->context->instID[0];
    }
    m->counter->perThread.local() += tests;
}

void countingOccluded(const RTCOccludedFunctionNArguments* args) {
    const auto* m = static_cast<const CountingMesh*>(args->geometryUserPtr);
    const uint32_t* tri = &m->indices[3 * size_t(args->primID)];
    const glm::vec3 &p0 = m->positions[tri[0]], &p1 = m->positions[tri[1]],
                    &p2 = m->positions[tri[2]];
    const unsigned N = args->N;
    RTCRayN* ray = args->ray;
    uint64_t tests = 0;
    for (unsigned i = 0; i < N; ++i) {
        if (args->valid[i] != -1) continue;
        ++tests;
        const glm::vec3 org(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i),
                            RTCRayN_org_z(ray, N, i));
        const glm::vec3 dir(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i),
                            RTCRayN_dir_z(ray, N, i));
        float t, u, v;
        if (intersectTriangle(org, dir, RTCRayN_tnear(ray, N, i), RTCRayN_tfar(ray, N, i), p0,
                              p1, p2, t, u, v))
            RTCRayN_tfar(ray, N, i) = -std::numeric_limits<float>::infinity();
    }
    m->counter->perThread.local() += tests;
}

}  // namespace

RTCGeometry newCountingGeometry(RTCDevice device, CountingMesh& mesh) {
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, unsigned(mesh.indices.size() / 3));
    rtcSetGeometryUserData(g, &mesh);
    rtcSetGeometryBoundsFunction(g, countingBounds, nullptr);
    rtcSetGeometryIntersectFunction(g, countingIntersect);
    rtcSetGeometryOccludedFunction(g, countingOccluded);
    return g;
}

}  // namespace rg::ray::detail

namespace rg::ray {

uint64_t Accel::triangleTests() const { return counter_ ? counter_->total() : 0; }

void Accel::resetTriangleTests() const {
    if (counter_) counter_->reset();
}

}  // namespace rg::ray
