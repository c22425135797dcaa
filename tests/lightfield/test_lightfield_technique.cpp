// lightfield in `retroglass compare`: the technique applies to a scene's first glass or
// mirror object, draws it from a per-view slab, and its three routes agree with each other.
#include <gtest/gtest.h>

#include "raycore/builtin_scenes.h"
#include "raycore/metrics.h"
#include "reproduce_lightfield.h"

namespace rg::lightfield {
namespace {

TEST(LightfieldTechnique, DrawsTheTeapotFromItsOwnSlabAndTheVqRoutesAgree) {
    const ray::Scene scene = ray::makeBuiltinScene("teapot-in-room");
    const LightfieldReproduction& lf = lightfieldReproduction();
    ASSERT_EQ(lf.appliesTo(scene), "teapot");
    demos::PrepareOptions po;
    po.width = 96;
    po.height = 72;
    auto t = lf.prepare(scene, {}, po);
    ASSERT_TRUE(t);
    const ray::ViewpointPath& path = scene.viewpointPaths.at(0);
    const ray::Camera cam = path.at(path.count / 2);
    const demos::GroundTruth truth = t->groundTruth(cam);
    std::map<std::string, demos::RenderedView> views;
    for (const std::string& v : t->variants()) views[v] = t->render(v, cam);
    ray::Image mask(po.width, po.height, 1);
    int covered = 0;
    for (int y = 0; y < po.height; ++y)
        for (int x = 0; x < po.width; ++x) {
            const bool in = truth.coverage.at(x, y, 0) >= 0.999f && views["gortler"].drawn.at(x, y, 0) != 0.0f;
            mask.at(x, y, 0) = in ? 1.0f : 0.0f;
            covered += in;
        }
    // The eye points cover most of the teapot (the slab is fitted to it and to the view).
    EXPECT_GT(covered, 1000);
    const double g = ray::compareMasked(truth.image, views["gortler"].image, mask, "gortler").psnr;
    // The same codebook through 2D and 4D textures: the routes differ only in the (s, t)
    // interpolant and rounding (Vq4DPasses), far less than the light field's own error.
    const double vv = ray::compareMasked(views["vq_alpha_basis"].image, views["vq_4d"].image, mask, "vq routes").psnr;
    // Measured: the fitted slab 17.2 dB at this size; light fields of the wrong rays score
    // 13.5 (a mirrored slab frame) and 11.2 (the slab-to-world scale inverted), both
    // planted and seen failing here. 15 dB sits between them: a sanity bar, not a claim.
    EXPECT_GT(g, 15.0);
    EXPECT_GT(vv, 30.0);
    std::printf("technique at 96x72: gortler %.2f dB vs ray tracer, vq 4D vs alpha basis %.2f dB, %d pixels\n", g, vv, covered);
    EXPECT_EQ(views["vq_4d"].passes, 33);
}

TEST(LightfieldTechnique, DoesNotApplyWithoutGlassOrMirror) {
    ray::Scene scene;
    ray::Material diffuse;
    diffuse.name = "diffuse";
    scene.addMaterial(diffuse);
    EXPECT_EQ(lightfieldReproduction().appliesTo(scene), "");
}

}  // namespace
}  // namespace rg::lightfield
