// `binary_search/retroglass/threads:N`: the retroglass side of the binary_search workload
// (bench/binary_search_workload.h, issue 4 item 6) — the search as a geforce8800 fragment
// program on the programmable device, one frame per iteration, items = fragments. The
// llvmpipe side is bench/bench_binary_search_mesa.cpp; the harness pairs them by name.
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>
#include <vector>

#include "binary_search_retroglass.h"
#include "harness.h"

namespace rg::bench {
namespace {

using binary_search::BinarySearchScene;
namespace bs = binary_search;

void runRetroglass(benchmark::State& state, int threads) {
    BinarySearchScene scene(threads);
    scene.frame();  // warm-up
    for (auto _ : state) {
        const auto t0 = std::chrono::steady_clock::now();
        scene.frame();
        const auto t1 = std::chrono::steady_clock::now();
        state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * bs::kFragmentsPerFrame);
    state.counters["fetches_per_fragment"] = scene.device.counters().meanFetchesPerFragment();
}

// Registered once `retroglass bench` has read its thread counts (harness.h).
const bool registered = addWorkloads([](const std::vector<int>& threadCounts) {
    for (int t : threadCounts)
        benchmark::RegisterBenchmark(("binary_search/retroglass/threads:" + std::to_string(t)).c_str(),
                                     [t](benchmark::State& s) { runRetroglass(s, t); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
});

}  // namespace
}  // namespace rg::bench
