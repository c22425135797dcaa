// The claims at quick quality, what `retroglass reproduce lightfield` runs (docs/testing.md,
// "Claims tests"), from one run: every claim reported with its numbers and a row in
// report.md; every verdict is what its numbers say against the margin
// reproduce_lightfield.cpp states (PSNR orderings 0.5 dB; the 4× cost within ±0.5; the
// Gortler weights within 2 LSB; the two routes equal to the byte); the claims that hold are
// asserted by id; each was decided on the numbers results.json reports. And the test can
// fail: a codebook of two entries for the (u, v)-halved light field breaks colour plate 3's
// ordering against the uncompressed light field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "claims_check.h"
#include "reproduce_lightfield.h"
#include "scratch_dir.h"

namespace rg::lightfield {
namespace {

TEST(LightfieldClaims, EveryReportedClaimAtQuickQuality) {
    using namespace rg::test;
    demos::ReproduceOptions o;
    o.outDir = scratchDir("lightfield-quick");
    const nlohmann::json r = runLightfield(lightfieldSettingsFor(demos::Quality::Quick), o);
    ASSERT_TRUE(r.contains("claims"));
    expectEveryClaimReportedWithNumbers(r);
    EXPECT_EQ(r["claims_total"].get<int>(), 10);
    for (const auto& c : r["claims"]) expectRowInReport(o.outDir / "report.md", r, c["id"].get<std::string>());

    // The verdicts against the stated margins, whether or not the claim holds.
    expectAtLeastVerdict(r, "uncompressed_beats_uv_halved", "uncompressed", "uv_halved", 0.5);
    expectAtLeastVerdict(r, "uv_halved_beats_all_halved", "uv_halved", "all_halved", 0.5);
    expectAtLeastVerdict(r, "uv_halved_beats_all_halved_vs_uncompressed", "uv_halved", "all_halved", 0.5);
    expectAtLeastVerdict(r, "light_field_lighting_beats_environment_map", "light_field", "environment_map", 0.5);
    expectWithinVerdict(r, "vq_colour_passes_cost_4x", "vq_over_uncompressed", "paper", 0.5);
    expectWithinVerdict(r, "pixel_texture_equals_software", "differing_pixels", "none", 0.0);
    expectWithinVerdict(r, "gortler_weights_sum_to_one", "max_error_lsb", "zero", 2.0);
    expectAtLeastVerdict(r, "interactive_at_400", "slower_route_fps", "paper_o2_fps", 0.0);
    {
        const nlohmann::json c = claimById(r, "uncompressed_overflows_compressed_fits");
        const auto& m = c["measured"];
        const bool swapped = r["vector_quantization"]["uncompressed"]["swapped"].get<bool>();
        EXPECT_EQ(c["holds"].get<bool>(), m["uncompressed_bytes"].get<uint64_t>() > m["texture_memory"].get<uint64_t>() &&
                                              swapped &&
                                              m["vq_bytes"].get<uint64_t>() <= m["texture_memory"].get<uint64_t>())
            << c.dump(2);
        // Swapped: the whole light field goes up every frame.
        EXPECT_EQ(m["upload_bytes_per_frame"].get<uint64_t>(), m["uncompressed_bytes"].get<uint64_t>()) << c.dump(2);
    }
    {
        const nlohmann::json c = claimById(r, "environment_swap_needs_no_recompute");
        const auto& m = c["measured"];
        const int env = r["settings"]["env_size"].get<int>();
        EXPECT_EQ(m["map_bytes"].get<uint64_t>(), uint64_t(env) * env * 2 * 3);  // two paraboloids, RGB8
        // The swap uploads the map and adds no light-field bytes; residency is a memory limit
        // reported beside it (a light field that does not fit is streamed every frame).
        EXPECT_EQ(c["holds"].get<bool>(), m["map_upload_bytes"].get<uint64_t>() == m["map_bytes"].get<uint64_t>() &&
                                              m["light_field_upload_bytes_after_swap"].get<uint64_t>() ==
                                                  m["light_field_upload_bytes_before_swap"].get<uint64_t>())
            << c.dump(2);
        const uint64_t lfUpload = r["environment_route"]["environment_swap_light_field_upload_bytes"].get<uint64_t>();
        EXPECT_EQ(lfUpload, m["light_field_upload_bytes_after_swap"].get<uint64_t>());
        if (m["light_field_resident"].get<bool>())
            EXPECT_EQ(lfUpload, 0u);
        else
            EXPECT_GT(lfUpload, 0u);  // the slices streamed in, not a count that reads 0
    }

    // Decided on the numbers results.json reports.
    expectMeasuredIs(r, "uncompressed_beats_uv_halved", "uncompressed", "/vector_quantization/uncompressed/psnr_vs_raytracer");
    expectMeasuredIs(r, "uncompressed_beats_uv_halved", "uv_halved",
                     "/vector_quantization/variants/uv_halved/psnr_vs_raytracer/psnr_db");
    expectMeasuredIs(r, "uv_halved_beats_all_halved", "all_halved",
                     "/vector_quantization/variants/all_halved/psnr_vs_raytracer/psnr_db");
    expectMeasuredIs(r, "uv_halved_beats_all_halved_vs_uncompressed", "uv_halved",
                     "/vector_quantization/variants/uv_halved/psnr_vs_uncompressed/psnr_db");
    expectMeasuredIs(r, "uv_halved_beats_all_halved_vs_uncompressed", "all_halved",
                     "/vector_quantization/variants/all_halved/psnr_vs_uncompressed/psnr_db");
    expectMeasuredIs(r, "vq_colour_passes_cost_4x", "vq_over_uncompressed",
                     "/vector_quantization/colour_fragment_ratio_all_halved");
    expectMeasuredIs(r, "light_field_lighting_beats_environment_map", "light_field",
                     "/lighting_from_light_field/light_field_lighting/psnr_db");
    expectMeasuredIs(r, "light_field_lighting_beats_environment_map", "environment_map",
                     "/lighting_from_light_field/environment_map_lighting/psnr_db");
    expectMeasuredIs(r, "pixel_texture_equals_software", "differing_pixels", "/environment_route/differing_pixels");
    expectMeasuredIs(r, "gortler_weights_sum_to_one", "max_error_lsb", "/environment_route/gortler_weight_max_error_lsb");
    {
        // The 4× is the all-halved variant's colour fragments over the uncompressed frame's.
        const auto& vq = r["vector_quantization"];
        EXPECT_NEAR(vq["colour_fragment_ratio_all_halved"].get<double>(),
                    vq["variants"]["all_halved"]["colour_fragments"].get<double>() /
                        vq["uncompressed"]["fragments"].get<double>(),
                    1e-12);
        // The routes' images are the same bytes: the hashes agree for both environments.
        const auto& e = r["environment_route"];
        EXPECT_EQ(e["pixel_texture_sha256_a"], e["software_sha256_a"]);
        EXPECT_EQ(e["pixel_texture_sha256_b"], e["software_sha256_b"]);
        // The slower route is the slower of the two timed at 400².
        const auto& f = r["frame_rates_400"];
        EXPECT_NEAR(claimById(r, "interactive_at_400")["measured"]["slower_route_fps"].get<double>(),
                    std::min(f["pixel_texture_sgi_octane_mxe"]["fps"].get<double>(), f["software_sgi_o2"]["fps"].get<double>()),
                    1e-9);
    }

    // Every claim that holds at quick quality and does not depend on the machine, by id.
    for (const char* id : {"vq_colour_passes_cost_4x", "uv_halved_beats_all_halved_vs_uncompressed",
                           "uncompressed_overflows_compressed_fits", "pixel_texture_equals_software",
                           "light_field_lighting_beats_environment_map", "environment_swap_needs_no_recompute",
                           "gortler_weights_sum_to_one"})
        expectHolds(r, id);
    // Not asserted to hold (verdicts checked above, rows in report.md):
    // - uncompressed_beats_uv_halved (0.24 dB) and uv_halved_beats_all_halved (0.05 dB) against
    //   the ray tracer: the light field's own sampling error (19.5 dB against the ray tracer)
    //   is far larger than the codebook's (30–32 dB against the uncompressed light field), so
    //   colour plate 3's ordering shows against the ray tracer by less than 0.5 dB; against
    //   the uncompressed light field it holds by 2.3 dB (asserted above). The report says so.
    // - interactive_at_400: a frame rate on this machine (about 80 fps against the paper's 10
    //   at quick quality), decided by its load and the suite's other processes; reported
    //   with its numbers (checked above), not asserted.

    // Orderings the report's text states: the uncompressed light field does not fit the
    // Octane's texture memory and the VQ one does (exact byte counts: one byte); "the light
    // field's own sampling error is larger than the codebook's": each VQ variant is closer
    // to the uncompressed light field than the uncompressed light field is to the ray
    // tracer, by the 0.5 dB of every PSNR ordering. (The report says it of the (u, v)- and
    // all-halved variants, colour plate 3's; the (s, t)-halved one samples its index textures
    // NEAREST, losing the (u, v) interpolation, and is 0.1 dB further from the uncompressed
    // light field than that is from the ray tracer.)
    expectOrdering(r, "/memory/radiance_light_field_bytes", "/memory/octane_texture_memory", 1,
                   "the uncompressed light field does not fit");
    expectOrdering(r, "/memory/octane_texture_memory", "/memory/vq_all_halved_bytes", 0, "the VQ light field fits");
    for (const char* v : {"uv_halved", "all_halved"})
        expectOrdering(r, std::string("/vector_quantization/variants/") + v + "/psnr_vs_uncompressed/psnr_db",
                       "/vector_quantization/uncompressed/psnr_vs_raytracer", 0.5,
                       "the light field's sampling error is larger than the codebook's");
}

// The claims test can fail: with a codebook of two entries for the (u, v)-halved light field
// (the paper's all-halved variant keeps its own), that variant loses almost everything the
// light field holds, and uv_halved_beats_all_halved_vs_uncompressed no longer holds.
TEST(LightfieldClaims, ATwoEntryCodebookBreaksAClaim) {
    demos::ReproduceOptions o;
    o.outDir = rg::test::scratchDir("lightfield-two-codewords");
    LightfieldSettings s = lightfieldSettingsFor(demos::Quality::Quick);
    s.vqKOther = 2;
    const nlohmann::json r = runLightfield(s, o);
    const std::vector<std::string> broken = rg::test::brokenClaims(r);
    for (const std::string& id : broken) std::printf("does not hold with the wrong setting: %s\n", id.c_str());
    EXPECT_NE(std::find(broken.begin(), broken.end(), "uv_halved_beats_all_halved_vs_uncompressed"), broken.end())
        << r["claims"].dump(2);
}

}  // namespace
}  // namespace rg::lightfield
