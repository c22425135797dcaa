// `tir_final_pass/<impl>/threads:N` (issue 20): the final pass of Davis & Wyman 2007 —
// the refractor through TirFP's search — on ours and as its GLSL twin on llvmpipe, one
// frame per iteration, items = the pass's fragment-program invocations
// (bench/tir_final_pass_workload.h). Both sides report manual time (seconds per frame), so
// the harness pairs them by name (bench/harness.h), as binary_search's do.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "harness.h"
#include "mesa_peer.h"
#include "tir_final_pass_mesa.h"
#include "tir_final_pass_retroglass.h"
#include "tir_final_pass_workload.h"

namespace rg::bench {
namespace {

namespace tfp = tir_final_pass;

void runRetroglass(benchmark::State& state, int threads) {
    const tfp::Inputs& in = tfp::inputs();
    tfp::TirFinalPassScene scene(in, threads);
    scene.frame();  // warm-up
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        scene.frame();
        const auto t1 = std::chrono::steady_clock::now();
        state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * in.fragmentsPerFrame);
}

void runLlvmpipe(benchmark::State& state, int threads) {
    // The inputs exist before the fork, so the child has its copy and renders nothing of
    // ours. setupGl() runs in the child; an exception must not unwind into the child's copy
    // of the benchmark runner, so it ends the child, which the parent reports.
    const tfp::Inputs& in = tfp::inputs();
    auto setup = [&in] {
        try {
            tfp::setupGl(in);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s\n", e.what());
            ::_exit(1);
        }
    };
    runMesaBenchmark(state, tfp::kWidth, tfp::kHeight, threads, setup, [&in] { tfp::drawFrameGl(in); },
                     in.fragmentsPerFrame);
}

const bool registered = [] {
    std::vector<int> threadCounts = {1};
    if (allThreads() > 1) threadCounts.push_back(allThreads());
    for (int t : threadCounts) {
        benchmark::RegisterBenchmark(("tir_final_pass/retroglass/threads:" + std::to_string(t)).c_str(),
                                     [t](benchmark::State& s) { runRetroglass(s, t); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("tir_final_pass/llvmpipe/threads:" + std::to_string(t)).c_str(),
                                     [t](benchmark::State& s) { runLlvmpipe(s, t); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
    }
    return true;
}();

}  // namespace
}  // namespace rg::bench
