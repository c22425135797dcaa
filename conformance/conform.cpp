// `retroglass conform`: every golden trace on ours and on Mesa (llvmpipe), compared per
// trace by the count of differing pixels and the largest channel difference, against the
// tolerances docs/hardware.md ("Conformance against Mesa") justifies.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "conformance/mesa_player.h"
#include "core/error.h"

namespace rg::conformance {

namespace {

// Per-trace tolerance: the share of pixels that may differ at all, and the largest
// difference of one channel among them. Where Mesa rounds differently (docs/hardware.md):
//   edges     llvmpipe snaps to 8 subpixel bits with its own fill convention on the
//             D3D-style pixel centres: a pixel or two per edge may flip (coverage),
//             so differing pixels may differ by anything; bounded by their share.
//   colour    llvmpipe interpolates colours in float and converts with its own rounding
//             (our: fixed point, docs/hardware.md "Colour interpolation"): ±2 per step.
//   blend     llvmpipe blends in unorm8 with x·y/255 approximated as (x·y + 128)·257 >> 16
//             style rounding, ours is round(x·y/255) exactly: ±1, ±2 with two factors.
//   filter    llvmpipe's bilinear weights have 8 fraction bits like ours, but its LOD
//             uses its own log2 approximation and per-pixel (not per-quad) λ in places,
//             so mip-level choices at λ boundaries differ: large differences, bounded share.
struct Tolerance {
    double maxShare;  // of the pixels, differing at all
    int maxDiff;      // largest channel difference allowed among them (255: any)
    const char* why;
};

Tolerance toleranceFor(const std::string& name) {
    if (name.rfind("raster-", 0) == 0) return {0.25, 255, "edges and colour interpolation"};
    if (name.rfind("depth-", 0) == 0) return {0.15, 255, "edges, depth quantization at equal depths"};
    if (name.rfind("blend-", 0) == 0) return {0.35, 255, "blend rounding, edges"};
    if (name.rfind("stage-", 0) == 0) return {0.50, 255, "combiner rounding (x·y/255), filtering"};
    if (name.rfind("texture-", 0) == 0 || name.rfind("texgen-", 0) == 0)
        return {0.60, 255, "filter weights, LOD at level boundaries, edges"};
    return {0.30, 255, "edges, interpolation and blend rounding"};
}

}  // namespace

int runConform(const std::string& goldenDir) {
    namespace fs = std::filesystem;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(goldenDir))
        if (e.path().extension() == ".trace") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw Error("no .trace files in '" + goldenDir + "'");
    std::printf("%-32s %-9s %9s %6s %8s  %s\n", "trace", "result", "differing", "share", "max diff", "tolerance / reason");
    int failures = 0, compared = 0, oursOnly = 0;
    std::string renderer;
    for (const fs::path& f : files) {
        const std::string name = f.stem().string();
        const raster::Trace trace = raster::readTraceFile(f);
        MesaReplay m = replayOnMesa(trace);
        if (!m.unsupported.empty()) {
            std::printf("%-32s %-9s %9s %6s %8s  Mesa lacks %s\n", name.c_str(), "ours-only", "-", "-", "-",
                        m.unsupported.c_str());
            ++oursOnly;
            continue;
        }
        renderer = m.renderer;
        const raster::ReplayResult ours = raster::replayTrace(trace, {Path::Reference, 1, -1});
        const auto a = ours.framebuffer.color();
        const auto b = m.framebuffer.color();
        size_t differing = 0;
        int maxDiff = 0;
        for (size_t i = 0; i < a.size(); ++i) {
            const int d = std::max({std::abs(a[i].r - b[i].r), std::abs(a[i].g - b[i].g),
                                    std::abs(a[i].b - b[i].b), std::abs(a[i].a - b[i].a)});
            if (d) ++differing;
            maxDiff = std::max(maxDiff, d);
        }
        const double share = double(differing) / double(a.size());
        const Tolerance t = toleranceFor(name);
        const bool pass = share <= t.maxShare && maxDiff <= t.maxDiff;
        if (!pass) ++failures;
        ++compared;
        std::printf("%-32s %-9s %9zu %5.1f%% %8d  share <= %.0f%%, diff <= %d: %s\n", name.c_str(),
                    pass ? "ok" : "FAIL", differing, 100.0 * share, maxDiff, 100.0 * t.maxShare, t.maxDiff, t.why);
        if (!pass)
            std::printf("    reproduce: ./retroglass replay %s --out ours.png && "
                        "./retroglass replay %s --backend mesa --out mesa.png\n",
                        f.string().c_str(), f.string().c_str());
    }
    std::printf("\n%d compared against %s, %d ours-only, %d outside tolerance\n", compared,
                renderer.empty() ? "Mesa" : renderer.c_str(), oursOnly, failures);
    return failures ? 1 : 0;
}

}  // namespace rg::conformance
