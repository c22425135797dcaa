// `retroglass bench --trace FILE`: one captured trace (docs/trace-format.md) replayed on
// ours and through Mesa llvmpipe in the same run, at 1 and all threads each, so that the
// harness prints ours/llvmpipe in replays per second.
//
// What one replay is, on both sides: the trace already in memory (read once, before
// timing) played from its initial framebuffer contents to the end, texture uploads
// (all levels, from the trace's texels) and read-backs included.
//   ours      raster::replayTrace(): a fresh Device, its textures, every command (no
//             hash of the result: ReplayOptions::hash)
//   llvmpipe  conformance::playOnCurrentContext() in bench/mesa_peer's child process
//             (llvmpipe takes its thread count per process): glTexImage of every texture
//             (deleted again after the replay), every command, glFinish. The OSMesa
//             context is made once per child, before timing — GL has no cheaper way to
//             get a fresh device — so ours pays for a Device per replay and Mesa does not.
// Traces using what GL 1.3 lacks (colour tables, pixel texture, 4D textures, the
// Direct3D-only stage ops, ...) and programmable traces with a program that has no GLSL
// twin are timed on ours only and listed as such with the reason
// conformance::oursOnlyReason() gives. A programmable trace's twins are compiled on the
// first replay in the child and kept (ours compiles its programs when retroglass is built).
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "conformance/mesa_player.h"
#include "core/error.h"
#include "harness.h"
#include "mesa_peer.h"
#include "rasterizer/trace.h"
#include "trace_replay.h"

namespace rg::bench {

void runTraceOnOurs(benchmark::State& state, const raster::Trace& trace, Path path, int threads) {
    raster::ReplayOptions options;
    options.path = path;
    options.threads = threads;
    options.hash = false;  // the llvmpipe side hashes nothing either
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        raster::ReplayResult r = raster::replayTrace(trace, options);
        benchmark::DoNotOptimize(r.framebuffer.color().data());
        // Wall-clock time, as the llvmpipe side is measured (manual time on both sides
        // also gives both the same name suffix, which the harness pairs on).
        state.SetIterationTime(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    state.SetItemsProcessed(state.iterations());
}

void runTraceOnMesa(benchmark::State& state, const std::shared_ptr<const raster::Trace>& trace,
                    int threads) {
    runMesaBenchmark(
        state, trace->width, trace->height, threads, [] {},
        [trace] { conformance::playOnCurrentContext(*trace); }, 1);
}

void registerTraceBenchmarks(const std::string& file, bool referencePath,
                             const std::vector<int>& threadCounts) {
    auto trace = std::make_shared<const raster::Trace>(raster::readTraceFile(file));
    const std::string workload = "trace:" + std::filesystem::path(file).stem().string();
    const std::string unsupported = conformance::mesaUnsupported(*trace);
    const Path path = referencePath ? Path::Reference : Path::Fast;
    for (int t : threadCounts) {
        const std::string suffix = "/threads:" + std::to_string(t);
        benchmark::RegisterBenchmark((workload + "/retroglass" + suffix).c_str(),
                                     [trace, path, t](benchmark::State& s) { runTraceOnOurs(s, *trace, path, t); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        if (!unsupported.empty()) continue;
        benchmark::RegisterBenchmark(
            (workload + "/llvmpipe" + suffix).c_str(),
            [trace, t](benchmark::State& s) { runTraceOnMesa(s, trace, t); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
    }
    if (!unsupported.empty()) noteOursOnly(workload, conformance::oursOnlyReason(*trace));
}

}  // namespace rg::bench
