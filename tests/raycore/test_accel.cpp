// Ray queries against analytic answers: distances to a sphere, rays aimed exactly at shared
// edges and vertices (robust mode), all-intersections with duplicates removed, packets.
#include <gtest/gtest.h>

#include <cstring>

#include <cmath>

#include "raycore/accel.h"
#include "raycore/builtin_scenes.h"
#include "raycore/shapes.h"

namespace rg::ray {
namespace {

Scene oneObject(Mesh m, MaterialType type = MaterialType::Diffuse) {
    Scene s;
    s.name = "test";
    Material mat;
    mat.name = "m";
    mat.type = type;
    s.addMaterial(mat);
    s.addObject("object", s.addMesh(std::move(m)), 0);
    return s;
}

Ray ray(glm::vec3 o, glm::vec3 d) {
    Ray r;
    r.origin = o;
    r.dir = glm::normalize(d);
    return r;
}

TEST(Accel, RayAtUnitSphereHitsAtTheKnownDistance) {
    Scene s = oneObject(makeSphere(1.0f, 128, 64));
    Accel accel(s);
    // Towards vertices of the tessellation (poles, equator points at multiples of 90°): the
    // hit is exactly on the sphere, at distance 5 − 1 = 4.
    for (glm::vec3 d : {glm::vec3(0, -1, 0), glm::vec3(0, 1, 0), glm::vec3(-1, 0, 0),
                        glm::vec3(0, 0, -1), glm::vec3(1, 0, 0)}) {
        Hit h = accel.intersect(ray(-5.0f * d, d));
        ASSERT_TRUE(h.valid()) << d.x << "," << d.y << "," << d.z;
        EXPECT_NEAR(h.t, 4.0f, 2e-6f * 5) << d.x << "," << d.y << "," << d.z;
        SurfacePoint sp = accel.surface(ray(-5.0f * d, d), h);
        EXPECT_TRUE(sp.frontFace);
        EXPECT_GT(glm::dot(sp.ng, -d), 0.99f);
    }
    // Any other direction through the centre: between the chord and the sphere, i.e. the
    // distance is 4 plus at most the sagitta 1 − cos(π/64) of the tessellation.
    const float sag = 1.0f - std::cos(3.14159265f / 64.0f);
    for (int i = 0; i < 50; ++i) {
        glm::vec3 d = glm::normalize(glm::vec3(std::sin(i * 1.3f), std::cos(i * 0.7f), std::sin(i * 2.1f + 1)));
        Hit h = accel.intersect(ray(-5.0f * d, d));
        ASSERT_TRUE(h.valid());
        EXPECT_GE(h.t, 4.0f - 1e-5f);
        EXPECT_LE(h.t, 4.0f + sag + 1e-5f);
    }
    // Missing the sphere.
    EXPECT_FALSE(accel.intersect(ray({0, 2, 5}, {0, 0, -1})).valid());
    EXPECT_TRUE(accel.occluded(ray({0, 0, 5}, {0, 0, -1})));
    EXPECT_FALSE(accel.occluded(ray({0, 2, 5}, {0, 0, -1})));
}

TEST(Accel, RaysAlongASharedEdgeNeverSlipThrough) {
    // Each cube face is two triangles split along a diagonal; rays through points of that
    // diagonal hit exactly on the shared edge. Robust mode must report a hit every time.
    Scene s = oneObject(makeCube(1.0f));
    Accel accel(s);
    for (int i = 0; i <= 1000; ++i) {
        float a = -0.999f + 1.998f * float(i) / 1000.0f;
        // +z face corners go (−1,−1) → (1,1) along its diagonal.
        Hit h = accel.intersect(ray({a, a, 5.0f}, {0, 0, -1}));
        ASSERT_TRUE(h.valid()) << "ray through (" << a << "," << a << ") missed";
        EXPECT_NEAR(h.t, 4.0f, 1e-5f);
    }
}

TEST(Accel, AllIntersectionsThroughASharedEdgeAreMerged) {
    Scene s = oneObject(makeCube(1.0f));
    Accel accel(s);
    Ray r = ray({0, 0, 5}, {0, 0, -1});  // through both face centres, on both diagonals
    std::vector<Hit> tri = accel.allTriangleHits(r);
    EXPECT_GE(tri.size(), 2u);
    std::vector<Hit> all = accel.allIntersections(r, false);
    ASSERT_EQ(all.size(), 2u) << "one entry, one exit";
    EXPECT_NEAR(all[0].t, 4.0f, 1e-5f);
    EXPECT_NEAR(all[1].t, 6.0f, 1e-5f);
    std::vector<Hit> front = accel.allIntersections(r, true);
    ASSERT_EQ(front.size(), 1u);
    EXPECT_NEAR(front[0].t, 4.0f, 1e-5f);
}

TEST(Accel, AllIntersectionsThroughSharedVerticesAreMerged) {
    // Through two opposite corners of the cube: each corner is shared by three faces
    // (several triangles each), all met at the same t.
    Scene s = oneObject(makeCube(1.0f));
    Accel accel(s);
    Ray r = ray({3, 3, 3}, {-1, -1, -1});
    std::vector<Hit> all = accel.allIntersections(r, false);
    ASSERT_EQ(all.size(), 2u);
    EXPECT_NEAR(all[0].t, 2.0f * std::sqrt(3.0f), 1e-4f);
    EXPECT_NEAR(all[1].t, 4.0f * std::sqrt(3.0f), 1e-4f);
    EXPECT_EQ(accel.allIntersections(r, true).size(), 1u);
    // The sphere's pole is a vertex shared by 128 triangles.
    Scene sp = oneObject(makeSphere(1.0f, 128, 64));
    Accel a2(sp);
    Ray down = ray({0, 5, 0}, {0, -1, 0});
    EXPECT_GE(a2.allTriangleHits(down).size(), 2u);
    std::vector<Hit> poles = a2.allIntersections(down, false);
    ASSERT_EQ(poles.size(), 2u);
    EXPECT_NEAR(poles[0].t, 4.0f, 1e-5f);
    EXPECT_NEAR(poles[1].t, 6.0f, 1e-5f);
}

TEST(Accel, AllIntersectionsContinueThroughOccluders) {
    Scene s;
    s.name = "two spheres";
    s.addMaterial({});
    uint32_t m = s.addMesh(makeSphere(1.0f, 64, 32));
    s.addObject("near", m, 0, glm::mat4(1.0f));
    glm::mat4 far(1.0f);
    far[3] = glm::vec4(0.3f, 0.2f, -4.0f, 1.0f);
    s.addObject("far", m, 0, far);
    Accel accel(s);
    Ray r = ray({0.1f, 0.05f, 5}, {0, 0, -1});
    std::vector<Hit> front = accel.allIntersections(r, true);
    ASSERT_EQ(front.size(), 2u);
    EXPECT_EQ(front[0].object, 0u);
    EXPECT_EQ(front[1].object, 1u);
    EXPECT_LT(front[0].t, front[1].t);
    EXPECT_EQ(accel.allIntersections(r, false).size(), 4u);
    // The nearest of them is what intersect() returns.
    Hit h = accel.intersect(r);
    EXPECT_EQ(h.object, 0u);
    EXPECT_FLOAT_EQ(h.t, front[0].t);
}

TEST(Accel, PacketsAgreeWithSingleRays) {
    Scene s = oneObject(makeSphere(1.0f, 64, 32));
    Accel accel(s);
    std::vector<Ray> rays;
    for (int i = 0; i < 16; ++i)
        rays.push_back(ray({-1.2f + 0.15f * i, 0.3f, 5.0f}, {0.01f * i, 0.0f, -1.0f}));
    Hit h8[8], h16[16];
    accel.intersect8(rays.data(), h8, 8);
    accel.intersect16(rays.data(), h16, 16);
    for (int i = 0; i < 16; ++i) {
        Hit one = accel.intersect(rays[size_t(i)]);
        EXPECT_EQ(h16[i].object, one.object) << i;
        if (one.valid()) {
            EXPECT_EQ(h16[i].triangle, one.triangle);
            EXPECT_EQ(h16[i].t, one.t);
        }
        if (i < 8) {
            EXPECT_EQ(h8[i].object, one.object);
        }
    }
    // A stream gives the same answers.
    std::vector<Hit> stream(rays.size());
    accel.intersectStream(rays.data(), stream.data(), rays.size(), true);
    for (size_t i = 0; i < rays.size(); ++i) {
        EXPECT_EQ(stream[i].object, h16[i].object) << i;
        EXPECT_EQ(stream[i].t, h16[i].t) << i;
    }
    // A partial packet leaves the rest alone and still answers the valid lanes.
    Hit part[16];
    accel.intersect16(rays.data(), part, 5);
    for (int i = 0; i < 5; ++i) EXPECT_EQ(part[i].object, h16[i].object);
}

// The batched hit resolution (SSE lanes) against the scalar one, bit for bit: rays from
// the camera and from points inside and around the teapot in every direction (front and
// back faces, the room's parts), misses, and a count that leaves a partial group.
TEST(Accel, SurfacesMatchSurfaceBitForBit) {
    Scene s = makeBuiltinScene("teapot-in-room");
    Accel accel(s);
    const Camera cam = s.viewpointPaths[0].at(0);
    std::vector<Ray> rays;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) rays.push_back(primaryRay(cam, 32, 24, x + 0.25f, y + 0.75f));
    uint32_t state = 12345u;
    auto next = [&] {  // xorshift: fixed sequence
        state ^= state << 13, state ^= state >> 17, state ^= state << 5;
        return float(state >> 8) / 16777216.0f;
    };
    for (int i = 0; i < 1001; ++i) {
        Ray r;
        r.origin = {4.0f * next() - 2.0f, 3.5f * next(), 4.0f * next() - 2.0f};
        r.dir = glm::normalize(glm::vec3(next() - 0.5f, next() - 0.5f, next() - 0.5f) + 1e-6f);
        rays.push_back(r);
    }
    std::vector<Hit> hits(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) hits[i] = accel.intersect(rays[i]);
    hits[3] = Hit();  // misses in the middle of a group
    hits[rays.size() - 2] = Hit();
    std::vector<SurfacePoint> batch(rays.size());
    accel.surfaces(rays.data(), hits.data(), batch.data(), rays.size());
    int back = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const SurfacePoint a = accel.surface(rays[i], hits[i]), &b = batch[i];
        EXPECT_EQ(std::memcmp(&a.p, &b.p, sizeof a.p), 0) << i;
        EXPECT_EQ(std::memcmp(&a.ng, &b.ng, sizeof a.ng), 0) << i;
        EXPECT_EQ(std::memcmp(&a.ns, &b.ns, sizeof a.ns), 0) << i;
        EXPECT_EQ(std::memcmp(&a.uv, &b.uv, sizeof a.uv), 0) << i;
        EXPECT_EQ(a.frontFace, b.frontFace) << i;
        EXPECT_EQ(a.object, b.object) << i;
        EXPECT_EQ(a.triangle, b.triangle) << i;
        EXPECT_EQ(a.part, b.part) << i;
        EXPECT_EQ(a.material, b.material) << i;
        back += hits[i].valid() && !a.frontFace;
    }
    EXPECT_GT(back, 10) << "no back faces exercised";
}

}  // namespace
}  // namespace rg::ray
