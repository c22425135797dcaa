// The reproduction end to end at a small setting: the files, the results' keys, every claim
// reported with its section, statement, measured values and verdict, and the claims whose
// margins do not depend on the frame size or the machine's load: the refractor map finds the
// sphere's exit within a texel (a search that stopped at the entry, itself a root of the
// ratio, misses by the whole chord), and secant iterations cut the analytic room's error.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "claims_check.h"
#include "reproduce_impostors.h"
#include "scratch_dir.h"

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
                          "refractor_maps.png", "environment_impostor.png", "caustics.png", "caustics_mirror.png"})
        EXPECT_TRUE(fs::exists(o.outDir / f)) << f;
    for (const char* k : {"timing", "figure2", "figure9", "depth_sweep", "iteration_sweep", "glass_pixels_sweep",
                          "figure3_refractor_exit", "figure4_outside_search", "exit_total_reflection", "caustics",
                          "caustics_mirror", "claims"})
        EXPECT_TRUE(r.contains(k)) << k;
    // §7's caustics: both passes timed, the splats placed by vertex texture fetch (two texels
    // per corner, six corners per photon, 32² photons per piece and light).
    EXPECT_TRUE(r["caustics"]["passes"].contains("caustics: all pieces")) << r["caustics"].dump();
    EXPECT_TRUE(r["caustics"]["passes"].contains("caustics: the mover")) << r["caustics"].dump();
    EXPECT_EQ(r["caustics"]["passes"]["caustics: the mover"]["vertex_texture_fetches"].get<uint64_t>() %
                  uint64_t(2 * 6 * 32 * 32),
              0u);
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
                           "outside_search_tells_hits_from_misses", "separation_as_good_as_classical",
                           "caustics_where_photon_tracing_puts_them", "mirror_caustics_where_photon_tracing_puts_them"})
        EXPECT_TRUE(claims.count(id)) << id;
    // The mirror pawn's caustic alone: its photons reach the board in both, ours and the reference.
    EXPECT_GT(r["caustics_mirror"]["reference_board_hits"].get<int64_t>(), 0) << r["caustics_mirror"].dump();
    EXPECT_GT(r["caustics_mirror"]["ours_board_hits_estimate"].get<double>(), 0.0) << r["caustics_mirror"].dump();
    EXPECT_EQ(r["claims_total"].get<int>(), int(claims.size()));
    EXPECT_TRUE(claims["refractor_map_finds_the_exit"]) << r["figure3_refractor_exit"].dump();
    EXPECT_TRUE(claims["iterations_reduce_error"]) << r["figure2"].dump();
    fs::remove_all(o.outDir);
}

// The claims at quick quality, what `retroglass reproduce impostors` runs (docs/testing.md,
// "Claims tests"), from one run: every claim reported with its numbers and a row in
// report.md; every verdict is what its numbers say against the margin
// reproduce_impostors.cpp states (glass PSNR 0.5 dB, over four times the 0.11 dB it moves
// from 8 to 16 converged secant iterations; Figure 2: half the first guesses' error, and the
// converged error e16 between early and late gains; the exit within a texel; the outside
// search 95 % right; the timings' ratios and fit as stated); the claims that hold and do not
// depend on the machine asserted by id; each decided on the numbers results.json reports.
TEST(ImpostorClaims, EveryReportedClaimAtQuickQuality) {
    using namespace rg::test;
    ImpostorReproduceSettings s = impostorSettingsFor(demos::Quality::Quick);
    s.timedFrames = 1;  // §8's frame rates decide timing claims only (reported, not asserted)
    demos::ReproduceOptions o;
    o.outDir = scratchDir("impostors-quick");
    const nlohmann::json r = runImpostors(s, o);
    ASSERT_TRUE(r.contains("claims"));
    expectEveryClaimReportedWithNumbers(r);
    EXPECT_EQ(r["claims_total"].get<int>(), 13);
    for (const auto& c : r["claims"]) expectRowInReport(o.outDir / "report.md", r, c["id"].get<std::string>());

    // The verdicts against the stated margins, whether or not the claim holds.
    expectAtLeastVerdict(r, "depth_adds_bounces", "changed_psnr_depth_2", "changed_psnr_depth_1", 0.5);
    expectWithinVerdict(r, "separation_as_good_as_classical", "glass_psnr_separated", "glass_psnr_classical", 0.5);
    const auto& e = r["figure2"]["mean_error_by_iterations"];
    {
        const nlohmann::json c = claimById(r, "iterations_reduce_error");
        EXPECT_EQ(c["measured"]["error_0_iterations"].get<double>(), e[0].get<double>());
        EXPECT_EQ(c["measured"]["error_8_iterations"].get<double>(), e[8].get<double>());
        EXPECT_EQ(c["holds"].get<bool>(), e[0].get<double>() - e[8].get<double>() >= 0.5 * e[0].get<double>()) << c.dump(2);
    }
    {
        const nlohmann::json c = claimById(r, "iterations_diminishing_returns");
        const double early = e[0].get<double>() - e[4].get<double>(), late = e[8].get<double>() - e[16].get<double>();
        EXPECT_NEAR(c["measured"]["gain_0_to_4"].get<double>(), early, 1e-15);
        EXPECT_NEAR(c["measured"]["gain_8_to_16"].get<double>(), late, 1e-15);
        EXPECT_EQ(c["measured"]["converged_error_16"].get<double>(), e[16].get<double>());
        EXPECT_EQ(c["holds"].get<bool>(), early - late >= e[16].get<double>()) << c.dump(2);
    }
    {
        const nlohmann::json c = claimById(r, "refractor_map_finds_the_exit");
        const double median = r["figure3_refractor_exit"]["median_exit_error_texels"].get<double>();
        EXPECT_EQ(c["measured"]["median_texels"].get<double>(), median);
        EXPECT_EQ(c["holds"].get<bool>(), median <= 1.0) << c.dump(2);
    }
    {
        const nlohmann::json c = claimById(r, "outside_search_tells_hits_from_misses");
        const double eps = r["settings"]["epsilon_half_diagonal"].get<double>();
        double accuracy = -1;
        for (const auto& row : r["figure4_outside_search"]["by_epsilon"])
            if (std::abs(row["epsilon_half_diagonal"].get<double>() - eps) < 1e-6) accuracy = row["accuracy"].get<double>();
        EXPECT_EQ(c["measured"]["accuracy"].get<double>(), accuracy);
        EXPECT_EQ(c["holds"].get<bool>(), accuracy >= 0.95) << c.dump(2);
    }
    // The timings: decided on the ratios and the fit results.json reports, by their bars.
    for (const auto& [id, ratio, bar] : std::vector<std::tuple<std::string, std::string, double>>{
             {"static_faster_than_separated", "static_over_separated", 1.2},
             {"separated_faster_than_classical", "separated_over_classical", 2.0},
             {"smaller_maps_faster", "small_over_large_maps", 1.1}}) {
        const nlohmann::json c = claimById(r, id);
        const double ours = r["timing"]["ratios"][ratio].get<double>();
        EXPECT_NEAR(c["measured"]["ours"].get<double>(), ours, 1e-12) << id;
        EXPECT_GT(ours, 0.0) << id;
        EXPECT_EQ(c["holds"].get<bool>(), ours >= bar) << c.dump(2);
    }
    {
        const nlohmann::json c = claimById(r, "glass_pixels_cost_linearly");
        const auto& dolly = r["glass_pixels_sweep"];
        const auto& sweep = dolly["image_sizes"];
        EXPECT_NEAR(c["measured"]["r2"].get<double>(), sweep["r2"].get<double>(), 1e-12);
        EXPECT_NEAR(c["measured"]["dolly_r2"].get<double>(), dolly["r2"].get<double>(), 1e-12);
        EXPECT_NEAR(c["measured"]["ms_per_million_glass_fragments"].get<double>(),
                    sweep["ms_per_million_glass_fragments"].get<double>(), 1e-9);
        EXPECT_EQ(c["holds"].get<bool>(), sweep["ms_per_million_glass_fragments"].get<double>() > 0 &&
                                              sweep["r2"].get<double>() >= 0.9)
            << c.dump(2);
        EXPECT_EQ(dolly["frames"].size(), s.dollies.size());
        ASSERT_EQ(sweep["frames"].size(), s.sizeSweep.size());
        // The sweep changes the glass fragments: more of them at every larger size.
        for (size_t i = 1; i < s.sizeSweep.size(); ++i)
            EXPECT_GT(sweep["frames"][i]["glass_fragments"].get<int64_t>(),
                      sweep["frames"][i - 1]["glass_fragments"].get<int64_t>());
    }

    // Decided on the numbers results.json reports.
    expectMeasuredIs(r, "depth_adds_bounces", "glass_psnr_depth_1", "/depth_sweep/1/glass_psnr_db");
    expectMeasuredIs(r, "depth_adds_bounces", "glass_psnr_depth_2", "/depth_sweep/2/glass_psnr_db");
    expectMeasuredIs(r, "depth_adds_bounces", "changed_psnr_depth_1", "/depth_sweep/1/changed_pixels_psnr_db");
    expectMeasuredIs(r, "depth_adds_bounces", "changed_psnr_depth_2", "/depth_sweep/2/changed_pixels_psnr_db");
    expectMeasuredIs(r, "depth_adds_bounces", "changed_pixels", "/depth_sweep/changed_pixels");
    {
        // The pixels the claim is decided on: some, and a part of the glass pixels only.
        const auto& d = r["depth_sweep"];
        EXPECT_GT(d["changed_pixels"].get<int64_t>(), 0);
        EXPECT_LT(d["changed_pixels"].get<int64_t>(), d["changed_pixels_of_glass_pixels"].get<int64_t>());
    }
    expectMeasuredIs(r, "separation_as_good_as_classical", "glass_psnr_separated", "/figure9/separated/glass_psnr_db");
    expectMeasuredIs(r, "separation_as_good_as_classical", "glass_psnr_classical", "/figure9/classical/glass_psnr_db");

    {
        // §6: the height map's glass PSNR above the distance map's in every view, the mean
        // gain at least twice its standard error over the views (recomputed here from the
        // per-view numbers of results.json), and the exit's total reflections nearer the ray
        // tracer's share.
        const nlohmann::json c = claimById(r, "height_maps_beat_distance_maps_for_double_refraction");
        const auto& views = r["height_maps"]["views"];
        ASSERT_GE(views.size(), 2u);
        std::vector<double> gain;
        for (const auto& v : views)
            gain.push_back(v["height-map"]["glass_psnr_db"].get<double>() - v["distance-map"]["glass_psnr_db"].get<double>());
        double mean = 0, var = 0, minGain = 1e30;
        for (double g : gain) mean += g / double(gain.size()), minGain = std::min(minGain, g);
        for (double g : gain) var += (g - mean) * (g - mean) / double(gain.size() - 1);
        const double margin = 2.0 * std::sqrt(var / double(gain.size()));
        EXPECT_NEAR(c["measured"]["mean_gain_db"].get<double>(), mean, 1e-9);
        EXPECT_NEAR(c["measured"]["margin_db"].get<double>(), margin, 1e-9);
        const auto& t0 = views[0];
        const double rt = t0["height-map"]["exit_total_reflection"]["ray_tracer_fraction"].get<double>();
        const double th = t0["height-map"]["exit_total_reflection"]["ours_fraction"].get<double>();
        const double td = t0["distance-map"]["exit_total_reflection"]["ours_fraction"].get<double>();
        EXPECT_EQ(c["holds"].get<bool>(), minGain > 0 && mean >= margin && std::fabs(th - rt) < std::fabs(td - rt)) << c.dump(2);
        // Where the true exit is on a curved face, which a height map holds, it beats the
        // distance map by more than the PSNR margin (0.5 dB); the claim over every glass pixel
        // does not hold (below), decided by the flat bases a height map cannot hold.
        const auto& bf = r["height_maps"]["first_view_by_exit_face"];
        ASSERT_TRUE(bf.contains("curved") && bf.contains("flat")) << r["height_maps"].dump(2);
        EXPECT_GE(bf["curved"]["glass_psnr_height_map_db"].get<double>() - bf["curved"]["glass_psnr_distance_map_db"].get<double>(),
                  0.5)
            << bf.dump(2);
        EXPECT_EQ(c["measured"]["glass_psnr_curved_exits_height_map_db"].get<double>(),
                  bf["curved"]["glass_psnr_height_map_db"].get<double>());
        EXPECT_LE(bf["curved"]["pixels"].get<int64_t>() + bf["flat"]["pixels"].get<int64_t>(),
                  views[0]["height-map"]["glass_pixels"].get<int64_t>());
    }

    {
        // §7: the caustics' verdict from the scores results.json reports: the median distance
        // from the reference's peaks to ours against the measured margin (twice the 90th
        // percentile for the reference traced with half the photons, at least one texel).
        const nlohmann::json c = claimById(r, "caustics_where_photon_tracing_puts_them");
        std::printf("caustics at quick quality: %s\n", r["caustics"].dump().c_str());
        const auto& sc = r["caustics"]["scores"];
        const double median = sc["peak_offset_median_texels"].get<double>();
        const double margin = sc["peak_margin_texels"].get<double>();
        EXPECT_EQ(margin, std::max(1.0, 2.0 * sc["half_photon_reference_peak_offset_p90_texels"].get<double>()));
        EXPECT_EQ(c["measured"]["peak_offset_median_texels"].get<double>(), median);
        EXPECT_EQ(c["holds"].get<bool>(), median <= margin) << c.dump(2);
    }
    {
        // §7 with a mirror: the same verdict from the mirror pawn's scores.
        const nlohmann::json c = claimById(r, "mirror_caustics_where_photon_tracing_puts_them");
        const auto& sc = r["caustics_mirror"]["scores"];
        const double median = sc["peak_offset_median_texels"].get<double>();
        const double margin = sc["peak_margin_texels"].get<double>();
        EXPECT_EQ(margin, std::max(1.0, 2.0 * sc["half_photon_reference_peak_offset_p90_texels"].get<double>()));
        EXPECT_EQ(c["holds"].get<bool>(), median <= margin) << c.dump(2);
    }
    // Every claim that holds at quick quality and does not depend on the machine, by id.
    for (const char* id : {"iterations_reduce_error", "iterations_diminishing_returns", "refractor_map_finds_the_exit",
                           "separation_as_good_as_classical", "caustics_where_photon_tracing_puts_them",
                           "mirror_caustics_where_photon_tracing_puts_them"})
        expectHolds(r, id);
    // Not asserted to hold (verdicts checked above, rows in report.md):
    // - height_maps_beat_distance_maps_for_double_refraction: with the pieces' bases
    //   glass-air faces in the reference (2026-11-28; before, the ray tracer took the base or
    //   the board pixel by pixel, and the claim held by 2.3 dB against that noise), the height
    //   map loses by 1.7 dB over every glass pixel. 53 % of the first view's refracted rays
    //   first leave through a flat base or top, which a height map sees edge-on: there it
    //   scores 8.8 dB against the distance map's 11.8. On the curved exits it wins, 15.2
    //   against 13.8 dB (asserted above).
    // - depth_adds_bounces: over all glass pixels DEPTH 2 is within 0.01 dB of DEPTH 1
    //   against the ray tracer at quick quality, an error the extra bounce does not touch.
    //   Decided on the glass pixels (3 views) that DEPTH 1 and 3 render differently, DEPTH 2
    //   is 0.30 dB closer (12.88 against 12.58 dB), under the 0.5 dB margin.
    // - outside_search_tells_hits_from_misses: 89.9 % agreement with Embree at ε = 3 % of
    //   the pawn's half diagonal against the 95 % bar; most disagreements are hits missed (the
    //   report's Figure 4 table).
    // - static_faster_than_separated, separated_faster_than_classical, smaller_maps_faster
    //   (they hold today) and glass_pixels_cost_linearly (decided on the image-size sweep
    //   since the dolly's fit fell to R² 0.81 with the glass fragments' cost down): frame
    //   rates on this machine, decided by its load and the suite's other processes; reported
    //   with their numbers (checked above), never asserted.

    // Orderings the report states: the refractor exit's 95th percentile no nearer than its
    // median; the mover's impostor alone rebuilt when separated (one of 33 when classical).
    expectOrdering(r, "/figure3_refractor_exit/p95_exit_error_texels", "/figure3_refractor_exit/median_exit_error_texels",
                   0.0, "percentiles in order");
    expectOrdering(r, "/timing/classical/impostors_rebuilt_per_frame", "/timing/separated/impostors_rebuilt_per_frame", 1,
                   "separation rebuilds the mover's impostor only");
}

// The claims test can fail: with no secant iteration after the first guesses p and l, the
// exit a refracted ray finds in the sphere's refractor map is the first guess, and
// refractor_map_finds_the_exit no longer holds.
TEST(ImpostorClaims, NoSecantIterationBreaksAClaim) {
    ImpostorReproduceSettings s = impostorSettingsFor(demos::Quality::Quick);
    s.iterations = 0;
    // The sweeps and timings cut short (they decide no claim this changes).
    s.timedFrames = 1;
    s.depthSweep = {1, 2};
    s.iterationSweep = {0};
    s.dollies = {1.0f, 0.5f};
    demos::ReproduceOptions o;
    o.outDir = rg::test::scratchDir("impostors-no-iterations");
    const nlohmann::json r = runImpostors(s, o);
    const std::vector<std::string> broken = rg::test::brokenClaims(r);
    for (const std::string& id : broken) std::printf("does not hold with the wrong setting: %s\n", id.c_str());
    EXPECT_NE(std::find(broken.begin(), broken.end(), "refractor_map_finds_the_exit"), broken.end())
        << r["claims"].dump(2);
}

}  // namespace
}  // namespace rg::impostors
