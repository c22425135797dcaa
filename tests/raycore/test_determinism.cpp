// Identical image bytes for any thread count: every sample position is keyed by
// (pixel, sample), rows are independent, counters are summed per row.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "raycore/builtin_scenes.h"
#include "raycore/layers_pem.h"
#include "raycore/tracer_two_term.h"
#include "raycore/tracer_whitted.h"
#include "test_util.h"

namespace rg::ray {
namespace {

TEST(Determinism, SameBytesFor1And2And4Threads) {
    // Let the arenas have 4 threads even on a 2-core machine (TBB caps workers at the core
    // count otherwise): oversubscription only shuffles the schedule more.
    tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 4);
    BuiltinOptions b;
    b.teapotLevel = 8;
    Scene s = makeBuiltinScene("teapot-in-room", b);
    Accel accel(s);
    Camera cam = s.viewpointPaths[0].at(17);
    uint64_t whitted[3], twoTerm[3], layers[3], rays[3];
    const int threads[3] = {1, 2, 4};
    for (int i = 0; i < 3; ++i) {
        RenderOptions o;
        o.width = 64;
        o.height = 48;
        o.spp = 2;
        o.maxDepth = 4;
        o.threads = threads[i];
        RenderCounters counters;
        o.counters = &counters;
        whitted[i] = test::hashImage(renderWhitted(accel, cam, o));
        rays[i] = counters.total();
        TwoTermImages t = renderTwoTerm(accel, cam, o);
        twoTerm[i] = test::hashImage(t.sum) ^ (test::hashImage(t.reflectConfidence) * 31);
        PemLayerImages l = renderPemLayers(accel, cam, o, {findSegment(s, "teapot/body"),
                                                           findSegment(s, "teapot/lid")});
        layers[i] = test::hashImage(l.segments[0].distant) ^ test::hashImage(l.segments[1].localAlpha) ^
                    test::hashImage(l.background);
        EXPECT_EQ(counters.count(RayKind::Primary), uint64_t(64 * 48 * 4 * 2 + 64 * 48 * 4))
            << threads[i] << " threads";
    }
    for (int i = 1; i < 3; ++i) {
        EXPECT_EQ(whitted[i], whitted[0]) << threads[i] << " threads vs 1 (whitted)";
        EXPECT_EQ(twoTerm[i], twoTerm[0]) << threads[i] << " threads vs 1 (two-term)";
        EXPECT_EQ(layers[i], layers[0]) << threads[i] << " threads vs 1 (PEM layers)";
        EXPECT_EQ(rays[i], rays[0]) << threads[i] << " threads vs 1 (ray count)";
    }
}

// The tracers trace each row's camera rays ahead of shading (CameraRowRays:
// Accel::intersectSurfaces a chunk of pixels at a time). Against their definitions one
// camera ray at a time (whittedRadiance, traceTwoTerm of a Ray), bit for bit, and with the
// same ray counts: a scene of glass, mirror and diffuse objects on two threads, with 2×2
// samples (a row is one chunk) and with 16×16 (chunks of 4 pixels, the last of a row
// partial).
void expectRowTracingMatchesEachRay(int width, int height, int n) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height) + ", " + std::to_string(n) + "x" +
                 std::to_string(n) + " samples");
    Scene s = makeBuiltinScene("glass-teapot");
    Accel accel(s);
    const Camera cam = s.cameras[0];
    RenderOptions o;
    o.width = width;
    o.height = height;
    o.spp = n;
    o.maxDepth = 4;
    o.threads = 2;
    const float inv = 1.0f / float(n * n);
    RayCounts wantWhitted, wantTwoTerm;
    Image whitted(o.width, o.height, 3), direct(o.width, o.height, 3), reflect(o.width, o.height, 3),
        refract(o.width, o.height, 3);
    int glassHits = 0;
    for (int y = 0; y < o.height; ++y)
        for (int x = 0; x < o.width; ++x) {
            glm::vec3 sum(0.0f), d(0.0f), tr(0.0f), tt(0.0f);
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    const glm::vec2 f = samplePosition(x, y, sx, sy, n);
                    const Ray r = primaryRay(cam, o.width, o.height, f.x, f.y);
                    wantWhitted.add(RayKind::Primary);
                    sum += whittedRadiance(accel, r, 0, o.maxDepth, wantWhitted);
                    wantTwoTerm.add(RayKind::Primary);
                    const TwoTermSample t = traceTwoTerm(accel, r, o.maxDepth, wantTwoTerm);
                    d += t.direct;
                    if (t.reflect.valid) tr += t.reflect.radiance * (t.reflect.F * t.reflect.G);
                    if (t.refract.valid) tt += t.refract.radiance * (t.refract.F * t.refract.G);
                    glassHits += t.refract.valid;
                }
            whitted.setRgb(x, y, sum * inv);
            direct.setRgb(x, y, d * inv);
            reflect.setRgb(x, y, tr * inv);
            refract.setRgb(x, y, tt * inv);
        }
    EXPECT_GT(glassHits, 100) << "the view must see glass";
    RenderCounters gotWhitted, gotTwoTerm;
    o.counters = &gotWhitted;
    EXPECT_EQ(renderWhitted(accel, cam, o).pixels, whitted.pixels);
    o.counters = &gotTwoTerm;
    const TwoTermImages im = renderTwoTerm(accel, cam, o);
    EXPECT_EQ(im.direct.pixels, direct.pixels);
    EXPECT_EQ(im.reflectTerm.pixels, reflect.pixels);
    EXPECT_EQ(im.refractTerm.pixels, refract.pixels);
    for (size_t k = 0; k < size_t(RayKind::Count); ++k) {
        EXPECT_EQ(gotWhitted.count(RayKind(k)), wantWhitted.n[k]) << rayKindName(RayKind(k));
        EXPECT_EQ(gotTwoTerm.count(RayKind(k)), wantTwoTerm.n[k]) << rayKindName(RayKind(k));
    }
}

TEST(Determinism, RowTracedCameraRaysGiveWhatEachRayGives) {
    static_assert(CameraRowRays::kChunkRays / (16 * 16) == 4, "the 16x16 case no longer splits rows in 4-pixel chunks");
    expectRowTracingMatchesEachRay(48, 36, 2);
    expectRowTracingMatchesEachRay(11, 5, 16);  // chunks of 4, 4 and 3 pixels
}

TEST(Determinism, RebuildingTheSceneGivesTheSameBytes) {
    BuiltinOptions b;
    b.teapotLevel = 8;
    Scene s = makeBuiltinScene("teapot-in-room", b);
    RenderOptions o;
    o.width = 40;
    o.height = 30;
    uint64_t first = 0;
    for (int i = 0; i < 2; ++i) {
        Accel accel(s);
        uint64_t h = test::hashImage(renderWhitted(accel, s.cameras[0], o));
        if (i == 0) first = h;
        else EXPECT_EQ(h, first);
    }
}

}  // namespace
}  // namespace rg::ray
