// 001 §3–4 segmented layers: they recombine to the reference, the local layer holds the
// self-reflections, the distant layer is defined everywhere, parts partition the object.
#include <gtest/gtest.h>

#include "core/error.h"
#include "raycore/builtin_scenes.h"
#include "raycore/layers_pem.h"
#include "raycore/shapes.h"
#include "raycore/tracer_whitted.h"

namespace rg::ray {
namespace {

Scene smallTeapotRoom() {
    BuiltinOptions b;
    b.teapotLevel = 6;
    return makeBuiltinScene("teapot-in-room", b);
}

RenderOptions small() {
    RenderOptions o;
    o.width = 80;
    o.height = 60;
    o.maxDepth = 4;
    return o;
}

TEST(PemLayers, RecombineToTheWhittedImage) {
    Scene s = smallTeapotRoom();
    Accel accel(s);
    Camera cam = s.viewpointPaths[0].at(30);
    RenderOptions o = small();
    std::vector<Segment> segs = {findSegment(s, "teapot/body"), findSegment(s, "teapot/lid")};
    PemLayerImages layers = renderPemLayers(accel, cam, o, segs);
    Image ref = renderWhitted(accel, cam, o);
    Image sum = layers.background;
    for (const PemLayers& l : layers.segments) {
        Image c = l.composite();
        for (size_t i = 0; i < sum.pixels.size(); ++i) sum.pixels[i] += c.pixels[i];
    }
    // One sample per pixel: diffuse + F·(α·local + (1−α)·distant) is the Whitted sum term
    // for term, so the recombination is exact up to rounding.
    for (size_t i = 0; i < sum.pixels.size(); ++i)
        ASSERT_NEAR(sum.pixels[i], ref.pixels[i], 1e-5f) << "pixel " << i / 3;
}

TEST(PemLayers, LocalLayerHoldsSelfReflectionsOnlyWhereTheyExist) {
    Scene s = smallTeapotRoom();
    Accel accel(s);
    RenderOptions o = small();
    PemLayerImages layers =
        renderPemLayers(accel, s.viewpointPaths[0].at(0), o, {findSegment(s, "teapot")});
    const PemLayers& l = layers.segments[0];
    int covered = 0, local = 0;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            float cov = l.coverage.at(x, y, 0), a = l.localAlpha.at(x, y, 0);
            ASSERT_GE(a, 0.0f);
            ASSERT_LE(a, 1.0f);
            if (cov == 0.0f) {
                ASSERT_EQ(a, 0.0f);
                continue;
            }
            ++covered;
            local += a > 0.0f;
            // Distant is defined on every covered pixel: the room is lit, never black.
            glm::vec3 d = l.distant.rgb(x, y);
            ASSERT_GT(d.x + d.y + d.z, 0.0f) << x << "," << y;
            // Schlick F ≥ F0 = 0.6.
            ASSERT_GE(l.fresnel.at(x, y, 0), 0.6f - 1e-6f);
        }
    EXPECT_GT(covered, 200);
    EXPECT_GT(local, 0) << "the teapot reflects its own spout, handle and lid";
    EXPECT_LT(local, covered / 2);
}

TEST(PemLayers, ConvexMirrorHasNoLocalLayer) {
    Scene s;
    s.name = "sphere";
    Material m;
    m.name = "mirror";
    m.type = MaterialType::Mirror;
    m.diffuse = glm::vec3(0.0f);
    s.addMaterial(m);
    s.addObject("sphere", s.addMesh(makeSphere(1.0f, 64, 32)), 0);
    s.environment.kind = EnvironmentKind::Gradient;
    Accel accel(s);
    RenderOptions o;
    o.width = 32;
    o.height = 32;
    o.spp = 2;
    PemLayerImages layers = renderPemLayers(accel, {"c", {0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 45.0f},
                                            o, {findSegment(s, "sphere")});
    float maxAlpha = 0.0f, maxCov = 0.0f;
    for (float a : layers.segments[0].localAlpha.pixels) maxAlpha = std::max(maxAlpha, a);
    for (float c : layers.segments[0].coverage.pixels) maxCov = std::max(maxCov, c);
    EXPECT_EQ(maxAlpha, 0.0f);
    EXPECT_EQ(maxCov, 1.0f);
}

TEST(PemLayers, PartsPartitionTheObject) {
    Scene s = smallTeapotRoom();
    Accel accel(s);
    RenderOptions o = small();
    o.spp = 2;
    Camera cam = s.viewpointPaths[0].at(60);
    PemLayerImages parts = renderPemLayers(
        accel, cam, o, {findSegment(s, "teapot/body"), findSegment(s, "teapot/lid")});
    PemLayerImages whole = renderPemLayers(accel, cam, o, {findSegment(s, "teapot")});
    int lidPixels = 0;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            float b = parts.segments[0].coverage.at(x, y, 0), l = parts.segments[1].coverage.at(x, y, 0);
            ASSERT_NEAR(b + l, whole.segments[0].coverage.at(x, y, 0), 1e-6f);
            lidPixels += l > 0.0f;
        }
    EXPECT_GT(lidPixels, 5);
    EXPECT_EQ(segmentName(s, parts.segments[1].segment), "teapot/lid");
    EXPECT_THROW(findSegment(s, "teapot/spout"), Error);
    EXPECT_THROW(findSegment(s, "kettle"), Error);
}

}  // namespace
}  // namespace rg::ray
