// The reproduction end to end at a small setting: the files, the results' keys, every claim
// reported with its section, statement, measured values and verdict, and the claims whose
// margins do not depend on the frame size or the machine's load: the refractor map finds the
// sphere's exit within a texel (a search that stopped at the entry, itself a root of the
// ratio, misses by the whole chord), and secant iterations cut the analytic room's error.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <map>
#include <set>

#include "reproduce_impostors.h"

namespace fs = std::filesystem;

namespace rg::impostors {
namespace {

TEST(ImpostorClaims, TheReproductionRunsSmallAndItsClaimsAreReported) {
    ImpostorReproduceSettings s;
    s.imageSize = 48;
    s.envSize = 16;
    s.envSizeLarge = 32;
    s.refractorSize = 32;
    s.segments = 12;
    s.sphereSlices = 24;
    s.timedFrames = 1;
    s.classicalFrames = 1;
    s.referenceDepth = 4;
    s.dollies = {1.0f, 0.7f, 0.5f};
    s.depthSweep = {1, 2};
    s.analyticRays = 400;
    s.outsideRays = 400;
    s.threads = 2;
    demos::ReproduceOptions o;
    o.outDir = fs::path(RETROGLASS_BUILD_DIR) / "test-out" / ("impostors-small-" + std::to_string(::getpid()));
    fs::remove_all(o.outDir);
    const nlohmann::json r = runImpostors(s, o);
    for (const char* f : {"report.md", "index.html", "results.json", "figure10_whole_scene.png",
                          "figure9_comparison.png", "figure5_searches.png", "figure2_error_by_iterations.svg",
                          "refractor_maps.png", "environment_impostor.png"})
        EXPECT_TRUE(fs::exists(o.outDir / f)) << f;
    for (const char* k : {"timing", "figure2", "figure9", "depth_sweep", "iteration_sweep", "glass_pixels_sweep",
                          "figure3_refractor_exit", "figure4_outside_search", "exit_total_reflection", "claims"})
        EXPECT_TRUE(r.contains(k)) << k;
    // The four configurations of §8, each timed, with the mover's maps alone rebuilt when
    // separated and every object's when classical.
    for (const char* c : {"static", "classical", "separated", "separated_large_maps"}) {
        EXPECT_GT(r["timing"][c]["fps"].get<double>(), 0.0) << c;
        EXPECT_GT(r["timing"][c]["fetches_per_glass_fragment"].get<double>(), 3.0) << c;
    }
    EXPECT_EQ(r["timing"]["static"]["impostors_rebuilt_per_frame"].get<int>(), 0);
    EXPECT_EQ(r["timing"]["separated"]["impostors_rebuilt_per_frame"].get<int>(), 1);
    EXPECT_EQ(r["timing"]["classical"]["impostors_rebuilt_per_frame"].get<int>(), 33);
    // Total reflection at the exit, ours against the ray tracer's, over the same glass pixels.
    const auto& tir = r["exit_total_reflection"];
    EXPECT_GT(tir["glass_pixels"].get<int64_t>(), 50) << tir.dump();
    for (const char* k : {"ours_fraction", "ray_tracer_fraction"}) {
        EXPECT_GE(tir[k].get<double>(), tir["both_fraction"].get<double>()) << tir.dump();
        EXPECT_LE(tir[k].get<double>(), 1.0) << tir.dump();
    }
    std::map<std::string, bool> claims;
    for (const auto& c : r["claims"]) {
        for (const char* k : {"section", "statement", "measured", "holds"}) EXPECT_TRUE(c.contains(k)) << c.dump();
        EXPECT_FALSE(c["measured"].empty()) << c.dump();
        claims[c["id"].get<std::string>()] = c["holds"].get<bool>();
    }
    for (const char* id : {"static_faster_than_separated", "separated_faster_than_classical", "smaller_maps_faster",
                           "glass_pixels_cost_linearly", "iterations_reduce_error", "iterations_diminishing_returns",
                           "depth_adds_bounces", "refractor_map_finds_the_exit",
                           "outside_search_tells_hits_from_misses", "separation_as_good_as_classical"})
        EXPECT_TRUE(claims.count(id)) << id;
    EXPECT_EQ(r["claims_total"].get<int>(), int(claims.size()));
    EXPECT_TRUE(claims["refractor_map_finds_the_exit"]) << r["figure3_refractor_exit"].dump();
    EXPECT_TRUE(claims["iterations_reduce_error"]) << r["figure2"].dump();
    fs::remove_all(o.outDir);
}

}  // namespace
}  // namespace rg::impostors
