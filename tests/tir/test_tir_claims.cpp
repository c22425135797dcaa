// The reproduction end to end at a small setting: the files, the results' keys, and the
// claims whose margins are wide enough to hold at this size (more bounces closer to the
// reference: ~9 dB at quick quality; ours over Wyman 2005 on the prism's TIR pixels: ~9 dB).
// At quick quality (what `retroglass reproduce` runs): every claim's verdict against its
// margin, the claims that hold asserted by id, and a wrong index of refraction breaking one.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <set>

#include "core/error.h"

#include "claims_check.h"
#include "reproduce_tir.h"
#include "scratch_dir.h"

namespace fs = std::filesystem;

namespace rg::tir {
namespace {

TEST(TirClaims, TheReproductionRunsSmallAndItsWideClaimsHold) {
    TirReproduceSettings s;
    s.imageSize = 64;
    s.supersample = 1;
    s.referenceSpp = 1;
    s.tableSizes = {64, 128};
    s.tableFrames = 1;
    s.tableScenes = {"kitchen"};
    s.mapScales = {0.25f, 1.0f};
    s.envSize = 16;
    s.textureSize = 64;
    s.threads = 2;
    demos::ReproduceOptions o;
    o.outDir = fs::path(RETROGLASS_BUILD_DIR) / "test-out" / ("tir-small-" + std::to_string(::getpid()));
    fs::remove_all(o.outDir);
    const nlohmann::json r = runTir(s, o);
    for (const char* f : {"report.md", "index.html", "results.json", "figure1_dragon.png", "figure2_passes.png",
                          "figure6_choice.png", "figure7_map_sizes.png", "figure8_bounces.png", "figure9_statue.png",
                          "figure10_kitchen.png", "figure11_front_and_back.png", "error_maps.png"})
        EXPECT_TRUE(fs::exists(o.outDir / f)) << f;
    for (const char* k : {"scenes", "figure6_front_back_choice", "figure8_bounces", "figure7_map_sizes", "iterations", "table1", "claims"})
        EXPECT_TRUE(r.contains(k)) << k;
    std::map<std::string, bool> claims;
    for (const auto& c : r["claims"]) claims[c["id"].get<std::string>()] = c["holds"].get<bool>();
    for (const char* id : {"more_bounces_closer", "diminishing_returns", "beats_wyman05_where_tir_prism",
                           "front_and_back_vital_somewhere", "choice_finds_front_hits", "iterations_8_5_suffice",
                           "smaller_maps_hurt_more_with_bounces", "frame_time_linear_in_bounces"})
        EXPECT_TRUE(claims.count(id)) << id;
    EXPECT_FALSE(claims.count("resolution_ratio_as_paper"));  // needs the paper's 512² and 1024²
    EXPECT_TRUE(claims["more_bounces_closer"]) << r["figure8_bounces"].dump();
    EXPECT_TRUE(claims["beats_wyman05_where_tir_prism"]) << r["scenes"]["prism"].dump();
    // Figure 6: per scene and bounce, the counts are consistent (the compared hits are
    // among the searching pixels; right and back-right among the compared).
    for (const auto& [scene, j] : r["figure6_front_back_choice"].items()) {
        if (scene == "all_scenes") continue;
        ASSERT_EQ(j["by_bounce"].size(), 3u) << scene;
        EXPECT_GT(j["by_bounce"][0]["compared"].get<int>(), 0) << scene;
        for (const auto& b : j["by_bounce"]) {
            EXPECT_LE(b["compared"].get<int>() + b["missed"].get<int>(), b["searching"].get<int>()) << scene;
            EXPECT_LE(b["front_right"].get<int>(), b["compared"].get<int>()) << scene;
        }
    }
    // Table 1: every cell measured, with the search's fetches counted.
    for (const char* size : {"64", "128"})
        for (const char* b : {"1", "2", "3", "4"}) {
            const auto& cell = r["table1"]["kitchen"][size][b];
            EXPECT_GT(cell["fps"].get<double>(), 0.0);
            EXPECT_GT(cell["fetches_per_refractive_fragment"].get<double>(), 1.0);
            EXPECT_EQ(cell["passes_ms"].size(), 4u);
        }
    // More bounces, more fetches per refractive fragment (each bounce searches again).
    EXPECT_GT(r["table1"]["kitchen"]["128"]["4"]["fetches_per_refractive_fragment"].get<double>(),
              r["table1"]["kitchen"]["128"]["1"]["fetches_per_refractive_fragment"].get<double>());
    fs::remove_all(o.outDir);
}

// The claims at quick quality, what `retroglass reproduce tir` runs (docs/testing.md, "Claims
// tests"), from one run: every claim reported with its numbers and a row in report.md; every
// verdict is what its numbers say against the margin reproduce_tir.cpp states (PSNR orderings
// and orderings of PSNR gains 0.5 dB, eight times the 0.06 dB that changes touching few of
// the refractor's pixels move one method; "similar" within 0.5 dB; Figure 6: a majority and
// no loss); the
// claims that hold are asserted to hold; each was decided on the numbers results.json reports.
TEST(TirClaims, EveryReportedClaimAtQuickQuality) {
    using namespace rg::test;
    TirReproduceSettings s = tirSettingsFor(demos::Quality::Quick);
    s.tableScenes = {"kitchen"};  // Table 1 decides the timing claims only (reported, not asserted)
    s.tableFrames = 1;
    demos::ReproduceOptions o;
    o.outDir = scratchDir("tir-quick");
    const nlohmann::json r = runTir(s, o);
    ASSERT_TRUE(r.contains("claims"));
    expectEveryClaimReportedWithNumbers(r);
    EXPECT_EQ(r["claims_total"].get<int>(), 10);
    for (const auto& c : r["claims"]) expectRowInReport(o.outDir / "report.md", r, c["id"].get<std::string>());

    // The verdicts against the stated margins, whether or not the claim holds.
    expectAtLeastVerdict(r, "more_bounces_closer", "psnr_3_bounces", "psnr_1_bounce", 0.5);
    expectAtLeastVerdict(r, "diminishing_returns", "gain_1_to_2", "gain_2_to_3", 0.5);
    expectAtLeastVerdict(r, "beats_wyman05_where_tir_dragon", "ours", "wyman05", 0.5);
    expectAtLeastVerdict(r, "beats_wyman05_where_tir_prism", "ours", "wyman05", 0.5);
    expectAtLeastVerdict(r, "smaller_maps_hurt_more_with_bounces", "loss_2_bounces", "loss_1_bounce", 0.5);
    expectWithinVerdict(r, "iterations_8_5_suffice", "psnr_8_5", "psnr_11_11", 0.5);
    expectWithinVerdict(r, "resolution_ratio_as_paper", "ours", "paper", 0.1);
    {
        const nlohmann::json c = claimById(r, "front_and_back_vital_somewhere");
        double best = -1e30;
        for (const auto& [scene, j] : r["scenes"].items()) {
            const double gain = j["ours_front_and_back"]["refractor"]["psnr_db"].get<double>() -
                                j["ours"]["refractor"]["psnr_db"].get<double>();
            EXPECT_NEAR(c["measured"]["gain_" + scene].get<double>(), gain, 1e-9) << scene;
            best = std::max(best, gain);
        }
        EXPECT_EQ(c["holds"].get<bool>(), best >= 0.5) << c.dump(2);
        EXPECT_NE(c["test"].get<std::string>().find("≥ 0.50 dB"), std::string::npos) << c["test"];
    }
    {
        const nlohmann::json c = claimById(r, "choice_finds_front_hits");
        const auto& m = c["measured"];
        EXPECT_EQ(c["holds"].get<bool>(), m["front_recall"].get<double>() > 0.5 &&
                                              m["agreement"].get<double>() >= m["back_only_agreement"].get<double>())
            << c.dump(2);
        // Over all scenes and bounces, as Figure 6's totals report them.
        int64_t compared = 0;
        for (const auto& b : r["figure6_front_back_choice"]["all_scenes"]) compared += b["compared"].get<int64_t>();
        EXPECT_GT(compared, 1000) << "Figure 6 compared too few hits to decide a majority";
        EXPECT_GT(m["front_hits"].get<int64_t>(), 100) << c.dump(2);
    }
    {
        // Table 1's linearity: the worst R² of the fits the results report.
        const nlohmann::json c = claimById(r, "frame_time_linear_in_bounces");
        double worst = 1.0;
        for (const auto& [scene, bySize] : r["table1_fits"].items())
            for (const auto& [size, f] : bySize.items()) worst = std::min(worst, f["r2"].get<double>());
        EXPECT_NEAR(c["measured"]["worst_r2"].get<double>(), worst, 1e-12);
        EXPECT_EQ(c["holds"].get<bool>(), worst >= 0.9) << c.dump(2);
        const auto& k = r["table1"]["kitchen"];
        EXPECT_NEAR(claimById(r, "resolution_ratio_as_paper")["measured"]["ours"].get<double>(),
                    k["1024"]["3"]["fps"].get<double>() / k["512"]["3"]["fps"].get<double>(), 1e-9);
    }

    // Decided on the numbers results.json reports.
    expectMeasuredIs(r, "more_bounces_closer", "psnr_3_bounces", "/figure8_bounces/by_bounces/3/psnr_db");
    expectMeasuredIs(r, "more_bounces_closer", "psnr_1_bounce", "/figure8_bounces/by_bounces/1/psnr_db");
    for (const char* scene : {"dragon", "prism"}) {
        const std::string id = std::string("beats_wyman05_where_tir_") + scene;
        expectMeasuredIs(r, id, "ours", std::string("/scenes/") + scene + "/ours/tir/psnr_db");
        expectMeasuredIs(r, id, "wyman05", std::string("/scenes/") + scene + "/wyman05/tir/psnr_db");
    }
    expectMeasuredIs(r, "iterations_8_5_suffice", "psnr_8_5", "/iterations/8_5_psnr_db");
    expectMeasuredIs(r, "iterations_8_5_suffice", "psnr_11_11", "/iterations/many_psnr_db");
    {
        const auto& f = r["figure7_map_sizes"]["psnr_db"];
        auto loss = [&](const char* b) {
            return f[b]["1.000"]["psnr_db"].get<double>() - f[b]["0.125"]["psnr_db"].get<double>();
        };
        const nlohmann::json c = claimById(r, "smaller_maps_hurt_more_with_bounces");
        EXPECT_NEAR(c["measured"]["loss_1_bounce"].get<double>(), loss("1"), 1e-9);
        EXPECT_NEAR(c["measured"]["loss_2_bounces"].get<double>(), loss("2"), 1e-9);
    }

    // Every claim that holds at quick quality, asserted by id.
    for (const char* id : {"more_bounces_closer", "diminishing_returns", "beats_wyman05_where_tir_prism",
                           "choice_finds_front_hits", "iterations_8_5_suffice"})
        expectHolds(r, id);
    // Not asserted to hold (verdicts checked above, rows in report.md):
    // - beats_wyman05_where_tir_dragon: ours leads Wyman 2005 on the substitute dragon's TIR
    //   pixels by 0.33 dB at quick quality, short of the 0.5 dB margin (on the prism: 9.6 dB).
    // - front_and_back_vital_somewhere: the scene that gains most from the front map (the
    //   kitchen) gains 0.31 dB, short of 0.5 dB.
    // - smaller_maps_hurt_more_with_bounces: at 256² (quick) the smallest maps lose 2.0 dB at
    //   one bounce and 1.7 dB at two: the loss does not grow with bounces at this size.
    // - frame_time_linear_in_bounces, resolution_ratio_as_paper: timings, decided by this
    //   machine's load and the other processes of the suite (`ctest -j`); reported with their
    //   numbers (checked above), never asserted.

    // Orderings the report's text states (Figure 8): more bounces, closer, by the PSNR margin
    // up to the third bounce; the fourth adds nothing on the prism (0.5 dB: no loss past it).
    expectOrdering(r, "/figure8_bounces/by_bounces/2/psnr_db", "/figure8_bounces/by_bounces/1/psnr_db", 0.5,
                   "a second bounce brings the prism closer");
    expectOrdering(r, "/figure8_bounces/by_bounces/4/psnr_db", "/figure8_bounces/by_bounces/3/psnr_db", -0.5,
                   "a fourth bounce loses nothing");
}

// The claims test can fail: with the glass drawn at index 1.0 (air) while the reference keeps
// the scene's 1.5, no ray bends or reflects totally inside the frames' glass, so further
// bounces change nothing and more_bounces_closer no longer holds (nor, at quick quality,
// diminishing_returns, beats_wyman05_where_tir_prism and choice_finds_front_hits: four of the
// five that hold; the printout lists them). Table 1 is left out: it decides timing claims
// only.
TEST(TirClaims, AWrongRefractiveIndexBreaksAClaim) {
    TirReproduceSettings s = tirSettingsFor(demos::Quality::Quick);
    s.tableScenes = {};
    s.frameIor = 1.0f;
    demos::ReproduceOptions o;
    o.outDir = rg::test::scratchDir("tir-wrong-ior");
    const nlohmann::json r = runTir(s, o);
    const std::vector<std::string> broken = rg::test::brokenClaims(r);
    for (const std::string& id : broken) std::printf("does not hold with the wrong setting: %s\n", id.c_str());
    EXPECT_NE(std::find(broken.begin(), broken.end(), "more_bounces_closer"), broken.end()) << r["claims"].dump(2);
}

TEST(TirClaims, AUserSceneWithoutGlassIsAnError) {
    const fs::path dir = fs::path(RETROGLASS_BUILD_DIR) / "test-out" / ("tir-noglass-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream(dir / "s.json") << R"({"name": "no-glass",
        "materials": [{"name": "clay", "type": "diffuse", "diffuse": [0.8, 0.7, 0.6]}],
        "objects": [{"name": "ball", "shape": "sphere", "params": {"radius": 1}, "material": "clay"}],
        "cameras": [{"name": "default", "eye": [0, 0, 5], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 45}]})";
    try {
        tirSceneFromFile((dir / "s.json").string());
        FAIL() << "no glass object";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no glass object"), std::string::npos) << e.what();
    }
    // An open glass mesh is used, with a warning naming it.
    std::ofstream(dir / "open.json") << R"({"name": "open-glass",
        "materials": [{"name": "glass", "type": "glass", "ior": 1.5}],
        "objects": [{"name": "cup", "shape": "room", "params": {"lo_x": -1, "lo_y": 0, "lo_z": -1,
                     "hi_x": 1, "hi_y": 1, "hi_z": 1, "part": 0}, "material": "glass"}],
        "cameras": [{"name": "default", "eye": [0, 1, 5], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45}]})";
    TirScene t = tirSceneFromFile((dir / "open.json").string());
    bool warned = false;
    for (const auto& w : t.warnings) warned = warned || w.find("'cup'") != std::string::npos;
    EXPECT_TRUE(warned);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace rg::tir
