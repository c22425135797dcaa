// 000 §4.1's records with continuation (Figure 4b, c) on a synthetic occluder, and the
// counting twin of an Accel (000 §6's triangle tests).
#include <gtest/gtest.h>

#include "core/error.h"

#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "hybrid_test_scenes.h"
#include "../../raycore/accel_counting.h"
#include "raycore/accel.h"
#include "raycore/shapes.h"
#include "raycore/tracer_two_term.h"

namespace rg::hybrid {
namespace {

// The ball, and an opaque slab between it and the camera covering its lower half; a
// column behind the ball (seen through it) in front of the room's wall.
ray::Scene occluded() {
    ray::Scene s = test::ballAndBox(24, 12, false);
    ray::Material clay;
    clay.name = "clay";
    clay.diffuse = glm::vec3(0.6f);
    const uint32_t m = s.addMaterial(clay);
    glm::mat4 slab = glm::translate(glm::mat4(1.0f), glm::vec3(3.0f, 0.8f, 0.0f));
    slab = glm::scale(slab, glm::vec3(0.1f, 2.0f, 3.0f));
    s.addObject("slab", s.addMesh(ray::makeCube(0.5f)), m, slab);
    s.addObject("column", s.addMesh(ray::makeCylinder(0.5f, 6.0f, 24)), m,
                glm::translate(glm::mat4(1.0f), glm::vec3(-4.0f, 0.0f, 0.0f)));
    return s;
}

struct Counted {
    int64_t samples = 0, occluded = 0, exits = 0, multiHitExits = 0, hits = 0;
};
Counted compile(const ray::Accel& accel, const ray::Camera& cam, bool in, bool out,
                std::vector<int> layers = {}) {
    ray::RenderOptions o;
    o.width = 64;
    o.height = 48;
    o.threads = 1;
    ray::LensRecordOptions lo;
    lo.lensObject = 0;
    lo.incomingContinuation = in;
    lo.outgoingContinuation = out;
    lo.layerOfObject = std::move(layers);
    Counted c;
    ray::compileLensRecords(accel, cam, o, lo, [&](const ray::LensRecordRow& row) {
        for (const ray::LensSampleRecord& s : row.samples) {
            ++c.samples;
            c.occluded += s.occluded;
            for (int t = 0; t < 2; ++t) {
                if (!s.path[t].valid) continue;
                ++c.exits;
                c.multiHitExits += s.hitCount[t] > 1;
                c.hits += s.hitCount[t];
                for (uint32_t h = 0; h < s.hitCount[t]; ++h)
                    EXPECT_NE(row.hits[s.firstHit[t] + h].object, 0u) << "the lens object itself";
            }
        }
    });
    return c;
}

TEST(LensRecords, IncomingContinuationReachesTheOccludedPartOfTheLensObject) {
    const ray::Scene scene = occluded();
    const ray::Accel accel(scene);
    const ray::Camera cam = scene.viewpointPaths[0].at(0);  // from +x: the slab in front
    const Counted with = compile(accel, cam, true, true), without = compile(accel, cam, false, true);
    EXPECT_GT(with.occluded, 50) << "records behind the slab";
    EXPECT_EQ(without.occluded, 0);
    EXPECT_EQ(with.samples - with.occluded, without.samples);
}

TEST(LensRecords, OutgoingContinuationKeepsEveryFrontFacingHitAlongTheExitRay) {
    const ray::Scene scene = occluded();
    const ray::Accel accel(scene);
    const ray::Camera cam = scene.viewpointPaths[0].at(0);
    const Counted with = compile(accel, cam, true, true), without = compile(accel, cam, true, false);
    EXPECT_EQ(with.exits, without.exits);
    EXPECT_EQ(without.hits, without.exits) << "first hit only";
    EXPECT_GT(with.multiHitExits, 20) << "the column, then the wall behind it";
    // With layers: only the first hit of each layer is kept (the column and the wall in
    // one layer: one hit per exit ray).
    std::vector<int> oneLayer(scene.objects.size() + 1, 0);
    oneLayer[0] = -1;
    const Counted layered = compile(accel, cam, true, true, oneLayer);
    EXPECT_EQ(layered.hits, layered.exits);
    std::vector<int> twoLayers = oneLayer;
    twoLayers[size_t(scene.findObject("column"))] = 1;
    EXPECT_GT(compile(accel, cam, true, true, twoLayers).hits, layered.hits);
}

TEST(CountingAccel, SameHitsAsTheTimedKernelsAndItCountsTheTests) {
    const ray::Scene scene = test::ballAndBox(32, 16, true);
    const ray::Accel plain(scene), counting(scene, ray::AccelOptions{true});
    EXPECT_FALSE(plain.counting());
    EXPECT_TRUE(counting.counting());
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int agree = 0, hits = 0;
    for (int i = 0; i < 2000; ++i) {
        ray::Ray r;
        r.origin = {5.0f * u(rng), 1.0f + u(rng), 5.0f};
        r.dir = glm::normalize(glm::vec3(-r.origin.x * 0.2f + 0.3f * u(rng), 0.3f * u(rng), -1.0f));
        const ray::Hit a = plain.intersect(r), b = counting.intersect(r);
        ASSERT_EQ(a.valid(), b.valid());
        if (!a.valid()) continue;
        ++hits;
        agree += a.object == b.object && std::abs(a.t - b.t) < 1e-4f * (1.0f + a.t);
        EXPECT_EQ(plain.occluded(r), counting.occluded(r));
    }
    EXPECT_GT(hits, 1500);
    EXPECT_GE(agree, hits - 2) << "an edge case or two may split differently";
    EXPECT_EQ(plain.triangleTests(), 0u);
    const uint64_t tests = counting.triangleTests();
    EXPECT_GT(tests, uint64_t(2 * 2000)) << "at least a test per ray and query";
    counting.resetTriangleTests();
    EXPECT_EQ(counting.triangleTests(), 0u);
    ray::Ray r;
    r.origin = {0, 1, 5};
    r.dir = {0, 0, -1};
    counting.intersect(r);
    EXPECT_GT(counting.triangleTests(), 0u);
    EXPECT_THROW(counting.allIntersections(r, true), Error);
}

TEST(CountingAccel, TheTriangleTestMatchesKnownHitsAndMisses) {
    float t, u, v;
    const glm::vec3 p0(0, 0, 0), p1(1, 0, 0), p2(0, 1, 0);
    ASSERT_TRUE(ray::detail::intersectTriangle({0.25f, 0.5f, 2}, {0, 0, -1}, 0, 10, p0, p1, p2, t, u, v));
    EXPECT_FLOAT_EQ(t, 2.0f);
    EXPECT_FLOAT_EQ(u, 0.25f);
    EXPECT_FLOAT_EQ(v, 0.5f);
    EXPECT_FALSE(ray::detail::intersectTriangle({0.75f, 0.5f, 2}, {0, 0, -1}, 0, 10, p0, p1, p2, t, u, v));
    EXPECT_FALSE(ray::detail::intersectTriangle({0.25f, 0.5f, 2}, {0, 0, -1}, 0, 1.5f, p0, p1, p2, t, u, v));
    EXPECT_FALSE(ray::detail::intersectTriangle({0.25f, 0.5f, 2}, {1, 0, 0}, 0, 10, p0, p1, p2, t, u, v));
}

}  // namespace
}  // namespace rg::hybrid
