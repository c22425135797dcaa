// `retroglass conform`: every golden trace on ours and on Mesa (llvmpipe), compared per
// trace by the count of differing pixels and the largest channel difference, against the
// tolerances docs/hardware.md ("Conformance against Mesa") justifies.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "conformance/mesa_player.h"
#include "core/error.h"

namespace rg::conformance {

namespace {

// Per-trace tolerance (docs/hardware.md, "Conformance against Mesa"): every pixel may
// differ by up to `smallDiff` per channel (rounding), and at most `maxLargeShare` of the
// pixels by more (coverage or level flips). Where Mesa (llvmpipe) rounds differently:
//   snapping  ours snaps window positions to the profile's subpixel bits (4 on the period
//             machines), llvmpipe to 8: a pixel centre within 1/16 px of an edge may flip,
//             and untransformed vertices move by up to 1/32 px, which shifts every
//             interpolated attribute of the triangle a little
//   blend     ours is round(x·y/255) exactly per product; llvmpipe's unorm8 multiply
//             approximates the division: ±1 per product, ±2 for src·f + dst·g
//   combine   llvmpipe evaluates ARB_texture_env_combine in unorm8 with the same kind of
//             approximation, then scales: ±1, up to ±3 with RGB_SCALE 2 or 4
//   filter    both weight bilinear taps with 8 fraction bits, but llvmpipe's coordinates
//             come from its own (float, per-pixel) interpolation; on the golden traces'
//             uncorrelated random texels a small coordinate difference is a visible one
struct Tolerance {
    int smallDiff;         // rounding: every pixel may differ by this much per channel
    double maxLargeShare;  // coverage and level flips: this share may differ by more
    const char* why;
};

const std::map<std::string, Tolerance>& tolerances() {
    static const std::map<std::string, Tolerance> table = {
        {"alpha-test", {2, 0.0, "colour interpolation ±1; alpha compared in 8 bits on both"}},
        {"blend-factors", {2, 0.0, "blend rounding: ±1 per product"}},
        {"blend-ops", {2, 0.0, "blend rounding: ±1 per product"}},
        {"depth-compare-d16", {2, 0.0, "colour interpolation ±1; depth quantized alike"}},
        {"depth-compare-d24", {2, 0.0, "colour interpolation ±1; depth quantized alike"}},
        {"fragment-scissor-mask-specular", {2, 0.0, "interpolation and the specular sum ±1"}},
        {"passes-readback", {4, 0.0, "filter, combine and blend rounding over two passes"}},
        {"programmable-binary-search",
         {1, 0.0, "the search is exact on both; float to unorm8 rounds the frame's one tie to even on llvmpipe "
                  "(bench/binary_search_workload.h)"}},
        {"raster-fill-rule", {2, 0.03, "snapping: 4 vs 8 subpixel bits flips edge pixels"}},
        {"raster-transform-clip-cull", {2, 0.03, "snapping: 4 vs 8 subpixel bits flips edge pixels"}},
        {"stage-ops-color", {3, 0.0, "combiner rounding, ±3 with the 2x/4x scales"}},
        {"stage-ops-alpha", {6, 0.0, "combiner alpha ±2, seen through a SRCALPHA blend"}},
        {"texgen-gl-modes", {40, 0.0, "snapped untransformed vertices move coordinates ~0.1 texel on minified noise"}},
        {"texture-address-filter", {4, 0.04, "GL_CLAMP border mixing and texel-edge ties flip"}},
        {"texture-cube-reflection", {4, 0.06, "edges, cube-face choice at seams, per-pixel λ"}},
        {"texture-formats", {2, 0.0, "filter and modulate rounding"}},
        {"texture-mipmap-lod", {2, 0.0, "filter rounding (pre-transformed: no snapping difference)"}},
        {"texture-units-3d", {2, 0.0, "filter and combine rounding"}},
    };
    return table;
}

Tolerance toleranceFor(const std::string& name) {
    if (auto it = tolerances().find(name); it != tolerances().end()) return it->second;
    return {2, 0.0, "no tolerance set for this trace: rounding only"};
}

// Whether a golden trace is compared or ours-only is part of what conform checks: a
// trace with a tolerance above that Mesa suddenly cannot play (a player or mapping change
// made mesaUnsupported() refuse it) must fail rather than silently drop to ours-only,
// and a trace listed here that Mesa now plays needs a tolerance instead. Traces in
// neither list (a --golden folder of one's own) are reported without expectation.
bool hasTolerance(const std::string& name) { return tolerances().count(name) > 0; }

bool expectedOursOnly(const std::string& name) {
    static const std::set<std::string> list = {
        "color-table",           // SGI_texture_color_table
        "pixel-texture",         // SGIX_pixel_texture
        "texture-4d",            // SGIS_texture4D
        "raster-affine-colour",  // colours without perspective correction
        "stage-args-cascade",    // D3DTA_SPECULAR as a stage argument
        "stage-ops-d3d-only",    // the Direct3D-only stage ops
    };
    return list.count(name) > 0;
}

}  // namespace

int runConform(const std::string& goldenDir) {
    namespace fs = std::filesystem;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(goldenDir))
        if (e.path().extension() == ".trace") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw Error("no .trace files in '" + goldenDir + "'");
    std::printf("%-32s %-9s %9s %8s %7s %6s  %s\n", "trace", "result", "differing", "max diff", "beyond", "share",
                "tolerance: channel difference <= N except a share of pixels (why)");
    int failures = 0, compared = 0, oursOnly = 0;
    std::string renderer;
    for (const fs::path& f : files) {
        const std::string name = f.stem().string();
        const raster::Trace trace = raster::readTraceFile(f);
        MesaReplay m = replayOnMesa(trace);
        const bool expectOursOnly = expectedOursOnly(name);
        if (!m.unsupported.empty()) {
            const bool unexpected = hasTolerance(name);
            std::printf("%-32s %-9s %9s %8s %7s %6s  %s%s\n", name.c_str(),
                        unexpected ? "FAIL" : "ours-only", "-", "-", "-", "-", oursOnlyReason(trace).c_str(),
                        unexpected ? " — but this trace has a tolerance: it used to be compared" : "");
            if (unexpected) {
                ++failures;
                std::printf("    reproduce: ./retroglass replay %s --backend mesa\n", f.string().c_str());
            }
            ++oursOnly;
            continue;
        }
        if (expectOursOnly) {
            std::printf("%-32s %-9s Mesa now plays it: give it a tolerance in conformance/conform.cpp "
                        "and drop it from the ours-only list\n", name.c_str(), "FAIL");
            ++failures;
        }
        renderer = m.renderer;
        const raster::ReplayResult ours = raster::replayTrace(trace, {Path::Reference, 1, -1});
        const auto a = ours.framebuffer.color();
        const auto b = m.framebuffer.color();
        size_t differing = 0, large = 0;
        int maxDiff = 0;
        const Tolerance t = toleranceFor(name);
        for (size_t i = 0; i < a.size(); ++i) {
            const int d = std::max({std::abs(a[i].r - b[i].r), std::abs(a[i].g - b[i].g),
                                    std::abs(a[i].b - b[i].b), std::abs(a[i].a - b[i].a)});
            if (d) ++differing;
            if (d > t.smallDiff) ++large;
            maxDiff = std::max(maxDiff, d);
        }
        const double share = double(large) / double(a.size());
        const bool pass = share <= t.maxLargeShare;
        if (!pass) ++failures;
        ++compared;
        std::printf("%-32s %-9s %9zu %8d %7zu %5.1f%%  <= %d, %.0f%% beyond: %s\n", name.c_str(),
                    pass ? "ok" : "FAIL", differing, maxDiff, large, 100.0 * share, t.smallDiff,
                    100.0 * t.maxLargeShare, t.why);
        if (!pass)
            std::printf("    reproduce: ./retroglass replay %s --out ours.png && "
                        "./retroglass replay %s --backend mesa --out mesa.png\n",
                        f.string().c_str(), f.string().c_str());
    }
    std::printf("\n%d compared against %s, %d ours-only, %d failing (outside tolerance, or not compared/ours-only as listed)\n", compared,
                renderer.empty() ? "Mesa" : renderer.c_str(), oursOnly, failures);
    return failures ? 1 : 0;
}

}  // namespace rg::conformance
