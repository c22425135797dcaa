// `binary_search/llvmpipe/threads:N`: the llvmpipe side of the binary_search workload
// (bench/binary_search_workload.h, issue 4 item 6), one frame per iteration in a
// bench/mesa_peer.h child with N llvmpipe threads, items = fragments. The retroglass side
// registers `binary_search/retroglass/threads:N` with UseManualTime() so the harness
// pairs the two (bench/harness.h).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "binary_search_mesa.h"
#include "binary_search_workload.h"
#include "harness.h"
#include "mesa_peer.h"

namespace rg::bench {
namespace {

void runLlvmpipe(benchmark::State& state, int threads) {
    // setupGl() runs in the peer's child; an exception must not unwind into the child's
    // copy of the benchmark runner, so it ends the child, which the parent reports.
    auto setup = [] {
        try {
            binary_search::setupGl();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "%s\n", e.what());
            ::_exit(1);
        }
    };
    runMesaBenchmark(state, binary_search::kWidth, binary_search::kHeight, threads, setup,
                     binary_search::drawFrameGl, binary_search::kFragmentsPerFrame);
}

// Registered once `retroglass bench` has read its thread counts (harness.h).
const bool registered = addWorkloads([](const std::vector<int>& threadCounts) {
    for (int t : threadCounts)
        benchmark::RegisterBenchmark(
            ("binary_search/llvmpipe/threads:" + std::to_string(t)).c_str(),
            [t](benchmark::State& s) { runLlvmpipe(s, t); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
});

}  // namespace
}  // namespace rg::bench
