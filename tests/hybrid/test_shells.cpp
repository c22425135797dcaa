// 000 §4 shells: where an exit ray meets a sphere, a capped cylinder and a quad, the
// forced intersection of §4.2 for rays leaving the quad's plane, and the least-squares
// quad of known points.
#include <gtest/gtest.h>

#include "core/error.h"

#include <cmath>

#include <glm/geometric.hpp>

#include "shells.h"

namespace rg::hybrid {
namespace {

TEST(Shells, SphereFromInsideMeetsItAtItsRadius) {
    const Shell s = sphereShell({1, 2, 3}, 5.0f);
    for (const glm::vec3 d : {glm::vec3(1, 0, 0), glm::normalize(glm::vec3(1, -2, 0.5f))}) {
        bool forced = true;
        const glm::vec3 p(1.5f, 2.2f, 2.0f);
        const glm::vec3 h = s.intersect(p, d, &forced);
        EXPECT_FALSE(forced);
        EXPECT_NEAR(glm::length(h - s.origin), 5.0f, 1e-4f);
        EXPECT_NEAR(glm::length(glm::cross(h - p, d)), 0.0f, 1e-4f) << "on the ray";
        EXPECT_GT(glm::dot(h - p, d), 0.0f);
        const glm::vec4 c = s.texCoord(p, d);
        EXPECT_NEAR(glm::length(glm::vec3(c) - (h - s.origin)), 0.0f, 1e-5f);
        EXPECT_EQ(c.w, 1.0f);
    }
}

TEST(Shells, SphereMissedFromOutsideFallsBackToTheDirection) {
    const Shell s = sphereShell({0, 0, 0}, 1.0f);
    bool forced = false;
    const glm::vec3 h = s.intersect({5, 0, 0}, {1, 0, 0}, &forced);
    EXPECT_TRUE(forced);
    EXPECT_NEAR(glm::length(h - glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
}

TEST(Shells, CylinderSideAndCaps) {
    const Shell s = cylinderShell({0, 1, 0}, 4.0f, 0.0f, 3.0f);
    bool forced = true;
    glm::vec3 h = s.intersect({0, 1, 0}, {0, 0, 1}, &forced);
    EXPECT_FALSE(forced);
    EXPECT_NEAR(h.z, 4.0f, 1e-5f);
    h = s.intersect({0, 1, 0}, {0, 1, 0}, &forced);  // straight up: the top cap
    EXPECT_FALSE(forced);
    EXPECT_NEAR(h.y, 3.0f, 1e-6f);
    h = s.intersect({0, 1, 0}, glm::normalize(glm::vec3(1, -0.1f, 0)), &forced);  // side first
    EXPECT_NEAR(std::hypot(h.x, h.z), 4.0f, 1e-4f);
    h = s.intersect({0, 1, 0}, glm::normalize(glm::vec3(1, -1, 0)), &forced);  // bottom first
    EXPECT_NEAR(h.y, 0.0f, 1e-5f);
    EXPECT_NEAR(h.x, 1.0f, 1e-5f);
}

Shell unitQuad() {
    // The plane z = 5 facing the origin (normal −z), rectangle [−1, 1]² in (x, y).
    Shell q;
    q.kind = ShellKind::Quad;
    q.origin = {0, 0, 0};
    q.center = {0, 0, 5};
    q.normal = {0, 0, -1};
    q.u = {1, 0, 0};
    q.v = {0, 1, 0};
    q.uMin = q.vMin = -1.0f;
    q.uMax = q.vMax = 1.0f;
    return q;
}

TEST(Shells, QuadMapsItsRectangleToTheUnitSquare) {
    const Shell q = unitQuad();
    bool forced = true;
    glm::vec4 c = q.texCoord({0, 0, 0}, {0, 0, 1}, &forced);
    EXPECT_FALSE(forced);
    EXPECT_NEAR(c.x, 0.5f, 1e-6f);
    EXPECT_NEAR(c.y, 0.5f, 1e-6f);
    c = q.texCoord({0, 0, 0}, glm::normalize(glm::vec3(1, -1, 5)), &forced);  // the corner
    EXPECT_NEAR(c.x, 1.0f, 1e-5f);
    EXPECT_NEAR(c.y, 0.0f, 1e-5f);
}

TEST(Shells, QuadForcesRaysLeavingItsPlaneFarAlongTheirTangentialDirection) {
    const Shell q = unitQuad();
    for (const glm::vec3 d : {glm::normalize(glm::vec3(0.6f, 0.0f, -0.8f)),  // away
                              glm::vec3(0.0f, 1.0f, 0.0f)}) {                 // parallel
        bool forced = false;
        const glm::vec3 h = q.intersect({0, 0, 0}, d, &forced);
        EXPECT_TRUE(forced);
        const glm::vec3 r = h - q.center;
        EXPECT_NEAR(glm::dot(r, q.normal), 0.0f, 1e-3f) << "on the plane";
        const glm::vec3 tangential = glm::normalize(d - glm::dot(d, q.normal) * q.normal);
        EXPECT_NEAR(glm::dot(glm::normalize(r), tangential), 1.0f, 1e-5f);
        EXPECT_GT(glm::length(r), 100.0f * 2.0f) << "very far from the centre";
        const glm::vec4 c = q.texCoord({0, 0, 0}, d);
        EXPECT_GT(std::max(std::abs(c.x - 0.5f), std::abs(c.y - 0.5f)), 50.0f);
    }
}

TEST(Shells, FitQuadRecoversThePlaneOfItsPointsFacingTheOrigin) {
    // Points on the plane x + y = 8 (normal (1,1,0)/√2), a grid; rays from the origin.
    std::vector<glm::vec3> pts, ro, rd;
    for (int i = -5; i <= 5; ++i)
        for (int j = -5; j <= 5; ++j) {
            const glm::vec3 p = glm::vec3(4, 4, 0) + float(i) * 0.3f * glm::vec3(1, -1, 0) +
                                float(j) * 0.2f * glm::vec3(0, 0, 1);
            pts.push_back(p);
            ro.push_back({0, 0, 0});
            rd.push_back(glm::normalize(p));
        }
    const Shell q = fitQuad({0, 0, 0}, pts, ro, rd);
    EXPECT_EQ(q.kind, ShellKind::Quad);
    EXPECT_NEAR(glm::dot(q.normal, glm::normalize(glm::vec3(-1, -1, 0))), 1.0f, 1e-4f);
    EXPECT_NEAR(glm::length(q.center - glm::vec3(4, 4, 0)), 0.0f, 1e-4f);
    EXPECT_NEAR(std::abs(glm::dot(q.u, glm::vec3(0, 1, 0))), 0.0f, 1e-5f) << "u horizontal";
    // u = up × n is world z here, v = n × u runs along (1, −1, 0): the extents of the grid
    // (2 along z, 3√2 along (1, −1, 0); the 2% trim keeps whole columns of 11 points).
    EXPECT_NEAR(std::abs(q.u.z), 1.0f, 1e-5f);
    EXPECT_NEAR(q.uMax - q.uMin, 2.0f, 1e-3f);
    EXPECT_NEAR(q.vMax - q.vMin, 3.0f * std::sqrt(2.0f), 1e-3f);
}

}  // namespace
}  // namespace rg::hybrid
