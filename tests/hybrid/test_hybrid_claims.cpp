// The reproduction at a small setting (every claim reported, the pass counts exact, the
// figures written), and bad input refused with a clear error before anything is written.
#include <gtest/gtest.h>

#include "core/error.h"

#include <filesystem>
#include <fstream>
#include <set>

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
        if (c["id"] == "passes_4n_2n" || c["id"] == "clustering_cup_columns_walls")
            EXPECT_TRUE(c["holds"].get<bool>()) << c.dump(2);
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
}

}  // namespace
}  // namespace rg::hybrid
