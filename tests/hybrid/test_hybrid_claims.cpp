// The reproduction at a small setting (every claim reported, the pass counts exact, the
// figures written), at quick quality (every claim's verdict against its margin, the claims
// that hold asserted by id, a wrong layer count breaking one), and bad input refused with a
// clear error before anything is written.
#include <gtest/gtest.h>

#include "core/error.h"

#include <filesystem>
#include <cstdio>
#include <fstream>
#include <algorithm>
#include <set>

#include "claims_check.h"
#include "hybrid_test_scenes.h"
#include "lens_scene.h"
#include "reproduce_hybrid.h"
#include "scratch_dir.h"

namespace fs = std::filesystem;

namespace rg::hybrid {
namespace {

HybridSettings small() {
    HybridSettings s = settingsFor(demos::Quality::Quick);
    s.pre.width = 96;
    s.pre.height = 72;
    s.pre.subsample = 2;
    s.pre.clusterWidth = 32;
    s.pre.clusterHeight = 24;
    s.pre.emSize = 16;
    s.teapotLevel = 6;
    s.tableFrames = 1;
    return s;
}

TEST(HybridClaims, EveryClaimIsReportedAtASmallSettingAndThePassCountsHold) {
    demos::ReproduceOptions o;
    o.outDir = rg::test::scratchDir("hybrid-small");
    const nlohmann::json r = runHybrid(small(), o);
    ASSERT_TRUE(r.contains("claims"));
    std::set<std::string> ids;
    for (const auto& c : r["claims"]) {
        ids.insert(c["id"].get<std::string>());
        if (c["id"] == "passes_4n_2n" || c["id"] == "clustering_cup_columns_walls") {
            EXPECT_TRUE(c["holds"].get<bool>()) << c.dump(2);
        }
    }
    for (const char* id : {"multi_beats_single_between", "multi_beats_single_above",
                           "single_layer_pops", "disocclusion_prevention_helps",
                           "tau3_at_least_tau5", "tau5_noisier_at_edges", "two_term_far_fewer_rays",
                           "two_term_similar_error", "fewer_rays_tau3", "fewer_rays_tau5",
                           "fewer_tests_tau3", "fewer_tests_tau5", "passes_4n_2n",
                           "clustering_cup_columns_walls", "complex_environment_increases_benefit"})
        EXPECT_TRUE(ids.count(id)) << id;
    EXPECT_EQ(r["claims_total"].get<int>(), int(ids.size()));
    // The §6 table beside the paper's, the clustering, the passes.
    EXPECT_GT(r["table"]["tau3"]["rays"]["total"].get<int64_t>(), 0);
    EXPECT_GT(r["table"]["uniform"]["triangle_tests"].get<int64_t>(),
              r["table"]["tau5"]["triangle_tests"].get<int64_t>());
    EXPECT_EQ(r["table"]["paper"]["tau3"]["rays"].get<int64_t>(), 1023876);
    EXPECT_EQ(r["passes"]["blended"]["layer_passes"].get<int>(), 4 * 3 + 2 * 2);
    EXPECT_EQ(r["passes"]["blended"]["alpha_clears"].get<int>(), 3 + 1);
    EXPECT_EQ(r["passes"]["on_sample"]["layer_passes"].get<int>(), 2 * 3 + 2);
    EXPECT_EQ(r["clustering"]["teapot"]["layers"].size(), 3u);
    for (const char* f : {"report.md", "index.html", "results.json", "figure2_shading_models.png",
                          "figure5_subdivision_levels.png", "figure7_layers.png",
                          "figure8_novel_views.png", "figure9_disocclusion.png", "figure10_tau.png"})
        EXPECT_TRUE(fs::exists(o.outDir / f)) << f;
}

// The claims at quick quality, what `retroglass reproduce hybrid` runs (docs/testing.md,
// "Claims tests"), from one run: every claim reported with its numbers and a row in
// report.md; every claim's verdict is what its numbers say against the margin the code and
// the report state (reproduce_hybrid.cpp, "Margins"); the claims that hold are asserted to
// hold; each was decided on the numbers results.json reports; the orderings the report's
// text states hold on those numbers.
TEST(HybridClaims, EveryReportedClaimAtQuickQuality) {
    using namespace rg::test;
    demos::ReproduceOptions o;
    o.outDir = scratchDir("hybrid-quick");
    HybridSettings s = settingsFor(demos::Quality::Quick);
    s.tableFrames = 1;  // the §6 table's times (no claim is decided on a time)
    const nlohmann::json r = runHybrid(s, o);
    ASSERT_TRUE(r.contains("claims"));
    expectEveryClaimReportedWithNumbers(r);
    EXPECT_EQ(r["claims_total"].get<int>(), 16);
    for (const auto& c : r["claims"]) expectRowInReport(o.outDir / "report.md", r, c["id"].get<std::string>());

    // The verdicts against the margins of reproduce_hybrid.cpp (PSNR 0.5 dB: over twice the
    // 0.2 dB a change of view moves one technique; τ = 3 "at least as good": −0.2 dB;
    // popping 0.5 and edge error 0.25 8-bit levels; counts: ≥ 2×, the heavier environment
    // +0.5×; the two-term model ≥ 30 dB).
    expectAtLeastVerdict(r, "multi_beats_single_between", "multi_layer", "single_layer", 0.5);
    expectAtLeastVerdict(r, "multi_beats_single_above", "multi_layer", "single_layer", 0.5);
    expectAtLeastVerdict(r, "single_layer_pops", "single_layer_excess_change", "multi_layer_excess_change", 0.5);
    expectAtLeastVerdict(r, "disocclusion_prevention_helps", "with", "without", 0.5);
    expectAtLeastVerdict(r, "tau3_at_least_tau5", "tau3", "tau5", -0.2);
    expectAtLeastVerdict(r, "tau5_noisier_at_edges", "tau5_edge_error", "tau3_edge_error", 0.25);
    expectAtLeastVerdict(r, "two_term_far_fewer_rays", "ratio", "one", 1.0);
    expectAtLeastVerdict(r, "two_term_similar_error", "psnr_two_term_vs_full_tree", "threshold", 0.0);
    for (const char* tau : {"tau3", "tau5"}) {
        expectAtLeastVerdict(r, std::string("fewer_rays_") + tau, "ray_reduction", "one", 1.0);
        expectAtLeastVerdict(r, std::string("fewer_tests_") + tau, "test_reduction", "one", 1.0);
        expectMeasuredIs(r, std::string("fewer_rays_") + tau, "ray_reduction", std::string("/table/") + tau + "/ray_reduction");
        expectMeasuredIs(r, std::string("fewer_tests_") + tau, "test_reduction", std::string("/table/") + tau + "/test_reduction");
    }
    expectAtLeastVerdict(r, "complex_environment_increases_benefit", "test_reduction_heavy", "test_reduction", 0.5);
    // Direct images (§4.3): their margin is twice the standard error of the paired gains over
    // the twelve novel views, read from results.json.
    expectAtLeastVerdict(r, "direct_images_help", "with_direct_images_mean", "neighbourhood_only_mean",
                         2.0 * r["disocclusion"]["direct_images"]["gain"]["direct_images_over_neighbourhood"]["se_db"].get<double>());
    expectMeasuredIs(r, "direct_images_help", "with_direct_images_mean",
                     "/disocclusion/direct_images/mean_psnr_db/with_direct_images");
    expectMeasuredIs(r, "direct_images_help", "neighbourhood_only_mean",
                     "/disocclusion/direct_images/mean_psnr_db/multi_layer");

    // Decided on the numbers results.json reports.
    expectMeasuredIs(r, "multi_beats_single_between", "multi_layer", "/novel_views/between/psnr_db/multi_layer");
    expectMeasuredIs(r, "multi_beats_single_between", "single_layer", "/novel_views/between/psnr_db/single_layer");
    expectMeasuredIs(r, "multi_beats_single_above", "multi_layer", "/novel_views/above/psnr_db/multi_layer");
    expectMeasuredIs(r, "multi_beats_single_above", "single_layer", "/novel_views/above/psnr_db/single_layer");
    expectMeasuredIs(r, "disocclusion_prevention_helps", "without", "/novel_views/between/psnr_db/without_prevention");
    expectMeasuredIs(r, "tau3_at_least_tau5", "tau5", "/novel_views/between/psnr_db/multi_layer_tau_fast");
    expectMeasuredIs(r, "single_layer_pops", "single_layer_excess_change", "/popping/single_layer/excess", 255.0);
    expectMeasuredIs(r, "single_layer_pops", "multi_layer_excess_change", "/popping/multi_layer/excess", 255.0);
    expectMeasuredIs(r, "tau5_noisier_at_edges", "tau5_edge_error", "/tau_quality/edge_error/tau5", 255.0);
    expectMeasuredIs(r, "two_term_far_fewer_rays", "ratio", "/shading_model/ratio");
    expectMeasuredIs(r, "two_term_similar_error", "psnr_two_term_vs_full_tree", "/shading_model/psnr_db");
    expectMeasuredIs(r, "complex_environment_increases_benefit", "test_reduction_heavy",
                     "/table/heavy_environment/test_reduction_tau3");

    // Every claim that holds at quick quality, asserted by id.
    for (const char* id : {"multi_beats_single_between", "multi_beats_single_above", "single_layer_pops",
                           "disocclusion_prevention_helps", "tau3_at_least_tau5", "tau5_noisier_at_edges",
                           "two_term_far_fewer_rays", "two_term_similar_error", "fewer_rays_tau3", "fewer_rays_tau5",
                           "fewer_tests_tau5", "clustering_cup_columns_walls", "passes_4n_2n"})
        expectHolds(r, id);
    // Not asserted to hold (their verdicts are checked above, their rows in report.md):
    // - fewer_tests_tau3: 2.00× falls short of "several times" by 0.06 % (1.9994×). Embree's
    //   BVH makes the environment's rays cheap (2.7 tests a ray against the paper's 27.4), so
    //   the test reduction follows the ray reduction (3.2×) instead of exceeding it; the
    //   report says why ("Why our reductions differ").
    // - direct_images_help: on top of the nearby viewpoints, direct images of the environment
    //   (one from the viewpoint sample for the glass teapot, six from the centre for the cup,
    //   as §4.3 advises) move the mean PSNR over twelve novel views by −0.18 dB (se 0.14): they
    //   fill most empty texels but their parallax against the exit rays costs in the plane
    //   (the report's "Direct images of the environment").
    // - complex_environment_increases_benefit: 64× finer columns raise the uniform tracer's
    //   tests by 9 % only (a BVH's cost grows with the logarithm of the geometry), the
    //   reduction by 0.19× against the 0.5× bar.

    // Orderings the report's text states ("The §6 table", "Why our reductions differ"), on
    // exact counts: a margin of one ray or test.
    expectOrdering(r, "/table/heavy_environment/uniform_triangle_tests", "/table/uniform/triangle_tests", 1,
                   "finer columns: the uniform tracer's tests grow");
    expectOrdering(r, "/table/tau3/rays/total", "/table/tau5/rays/total", 1,
                   "the vertex rays depend on τ: fewer at τ = 5");
    expectOrdering(r, "/table/uniform/rays/total", "/table/tau3/rays/total", 1, "the hybrid frame casts fewer rays");
}

// The claims test can fail: with one glass layer where the teapot needs three (the cup, the
// columns, the walls), the clustering no longer separates them and the "multi-layer" frame
// between samples falls below the single layer (18.4 against 22.0 dB: its one layer is
// Figure 7's quad, the cup's shell, standing in for the whole environment), so
// multi_beats_single_between and clustering_cup_columns_walls no longer hold. (Above the
// plane it still beats the single layer by 1.6 dB: the mirror cup keeps its two layers.)
// The §6 table's counts are left out: they decide no claim this changes.
TEST(HybridClaims, AWrongLayerCountBreaksAClaim) {
    demos::ReproduceOptions o;
    o.outDir = rg::test::scratchDir("hybrid-one-layer");
    HybridSettings s = settingsFor(demos::Quality::Quick);
    s.tableFrames = 1;
    s.countTests = false;
    s.glassLayers = 1;
    const nlohmann::json r = runHybrid(s, o);
    const std::vector<std::string> broken = rg::test::brokenClaims(r);
    for (const std::string& id : broken) std::printf("does not hold with the wrong setting: %s\n", id.c_str());
    auto brokenHas = [&](const char* id) { return std::find(broken.begin(), broken.end(), id) != broken.end(); };
    EXPECT_TRUE(brokenHas("multi_beats_single_between")) << r["claims"].dump(2);
    EXPECT_TRUE(brokenHas("clustering_cup_columns_walls")) << r["claims"].dump(2);
    // One glass layer is Figure 7's quad, not a cube shell: the shared-distant-layer variant
    // is left out with its reason, and the run still reports everything else.
    ASSERT_TRUE(r.contains("shared_distant_layers_left_out")) << "the shared layers ran on a quad";
    EXPECT_NE(r["shared_distant_layers_left_out"].get<std::string>().find("cube shell"), std::string::npos);
    EXPECT_FALSE(r.contains("shared_distant_layers"));
}

// Runs with one setting changed; expects rg::Error mentioning `words` and no output folder.
void expectRefused(const std::function<void(HybridSettings&, demos::ReproduceOptions&)>& change,
                   const std::string& words) {
    demos::ReproduceOptions o;
    o.outDir = rg::test::scratchDir("refused") / "out";
    HybridSettings s = small();
    change(s, o);
    try {
        runHybrid(s, o);
        FAIL() << "accepted; expected an error about " << words;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(o.outDir)) << "something was written before the error";
}

TEST(HybridBadInput, TauAtOrBelowZero) {
    expectRefused([](HybridSettings& s, auto&) { s.pre.tau = 0.0f; }, "τ must be > 0");
    expectRefused([](HybridSettings& s, auto&) { s.tauFast = -3.0f; }, "τ must be > 0");
}

TEST(HybridBadInput, LayerCountOfZeroOrBeyondTheProfile) {
    expectRefused([](HybridSettings& s, auto&) { s.glassLayers = 0; }, "layer count of 0");
    expectRefused([](HybridSettings& s, auto&) { s.mirrorLayers = 0; }, "layer count of 0");
    // 2 terms × 5 layers: more coordinate sets than a GeForce 256 vertex has.
    expectRefused([](HybridSettings& s, auto&) { s.glassLayers = 5; }, "texture-coordinate sets");
    // Four 512² cube layers and two mirror layers for two samples: past 32 MiB.
    expectRefused([](HybridSettings& s, auto&) {
        s.glassLayers = 4;
        s.pre.emSize = 512;
    }, "texture memory");
}

TEST(HybridBadInput, ASceneWithoutGlassOrMirror) {
    const fs::path dir = rg::test::scratchDir("no-lens");
    {
        std::ofstream f(dir / "diffuse.json");
        f << R"({"name": "all-diffuse",
                 "materials": [{"name": "clay", "type": "diffuse"}],
                 "objects": [{"name": "ball", "shape": "sphere", "material": "clay"}],
                 "viewpoint_paths": [{"name": "circle", "center": [0, 0, 0], "radius": 5,
                                      "height": 1, "step": 8, "count": 10}]})";
    }
    expectRefused([&](HybridSettings&, demos::ReproduceOptions& o) { o.scene = (dir / "diffuse.json").string(); },
                  "no glass or mirror object");
}

TEST(HybridBadInput, ALensObjectWithoutATriangle) {
    ray::Scene s = test::ballAndBox();
    ray::Mesh empty;
    empty.name = "nothing";
    s.objects[0].mesh = uint32_t(s.meshes.size());
    s.meshes.push_back(empty);
    try {
        LensScene ls(s, LensSceneOptions{});
        FAIL() << "accepted a lens object without a triangle";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("'ball' has no triangle"), std::string::npos) << e.what();
    }
    LensSceneOptions named;
    named.objects = {"room_floor"};
    EXPECT_THROW(LensScene(test::ballAndBox(), named), Error);  // diffuse
    named.objects = {"nope"};
    EXPECT_THROW(LensScene(test::ballAndBox(), named), Error);
}

TEST(HybridBadInput, AnOpenGlassMeshIsAWarningNamingIt) {
    ray::Scene s = test::ballAndBox();
    ray::Mesh open = s.meshes[s.objects[0].mesh];
    open.indices.resize(open.indices.size() - 3);  // one triangle short: a hole
    s.objects[0].mesh = uint32_t(s.meshes.size());
    s.meshes.push_back(open);
    LensScene ls(s, LensSceneOptions{});
    bool named = false;
    for (const std::string& w : ls.warnings()) named = named || w.find("lens object 'ball'") != std::string::npos;
    EXPECT_TRUE(named);
    EXPECT_FALSE(ls.objects()[0].closedManifold);
    EXPECT_TRUE(ls.objects()[1].closedManifold) << "the mirror box is closed";

    // A mirror needs no inside: an open one is drawn without a warning about it.
    ray::Mesh openBox = s.meshes[s.objects[1].mesh];
    openBox.indices.resize(openBox.indices.size() - 3);
    s.objects[1].mesh = uint32_t(s.meshes.size());
    s.meshes.push_back(openBox);
    LensScene withOpenMirror(s, LensSceneOptions{});
    EXPECT_FALSE(withOpenMirror.objects()[1].closedManifold);
    for (const std::string& w : withOpenMirror.warnings())
        EXPECT_EQ(w.find("lens object 'box'"), std::string::npos) << w;
}

}  // namespace
}  // namespace rg::hybrid
