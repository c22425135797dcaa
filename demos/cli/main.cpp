// `retroglass`: the command-line program behind ./retroglass (see README.md).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "bench_programs.h"
#include "core/error.h"
#include "conformance/trace_commands.h"
#include "core/profile.h"
#include "raycore/raytrace_command.h"
#include "compare.h"
#include "gallery.h"
#include "report.h"
#include "reproduction.h"
#include "shards.h"
#include "view_command.h"
#ifdef RETROGLASS_HAVE_BENCH
#include "bench_command.h"
#endif

namespace fs = std::filesystem;

namespace {

struct GlobalOptions {
    int threads = 0;
    std::string path = "fast";
    bool stats = false;
    std::string capture;
};

int hardwareThreads() {
    unsigned n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : int(n);
}

// ---- programs ---------------------------------------------------------------------------
// Every program a trace may name (docs/trace-format.md, version 2;
// rasterizer/include/rasterizer/program_registry.h): the bench workloads' and each paper's,
// registered before any command reads or records a programmable trace.
void registerTracePrograms() {
    rg::bench::registerPrograms();
    for (const rg::demos::Reproduction* r : rg::demos::reproductions()) r->registerPrograms();
}

// ---- profiles ---------------------------------------------------------------------------
int runProfiles() {
    for (const rg::Profile& p : rg::allProfiles()) {
        std::printf("%s\n  machine        %s\n  api            %s\n", std::string(p.name).c_str(),
                    std::string(p.machine).c_str(), std::string(p.apiName).c_str());
        std::printf("  texture stages %d per pass, %d coordinate sets\n", p.maxTextureStages,
                    p.maxTexCoordSets);
        std::printf("  max texture    %d (cube %d, 4D %d)%s\n", p.maxTextureSize, p.maxCubeMapSize,
                    p.max4DTextureSize, p.powerOfTwoOnly ? ", powers of two only" : "");
        std::printf("  texture memory %llu MiB\n",
                    (unsigned long long)(p.textureMemoryBytes >> 20));
        std::printf("  color table    %d entries\n", p.colorTableSize);
        std::printf("  framebuffer    RGBA%d, max viewport %d, %d subpixel bits\n", p.colorBits,
                    p.maxViewport, p.subpixelBits);
        std::printf("  features      ");
        for (uint32_t f = 0; f < uint32_t(rg::Feature::Count); ++f)
            if (p.has(rg::Feature(f)))
                std::printf(" [%s]", std::string(rg::featureName(rg::Feature(f))).c_str());
        std::printf("\n  sources        %s\n\n", std::string(p.sources).c_str());
    }
    return 0;
}

// ---- reproduce --------------------------------------------------------------------------
int runReproduce(const std::string& name, const std::string& quality, const std::string& outDir,
                 const std::string& scene, const std::string& views, const std::string& mover,
                 const GlobalOptions& g) {
    rg::demos::ReproduceOptions base;
    base.quality = rg::demos::qualityByName(quality);
    base.threads = g.threads;
    base.referencePath = g.path == "reference";
    base.stats = g.stats;
    base.scene = scene;
    base.views = views;
    base.mover = mover;
    base.capture = g.capture;
    if (name != "all") rg::demos::findReproduction(name);  // an unknown name is an error
    if (!g.capture.empty()) {
        // One file holds one frame: name the reproduction, and one that records a frame.
        std::string which;
        for (const rg::demos::Reproduction* r : rg::demos::reproductions())
            if (r->built() && !r->capturedFrame().empty())
                which += (which.empty() ? "" : ", ") + r->name();
        if (name == "all")
            throw rg::Error("--capture records one reproduction's frame: name it (" + which + ")");
        const std::string frame = rg::demos::findReproduction(name).capturedFrame();
        if (frame.empty())
            throw rg::Error("--capture: " + name + " records no frame as a trace yet (" + which + " do)");
        if (!views.empty())
            throw rg::Error("--capture records a frame of the evaluation, which a --views shard "
                            "does not run: capture from `reproduce " + name + "` without --views");
        // The file is written after the whole reproduction: a path that cannot be written
        // is refused now, not after minutes of precompute (the probe leaves no file behind).
        {
            const bool existed = fs::exists(g.capture);
            std::ofstream probe(g.capture, std::ios::binary | std::ios::app);
            if (!probe) throw rg::Error("--capture: cannot write '" + g.capture + "'");
            probe.close();
            if (!existed) fs::remove(g.capture);
        }
        std::printf("%-10s --capture %s: %s\n", name.c_str(), g.capture.c_str(), frame.c_str());
    }

    int status = 0;
    fs::create_directories(outDir);
    std::vector<std::string> summary;
    for (const rg::demos::Reproduction* r : rg::demos::reproductions()) {
        if (name != "all" && name != r->name()) continue;
        if (!r->built()) {
            std::printf("%-10s not built yet (%s)\n", r->name().c_str(), r->paper().c_str());
            continue;
        }
        rg::demos::ReproduceOptions o = base;
        o.outDir = fs::path(outDir) / r->name();
        fs::create_directories(o.outDir);
        std::printf("%-10s reproducing on profile %s at %s quality into %s\n", r->name().c_str(),
                    r->profile().c_str(), quality.c_str(), o.outDir.string().c_str());
        std::fflush(stdout);
        try {
            nlohmann::json results = r->reproduce(o);
            if (!results.empty()) summary.push_back(rg::demos::claimsLine(r->name(), results));
        } catch (const rg::Error& e) {
            // One paper failing does not stop the others; the status says it failed.
            std::fprintf(stderr, "retroglass: %s: %s\n", r->name().c_str(), e.what());
            summary.push_back(r->name() + ": FAILED (" + e.what() + ")");
            status = 1;
        }
    }
    rg::demos::writeGallery(outDir, rg::demos::reproductions());
    for (const std::string& line : summary) std::printf("%s\n", line.c_str());
    std::printf("gallery: %s\n", (fs::path(outDir) / "index.html").string().c_str());
    return status;
}

// ---- test -------------------------------------------------------------------------------
int runTests(const std::vector<std::string>& extra, const GlobalOptions& g) {
    std::string cmd = "ctest --test-dir '" RETROGLASS_BUILD_DIR "' --output-on-failure -j " +
                      std::to_string(g.threads > 0 ? g.threads : hardwareThreads());
    for (const auto& e : extra) cmd += " '" + e + "'";
    std::printf("%s\n", cmd.c_str());
    std::fflush(stdout);
    int rc = std::system(cmd.c_str());
    return rc == 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"retroglass: 1999-2008 graphics hardware, emulated bit-exactly on the CPU, "
                 "reproducing five papers on interactive reflections and refractions"};
    app.require_subcommand(1);
    GlobalOptions g;
    app.add_option("--threads", g.threads, "worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    app.add_option("--path", g.path,
                   "rasterizer implementation: fast (tiles, threads, SIMD) or reference (the "
                   "scalar code that reads like docs/hardware.md); both give the same bytes")
        ->check(CLI::IsMember({"fast", "reference"}));
    app.add_flag("--stats", g.stats, "print the emulated device's per-frame counters");
    app.add_option("--capture", g.capture,
                   "record the frame a reproduction times as a trace (docs/trace-format.md; "
                   "play it with `retroglass replay FILE`)");

    auto* profiles = app.add_subcommand("profiles", "print every hardware profile and its limits");

    std::string reproName = "all", quality = "quick", outDir = "out", scene, views, mover;
    auto* reproduce = app.add_subcommand(
        "reproduce", "run the paper reproductions into out/ (with out/index.html)");
    reproduce->add_option("name", reproName, "pem, hybrid, lightfield, impostors, tir or all");
    reproduce->add_option("--quality", quality, "quick (minutes) or paper (the paper's settings)")
        ->check(CLI::IsMember({"quick", "paper"}));
    reproduce->add_option("--out", outDir, "output folder");
    reproduce->add_option("--scene", scene, "a scene file (docs/scene-format.md) to use instead");
    reproduce->add_option("--views", views, "viewpoint range A:B of a split precompute");
    reproduce->add_option("--mover", mover, "impostors with --scene: the object that moves (default: the last glass or mirror object)");

    std::string mergeOut = "out";
    std::vector<std::string> mergeShardDirs;
    auto* merge = app.add_subcommand(
        "merge", "join the precompute shards of `reproduce --views A:B` runs (docs/cluster.md) "
                 "into <out>/<paper>/assets; then `reproduce <paper> --out <out>` evaluates");
    merge->add_option("shards", mergeShardDirs, "the shards' --out folders (or assets folders)")
        ->required();
    merge->add_option("--out", mergeOut, "output folder (its <paper>/assets must not exist)");

    rg::ray::RaytraceArgs rt;
    auto* raytrace = app.add_subcommand(
        "raytrace", "render the ray-traced ground truth of a scene (built-in name or JSON file)");
    raytrace->add_option("--scene", rt.scene, "built-in scene name or scene file")->required();
    raytrace->add_option("--camera", rt.camera, "camera name, index, or PATH:I on a viewpoint path");
    raytrace->add_option("--spp", rt.spp, "n for n×n samples per pixel")->check(CLI::Range(1, 64));
    raytrace->add_option("--mode", rt.mode, "whitted, two-term or pem-layers")
        ->check(CLI::IsMember({"whitted", "two-term", "pem-layers"}));
    raytrace->add_option("--depth", rt.depth, "ray-tree depth")->check(CLI::Range(0, 64));
    raytrace->add_option("--width", rt.width, "image width")->check(CLI::Range(1, 16384));
    raytrace->add_option("--height", rt.height, "image height")->check(CLI::Range(1, 16384));
    raytrace->add_option("--out", rt.out, "output image (.png, .exr, .hdr)")->required();

    rg::viewer::ViewOptions view;
    auto* viewCmd = app.add_subcommand(
        "view", "the interactive viewer of a demo (window with a control panel; or replay a "
                "recording headless)");
    viewCmd->add_option("demo", view.demo, "the demo: pem");
    viewCmd->add_option("--profile", view.profile, "hardware profile (default: the paper's)");
    viewCmd->add_option("--scene", view.scene, "a scene file (docs/scene-format.md)");
    viewCmd->add_option("--record", view.record, "save the input stream with frame numbers");
    viewCmd->add_option("--replay", view.replay, "play a recording (in the window, or --headless)");
    viewCmd->add_flag("--headless", view.headless, "no window: render the replayed frames into --out");
    viewCmd->add_option("--out", view.out, "folder for the headless frames (default out/view/replay)");
    viewCmd->add_option("--shots", view.shots, "folder for the window's screenshots");
    viewCmd->add_option("--frames", view.maxFrames, "quit after this many frames (0: when closed)");
    viewCmd->footer(rg::viewer::bindingsHelp());

    rg::demos::CompareOptions compareOptions;
    std::string compareQuality = "quick";
    auto* compare = app.add_subcommand(
        "compare", "every technique that applies to a scene's mirror or glass objects, side by "
                   "side against the ray tracer (tables, image grids, a plot into out/compare)");
    compare->add_option("--scene", compareOptions.scene, "built-in scene name or scene file");
    compare->add_option("--view", compareOptions.views,
                        "a view: on, between, above (around the scene's viewpoint path), a "
                        "camera name or index, or PATH:I (repeatable; default on, between, above)");
    compare->add_option("--technique", compareOptions.techniques,
                        "only these papers' techniques (repeatable)");
    compare->add_option("--out", compareOptions.outDir, "output folder");
    compare->add_option("--quality", compareQuality, "quick or paper")
        ->check(CLI::IsMember({"quick", "paper"}));
    compare->add_option("--width", compareOptions.width, "image width")->check(CLI::Range(16, 4096));
    compare->add_option("--height", compareOptions.height, "image height")->check(CLI::Range(16, 4096));

    rg::conformance::TraceCommands traceCommands(app);  // replay, conform

    std::vector<std::string> testArgs;
    auto* test = app.add_subcommand("test", "run the whole test suite through CTest");
    test->add_option("ctest-args", testArgs, "extra arguments for ctest (e.g. -R blend)");

#ifdef RETROGLASS_HAVE_BENCH
    rg::bench::BenchCommand bench;
    bench.add(app, /*withTrace=*/true);
#endif

    CLI11_PARSE(app, argc, argv);
    try {
        registerTracePrograms();
        if (!g.capture.empty() && !*reproduce)
            throw rg::Error("--capture records the frame a reproduction times: use it with `reproduce <name>`");
        if (*profiles) return runProfiles();
        if (*reproduce) return runReproduce(reproName, quality, outDir, scene, views, mover, g);
        if (*test) return runTests(testArgs, g);
        if (*merge) {
            std::vector<fs::path> shards(mergeShardDirs.begin(), mergeShardDirs.end());
            const rg::demos::MergeResult m = rg::demos::mergeShards(shards, mergeOut);
            std::printf("merge: %d views of %s from %zu shards into %s\n", m.views,
                        m.paper.c_str(), shards.size(), m.assets.string().c_str());
            return 0;
        }
        if (*compare) {
            compareOptions.threads = g.threads;
            compareOptions.quality = rg::demos::qualityByName(compareQuality);
            rg::demos::runCompare(compareOptions);
            return 0;
        }
        if (traceCommands.parsed()) return traceCommands.run(g.threads, g.path);
        if (*viewCmd) {
            view.threads = g.threads;
            return rg::viewer::runView(view);
        }
        if (*raytrace) {
            rt.threads = g.threads;
            return rg::ray::runRaytraceCommand(rt);
        }
#ifdef RETROGLASS_HAVE_BENCH
        if (*bench.subcommand) return bench.run(g.threads, g.path == "reference", argv[0]);
#endif
    } catch (const rg::Error& e) {
        std::fprintf(stderr, "retroglass: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "retroglass: unexpected error: %s\n", e.what());
        return 3;
    }
    return 0;
}
