// `impostor_secant/<impl>/threads:N` and `impostor_height/<impl>/threads:N` (issue 19): the
// glass pass of Dancsik & Minarik's chess frame — every piece through GlassFP's secant
// searches, or through GlassHeightFP's height-map binary search — on ours and as their GLSL
// twins on llvmpipe, one frame per iteration, items = the pass's fragment-program
// invocations (bench/impostor_peers_workload.h). Both sides report manual time (seconds per
// frame), so the harness pairs them by name (bench/harness.h), as tir_final_pass's do.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "harness.h"
#include "impostor_peers_mesa.h"
#include "impostor_peers_retroglass.h"
#include "impostor_peers_workload.h"
#include "mesa_peer.h"

namespace rg::bench {
namespace {

namespace ip = impostor_peers;

void runRetroglass(benchmark::State& state, ip::Exit exit, int threads) {
    const ip::Inputs& in = ip::inputs(exit);
    ip::ImpostorPeerScene scene(in, threads);
    scene.frame();  // warm-up
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        scene.frame();
        const auto t1 = std::chrono::steady_clock::now();
        state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * in.fragmentsPerFrame);
}

void runLlvmpipe(benchmark::State& state, ip::Exit exit, int threads) {
    // The inputs exist before the fork, so the child has its copy and renders nothing of
    // ours. setupGl() runs in the child; an exception must not unwind into the child's copy
    // of the benchmark runner, so it ends the child, which the parent reports.
    const ip::Inputs& in = ip::inputs(exit);
    auto setup = [&in] {
        try {
            ip::setupGl(in, ip::fragmentShader(in.exit));
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s\n", e.what());
            ::_exit(1);
        }
    };
    runMesaBenchmark(state, ip::kWidth, ip::kHeight, threads, setup, [&in] { ip::drawFrameGl(in); },
                     in.fragmentsPerFrame);
}

// Registered once `retroglass bench` has read its thread counts (harness.h).
const bool registered = addWorkloads([](const std::vector<int>& threadCounts) {
    for (ip::Exit exit : {ip::Exit::Secant, ip::Exit::Height}) {
        const std::string name = ip::workloadName(exit);
        for (int t : threadCounts) {
            benchmark::RegisterBenchmark((name + "/retroglass/threads:" + std::to_string(t)).c_str(),
                                         [exit, t](benchmark::State& s) { runRetroglass(s, exit, t); })
                ->UseManualTime()
                ->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark((name + "/llvmpipe/threads:" + std::to_string(t)).c_str(),
                                         [exit, t](benchmark::State& s) { runLlvmpipe(s, exit, t); })
                ->UseManualTime()
                ->Unit(benchmark::kMillisecond);
        }
    }
});

}  // namespace
}  // namespace rg::bench
