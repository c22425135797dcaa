// Scenes with a known answer for the Whitted reference.
#include <gtest/gtest.h>

#include "raycore/builtin_scenes.h"
#include "raycore/shapes.h"
#include "raycore/tracer_whitted.h"

namespace rg::ray {
namespace {

Scene mirrorSphere(MirrorFresnel fresnel, glm::vec3 env) {
    Scene s;
    s.name = "mirror sphere";
    Material m;
    m.name = "mirror";
    m.type = MaterialType::Mirror;
    m.diffuse = glm::vec3(0.0f);
    m.reflectance = {0.8f, 0.6f, 0.4f};
    m.fresnel = fresnel;
    s.addMaterial(m);
    s.addObject("sphere", s.addMesh(makeSphere(1.0f, 128, 64)), 0);
    s.environment.kind = EnvironmentKind::Constant;
    s.environment.color = env;
    s.ambient = glm::vec3(0.0f);
    return s;
}

TEST(Whitted, MirrorSphereInConstantEnvironmentIsReflectanceTimesConstant) {
    const glm::vec3 env(0.5f, 0.7f, 0.9f);
    Scene s = mirrorSphere(MirrorFresnel::Constant, env);
    Accel accel(s);
    RenderOptions o;
    o.width = 41;
    o.height = 41;
    Camera cam{"c", {0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 45.0f};
    Image img = renderWhitted(accel, cam, o);
    int onSphere = 0;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            glm::vec2 f = samplePosition(x, y, 0, 0, 1);
            bool hits = accel.intersect(primaryRay(cam, o.width, o.height, f.x, f.y)).valid();
            glm::vec3 expected = hits ? s.materials[0].reflectance * env : env;
            onSphere += hits;
            glm::vec3 got = img.rgb(x, y);
            ASSERT_NEAR(got.x, expected.x, 1e-6f) << x << "," << y;
            ASSERT_NEAR(got.y, expected.y, 1e-6f) << x << "," << y;
            ASSERT_NEAR(got.z, expected.z, 1e-6f) << x << "," << y;
        }
    EXPECT_GT(onSphere, 300);
}

TEST(Whitted, SchlickMirrorAtNormalIncidenceIsF0) {
    const glm::vec3 env(1.0f);
    Scene s = mirrorSphere(MirrorFresnel::Schlick, env);
    Accel accel(s);
    RenderOptions o;
    o.width = 41;  // odd: the centre pixel's ray runs exactly along −z
    o.height = 41;
    Camera cam{"c", {0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 45.0f};
    Image img = renderWhitted(accel, cam, o);
    glm::vec3 c = img.rgb(20, 20);
    EXPECT_NEAR(c.x, 0.8f, 1e-4f);
    EXPECT_NEAR(c.y, 0.6f, 1e-4f);
    EXPECT_NEAR(c.z, 0.4f, 1e-4f);
    // Towards the silhouette Schlick rises towards 1.
    float edge = 0.0f;
    for (int x = 0; x < 20; ++x)
        if (accel.intersect(primaryRay(cam, 41, 41, x + 0.5f, 20.5f)).valid()) {
            edge = img.rgb(x, 20).z;
            break;
        }
    EXPECT_GT(edge, 0.45f);  // vs F0 = 0.4 at the centre
}

TEST(Whitted, GlassCubeWithTotalInternalReflectionIsUniformlyBright) {
    // No absorption and a white environment: every branch of the ray tree ends in the
    // environment and the Fresnel weights of the children sum to the parent's, so the true
    // image is exactly 1 everywhere. Treating TIR wrongly (dropping the reflected child, or
    // refracting anyway) shows as dark regions; only the truncation of the tree at maxDepth
    // loses a little energy on the longest paths.
    Scene s = makeBuiltinScene("glass-cube");
    Accel accel(s);
    RenderOptions o;
    o.width = 48;
    o.height = 48;
    o.maxDepth = 12;
    RenderCounters counters;
    o.counters = &counters;
    Image img = renderWhitted(accel, s.cameras[0], o);
    float lo = 2.0f, hi = 0.0f;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x)
            for (int c = 0; c < 3; ++c) {
                lo = std::min(lo, img.at(x, y, c));
                hi = std::max(hi, img.at(x, y, c));
            }
    EXPECT_GE(lo, 0.98f) << "a dark pixel: energy lost at an interface";
    EXPECT_LE(hi, 1.0f + 1e-5f) << "energy created at an interface";
    EXPECT_GT(counters.count(RayKind::Refraction), 0u);
    EXPECT_EQ(counters.count(RayKind::Primary), uint64_t(48 * 48));
}

TEST(Whitted, GlassSlabAttenuatesByTransmittanceToTheThickness) {
    // Straight through a cube of side 2 with transmittance t per unit: with F = 0.04 at
    // each face and g = t², the ray tree sums to F + g(1−F)²/(1 − gF) (internal bounces
    // form a geometric series).
    Scene s;
    s.name = "slab";
    Material glass;
    glass.name = "glass";
    glass.type = MaterialType::Glass;
    glass.diffuse = glm::vec3(0.0f);
    glass.ior = 1.5f;
    glass.transmittance = {0.5f, 0.8f, 1.0f};
    s.addMaterial(glass);
    s.addObject("cube", s.addMesh(makeCube(1.0f)), 0);
    s.environment.color = glm::vec3(1.0f);
    s.ambient = glm::vec3(0.0f);
    Accel accel(s);
    RayCounts counts;
    Ray r;
    r.origin = {0.0f, 0.0f, 5.0f};
    r.dir = {0.0f, 0.0f, -1.0f};
    glm::vec3 L = whittedRadiance(accel, r, 0, 30, counts);
    const float F = 0.04f;
    for (int c = 0; c < 3; ++c) {
        float g = glass.transmittance[c] * glass.transmittance[c];
        float expected = F + g * (1 - F) * (1 - F) / (1 - g * F);
        EXPECT_NEAR(L[c], expected, 2e-5f) << "channel " << c;
    }
}

TEST(Whitted, DiffuseFloorIsLitByVisibleLightsOnly) {
    Scene s;
    s.name = "floor";
    Material d;
    d.name = "white";
    d.diffuse = glm::vec3(0.5f);
    s.addMaterial(d);
    s.addObject("floor", s.addMesh(makeRoom({-5, 0, -5}, {5, 1, 5})), 0);  // box seen from inside
    s.ambient = glm::vec3(0.1f);
    s.lights.push_back({"l", {0.0f, 0.9f, 0.0f}, glm::vec3(1.0f)});
    Accel accel(s);
    RayCounts counts;
    Ray down;
    down.origin = {0.0f, 0.5f, 0.0f};
    down.dir = {0.0f, -1.0f, 0.0f};
    // Directly under the light: albedo·(ambient + 1·cos 0).
    glm::vec3 L = whittedRadiance(accel, down, 0, 4, counts);
    EXPECT_NEAR(L.x, 0.5f * 1.1f, 1e-5f);
    EXPECT_EQ(counts.n[size_t(RayKind::Shadow)], 1u);
}

}  // namespace
}  // namespace rg::ray
