// The reproduction end to end at a small setting: the files, the results' keys, and the
// claims whose margins are wide enough to hold at this size (more bounces closer to the
// reference: ~9 dB at quick quality; ours over Wyman 2005 on the prism's TIR pixels: ~9 dB).
#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>
#include <set>

#include "core/error.h"

#include "reproduce_tir.h"

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
