// 000 §3's two-term model and §4.3's confidence.
#include <gtest/gtest.h>

#include "raycore/metrics.h"
#include "raycore/shapes.h"
#include "raycore/tracer_two_term.h"
#include "raycore/tracer_whitted.h"

namespace rg::ray {
namespace {

Scene glassSphere(glm::vec3 env, glm::vec3 transmittance = glm::vec3(1.0f)) {
    Scene s;
    s.name = "glass sphere";
    Material m;
    m.name = "glass";
    m.type = MaterialType::Glass;
    m.diffuse = glm::vec3(0.0f);
    m.ior = 1.5f;
    m.transmittance = transmittance;
    s.addMaterial(m);
    s.addObject("sphere", s.addMesh(makeSphere(1.0f, 128, 64)), 0);
    s.environment.color = env;
    s.ambient = glm::vec3(0.0f);
    return s;
}

const Camera kCam{"c", {0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 45.0f};

TEST(TwoTerm, GlassSphereAtNormalIncidenceHasAnalyticFG) {
    // Centre ray: reflect path F_R = F̂(0°) = 0.04; refract path crosses two interfaces at
    // normal incidence, keeping the larger coefficient 0.96 at the back: F_T = 0.96².
    const glm::vec3 env(0.2f, 0.5f, 1.0f);
    Scene s = glassSphere(env);
    Accel accel(s);
    RayCounts counts;
    TwoTermSample t = traceTwoTerm(accel, primaryRay(kCam, 41, 41, 20.5f, 20.5f), 8, counts);
    ASSERT_TRUE(t.hitLens);
    ASSERT_TRUE(t.reflect.valid);
    ASSERT_TRUE(t.refract.valid);
    EXPECT_NEAR(t.reflect.F.x, 0.04f, 1e-4f);
    EXPECT_NEAR(t.refract.F.x, 0.96f * 0.96f, 1e-4f);
    EXPECT_EQ(t.reflect.events.size(), 1u);
    ASSERT_EQ(t.refract.events.size(), 2u);
    EXPECT_EQ(t.refract.events[0], PathEvent::Refract);
    EXPECT_EQ(t.refract.events[1], PathEvent::Refract);
    EXPECT_EQ(t.reflect.G, glm::vec3(1.0f));
    EXPECT_NEAR(t.reflect.radiance.z, env.z, 1e-6f);
    EXPECT_NEAR(t.refract.radiance.z, env.z, 1e-6f);
    // Exit ray continues straight on through the sphere.
    EXPECT_NEAR(t.refract.exitRay.dir.z, -1.0f, 1e-4f);
    EXPECT_FALSE(t.refract.exitHit.valid());
}

TEST(TwoTerm, TransparencyAttenuationIsThicknessTraversed) {
    Scene s = glassSphere(glm::vec3(1.0f), {0.5f, 0.5f, 0.5f});
    Accel accel(s);
    RayCounts counts;
    TwoTermSample t = traceTwoTerm(accel, primaryRay(kCam, 41, 41, 20.5f, 20.5f), 8, counts);
    // Diameter 2 of glass: G_T = 0.5² (to the tessellation's chord error).
    EXPECT_NEAR(t.refract.G.x, 0.25f, 1e-3f);
    EXPECT_EQ(t.reflect.G, glm::vec3(1.0f));
}

TEST(TwoTerm, TermsSumToTheImageAndFGProductsStayBelowOne) {
    Scene s = glassSphere(glm::vec3(1.0f));
    Accel accel(s);
    RenderOptions o;
    o.width = 40;
    o.height = 30;
    o.spp = 2;
    TwoTermImages im = renderTwoTerm(accel, kCam, o);
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x)
            for (int c = 0; c < 3; ++c) {
                float sum = im.direct.at(x, y, c) + im.reflectTerm.at(x, y, c) +
                            im.refractTerm.at(x, y, c);
                ASSERT_NEAR(im.sum.at(x, y, c), sum, 1e-6f);
                float fg = im.reflectFG.at(x, y, c) + im.refractFG.at(x, y, c);
                // Two greedy paths keep at most what the first interface split: F_R + F_T ≤ 1.
                ASSERT_LE(fg, 1.0f + 1e-6f);
                // With a white environment and no absorption each term is its FG.
                ASSERT_NEAR(im.reflectTerm.at(x, y, c), im.reflectFG.at(x, y, c), 1e-6f);
            }
    // Centre: F_R + F_T = 0.04 + 0.9216; no absorption, so G = 1 and FG = F.
    EXPECT_NEAR(im.reflectFG.at(20, 15, 0) + im.refractFG.at(20, 15, 0), 0.9616f, 2e-3f);
    EXPECT_NEAR(im.reflectF.at(20, 15, 0), im.reflectFG.at(20, 15, 0), 1e-6f);
    EXPECT_NEAR(im.refractG.at(20, 15, 1), 1.0f, 1e-6f);
}

TEST(TwoTerm, ApproximatesTheFullRayTree) {
    // 000 Fig. 2: the two greedy paths approximate the full tree well. Against a textured
    // environment the difference stays small.
    Scene s = glassSphere(glm::vec3(1.0f));
    s.environment.kind = EnvironmentKind::Gradient;
    Accel accel(s);
    RenderOptions o;
    o.width = 48;
    o.height = 48;
    o.maxDepth = 6;
    Image full = renderWhitted(accel, kCam, o);
    TwoTermImages two = renderTwoTerm(accel, kCam, o);
    double p = psnr(full, two.sum);
    EXPECT_GT(p, 25.0) << "two-term vs full tree PSNR " << p;
    EXPECT_LT(p, 1e9) << "the pruned tree cannot equal the full tree exactly";
}

TEST(TwoTerm, MirrorHasOnlyTheReflectionTerm) {
    Scene s = glassSphere(glm::vec3(0.3f));
    s.materials[0].type = MaterialType::Mirror;
    s.materials[0].reflectance = glm::vec3(0.7f);
    Accel accel(s);
    RenderOptions o;
    o.width = 24;
    o.height = 24;
    TwoTermImages im = renderTwoTerm(accel, kCam, o);
    Image whitted = renderWhitted(accel, kCam, o);
    for (size_t i = 0; i < im.refractTerm.pixels.size(); ++i) {
        ASSERT_EQ(im.refractTerm.pixels[i], 0.0f);
        ASSERT_NEAR(im.sum.pixels[i], whitted.pixels[i], 1e-6f);
    }
}

TEST(TwoTerm, ConfidenceFollowsTheFormula) {
    const float deg = 3.14159265f / 180.0f;
    glm::vec3 a(0, 0, -1);
    auto rotated = [&](float degrees) {
        return glm::vec3(std::sin(degrees * deg), 0.0f, -std::cos(degrees * deg));
    };
    EXPECT_FLOAT_EQ(pathConfidence({a}), 1.0f);
    EXPECT_NEAR(pathConfidence({a, a, a}), 1.0f, 1e-6f);
    EXPECT_NEAR(pathConfidence({a, rotated(2.5f)}), 0.75f, 1e-3f);  // 1 − (2.5/5)²
    EXPECT_NEAR(pathConfidence({a, rotated(1.0f), rotated(-1.0f)}), 1.0f - 0.16f, 1e-3f);
    EXPECT_NEAR(pathConfidence({a, rotated(5.0f)}), 0.0f, 1e-4f);
    EXPECT_FLOAT_EQ(pathConfidence({a, rotated(30.0f)}), 0.0f);
}

TEST(TwoTerm, ConfidenceDropsAtTheSilhouette) {
    Scene s = glassSphere(glm::vec3(1.0f));
    Accel accel(s);
    // 3×3 samples; pixels small enough (0.22°) that the reflected rays of one pixel at the
    // sphere's centre stay ~1.3° apart, while at the silhouette they fan out widely.
    RenderOptions o;
    o.width = 160;
    o.height = 160;
    o.spp = 3;
    Camera cam = kCam;
    cam.fovYDegrees = 35.0f;
    TwoTermImages im = renderTwoTerm(accel, cam, o);
    EXPECT_GT(im.reflectConfidence.at(80, 80, 0), 0.85f);
    float lowest = 1.0f;
    for (float v : im.reflectConfidence.pixels) {
        ASSERT_GE(v, 0.0f);
        ASSERT_LE(v, 1.0f);
        lowest = std::min(lowest, v);
    }
    EXPECT_LT(lowest, 0.5f);
}

TEST(TwoTerm, RayPathRecordsCarryEveryFrontFacingExitIntersection) {
    Scene s = glassSphere(glm::vec3(1.0f));
    // A second object behind the sphere, hit by the refracted exit rays.
    uint32_t m = s.addMesh(makeCube(1.0f));
    glm::mat4 behind(1.0f);
    behind[3] = glm::vec4(0.0f, 0.0f, -4.0f, 1.0f);
    s.addMaterial({});
    s.addObject("box", m, 1, behind);
    Accel accel(s);
    RenderOptions o;
    o.width = 9;
    o.height = 9;
    std::vector<RayPathRecord> recs = compileRayPathRecords(accel, kCam, o);
    ASSERT_FALSE(recs.empty());
    bool sawBox = false;
    for (const RayPathRecord& r : recs) {
        EXPECT_EQ(r.path.events[0], r.term == 0 ? PathEvent::Reflect : PathEvent::Refract);
        for (size_t i = 1; i < r.exitIntersections.size(); ++i)
            EXPECT_LT(r.exitIntersections[i - 1].t, r.exitIntersections[i].t);
        for (const Hit& h : r.exitIntersections) sawBox |= h.object == 1;
    }
    EXPECT_TRUE(sawBox);
}

}  // namespace
}  // namespace rg::ray
