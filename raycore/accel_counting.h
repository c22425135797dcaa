// The counting twin of an Accel (AccelOptions::countTriangleTests): each object as an
// Embree user geometry whose callbacks test one triangle and count the test. Internal to
// raycore; Accel owns the meshes and the counter.
#pragma once

#include <embree3/rtcore.h>
#include <glm/vec3.hpp>
#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace rg::ray::detail {

// One counter per thread (no sharing on the hot path), summed when read.
struct TriangleTestCounter {
    tbb::enumerable_thread_specific<uint64_t> perThread{0};
    uint64_t total() const;
    void reset();
};
std::unique_ptr<TriangleTestCounter> newTriangleTestCounter();

// An object's world-space triangles, the user data of its geometry.
struct CountingMesh {
    CountingMesh(std::vector<glm::vec3> p, std::vector<uint32_t> i, TriangleTestCounter* c)
        : positions(std::move(p)), indices(std::move(i)), counter(c) {}
    std::vector<glm::vec3> positions;
    std::vector<uint32_t> indices;
    TriangleTestCounter* counter;
};

// A user geometry over mesh's triangles (bounds, intersect and occluded callbacks).
RTCGeometry newCountingGeometry(RTCDevice device, CountingMesh& mesh);

// The test itself (Möller & Trumbore 1997, float): the distance along the ray and Embree's
// barycentrics (p = (1−u−v)·p0 + u·p1 + v·p2) when the ray meets the triangle inside
// [tnear, tfar]. Public for the tests.
bool intersectTriangle(const glm::vec3& org, const glm::vec3& dir, float tnear, float tfar,
                       const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, float& t,
                       float& u, float& v);

}  // namespace rg::ray::detail
