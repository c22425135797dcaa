// `retroglass bench --filter <paper>`: each reproduction's frame workloads, found through the
// one registry (demos/registry.cpp, Reproduction::benchCases). A whole paper's frame has no
// software peer; the paper's own figures (paper_fps, ...) are reported beside ours as
// counters, and docs/performance.md lists them apart from the ratio table.
#include <benchmark/benchmark.h>

#include "harness.h"
#include "reproduction.h"

namespace rg::bench {
namespace {

void runCase(benchmark::State& state, const demos::BenchCase& c, int threads, bool peer) {
    auto frame = peer ? c.setupPeer(threads) : c.setup(threads);
    std::map<std::string, double> sums;
    int64_t frames = 0;
    for (auto _ : state) {
        for (const auto& [k, v] : frame()) sums[k] += v;
        ++frames;
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["fps"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
    if (!peer)
        for (const auto& [k, v] : c.paper) state.counters[k] = v;
    for (const auto& [k, v] : sums) state.counters[k] = frames ? v / double(frames) : 0.0;
}

// Registered once `retroglass bench` has read its thread counts (harness.h).
const bool registered = addWorkloads([](const std::vector<int>& threadCounts) {
    for (const demos::Reproduction* r : demos::reproductions())
        for (const demos::BenchCase& c : r->benchCases())
            for (int t : threadCounts)
                for (bool peer : {false, true}) {
                    if (peer && !c.setupPeer) continue;
                    std::string name = c.name + "/" + (peer ? c.peer : std::string("retroglass")) +
                                       "/threads:" + std::to_string(t);
                    benchmark::RegisterBenchmark(name.c_str(), [c, t, peer](benchmark::State& s) {
                        runCase(s, c, t, peer);
                    })->Unit(benchmark::kMillisecond)->UseRealTime();
                }
});

}  // namespace
}  // namespace rg::bench
