// EM geometry and texture-coordinate generation (001 §4), against analytic answers.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "em_geometry.h"
#include "pem_scene.h"

namespace rg::pem {
namespace {

TEST(EmGeometry, ExitOfUnitSphereFromCentreIsOne) {
    for (glm::vec3 d : {glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::normalize(glm::vec3(1, 2, 3))}) {
        auto t = exitEllipsoid(glm::vec3(0.0f), d, glm::vec3(0.0f), glm::vec3(1.0f));
        ASSERT_TRUE(t);
        EXPECT_NEAR(*t, 1.0f, 1e-6f);
    }
}

TEST(EmGeometry, ExitOfEllipsoidAlongAxesIsTheSemiAxis) {
    glm::vec3 c(1, 2, 3), a(3, 1, 2);
    EXPECT_NEAR(*exitEllipsoid(c, {1, 0, 0}, c, a), 3.0f, 1e-5f);
    EXPECT_NEAR(*exitEllipsoid(c, {0, -1, 0}, c, a), 1.0f, 1e-5f);
    EXPECT_NEAR(*exitEllipsoid(c, {0, 0, 1}, c, a), 2.0f, 1e-5f);
    // Outside the shell there is no exit.
    EXPECT_FALSE(exitEllipsoid(c + glm::vec3(10, 0, 0), {1, 0, 0}, c, a));
}

TEST(EmGeometry, ExitOfBoxIsTheNearestWallAlongTheRay) {
    glm::vec3 lo(-1, 0, -2), hi(3, 1, 2);
    EXPECT_NEAR(*exitBox({0, 0.5f, 0}, {1, 0, 0}, lo, hi), 3.0f, 1e-6f);
    EXPECT_NEAR(*exitBox({0, 0.5f, 0}, glm::normalize(glm::vec3(0, 1, 1)), lo, hi),
                0.5f * std::sqrt(2.0f), 1e-6f);
    EXPECT_FALSE(exitBox({5, 0.5f, 0}, {1, 0, 0}, lo, hi));
}

TEST(EmGeometry, IndexIsHitMinusOriginForFiniteShellsAndTheDirectionAtInfinity) {
    EmGeometry box;
    box.kind = EmGeometryKind::Box;
    box.boxMin = glm::vec3(-2);
    box.boxMax = glm::vec3(2);
    box.origin = glm::vec3(0.5f, 0, 0);
    glm::vec3 idx = box.index(glm::vec3(0), glm::vec3(0, 1, 0));
    EXPECT_NEAR(idx.x, -0.5f, 1e-6f);
    EXPECT_NEAR(idx.y, 2.0f, 1e-6f);
    EmGeometry inf;
    glm::vec3 r = glm::normalize(glm::vec3(1, 1, 0));
    EXPECT_EQ(inf.index(glm::vec3(7), r), r);
}

TEST(EmGeometry, BoundingEllipsoidContainsEveryPointAndRecoversAKnownEllipsoid) {
    // Points on the surface of the ellipsoid with semi-axes (3, 1, 2): the minimum-volume
    // axis-aligned bounding ellipsoid centred there is that ellipsoid.
    std::mt19937 rng(7);
    std::normal_distribution<float> n;
    std::vector<glm::vec3> pts;
    for (int i = 0; i < 2000; ++i) {
        glm::vec3 d = glm::normalize(glm::vec3(n(rng), n(rng), n(rng)));
        pts.push_back(d * glm::vec3(3, 1, 2));
    }
    EmGeometry g = fitBoundingEllipsoid(pts, glm::vec3(0), glm::vec3(0));
    for (const auto& p : pts) {
        glm::vec3 q = p / g.radii;
        EXPECT_LE(glm::dot(q, q), 1.0f + 1e-5f);
    }
    EXPECT_NEAR(g.radii.x, 3.0f, 0.06f);
    EXPECT_NEAR(g.radii.y, 1.0f, 0.03f);
    EXPECT_NEAR(g.radii.z, 2.0f, 0.04f);
}

TEST(EmGeometry, AreaWeightedCentroidOfTwoTrianglesFavoursTheLargerOne) {
    std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {10, 0, 0}, {13, 0, 0}, {10, 3, 0}};
    std::vector<uint32_t> idx = {0, 1, 2, 3, 4, 5};
    glm::vec3 c = areaWeightedCentroid(p, idx);
    // Areas 0.5 and 4.5; centroids (1/3, 1/3) and (11, 1).
    EXPECT_NEAR(c.x, (0.5f / 3 + 4.5f * 11) / 5.0f, 1e-5f);
    EXPECT_NEAR(c.y, (0.5f / 3 + 4.5f * 1) / 5.0f, 1e-5f);
}

TEST(PemScene, HullTrianglesOfACubeAreAllOnTheHullAndAnInnerOneIsNot) {
    std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    // Bottom face (outward −z, wound clockwise seen from +z) and a diagonal inner triangle.
    std::vector<uint32_t> idx = {0, 2, 1, 0, 3, 2, 0, 1, 6};
    auto hull = classifyHullTriangles(p, p, idx, 1e-5f);
    EXPECT_EQ(hull[0], 1);
    EXPECT_EQ(hull[1], 1);
    EXPECT_EQ(hull[2], 0);
}

TEST(PemScene, ConnectedComponentsSeparateDisjointPatches) {
    std::vector<uint32_t> idx = {0, 1, 2, 2, 1, 3, 4, 5, 6};
    int count = 0;
    auto comp = connectedComponents(7, idx, &count);
    EXPECT_EQ(count, 2);
    EXPECT_EQ(comp[0], comp[3]);
    EXPECT_NE(comp[0], comp[4]);
}

}  // namespace
}  // namespace rg::pem
