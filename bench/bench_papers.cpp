// `retroglass bench --filter <paper>`: each reproduction's frame workloads, found through the
// one registry (demos/registry.cpp, Reproduction::benchCases). A whole paper's frame has no
// software peer; the paper's own figures (paper_fps, ...) are reported beside ours as
// counters, and docs/performance.md lists them apart from the ratio table.
//
// A case that captures its frame (BenchCase::capture) also gets <name>_passes: the replay
// of those device commands on ours and on llvmpipe (trace_replay.h), captured once, at the
// first of its benchmarks that runs.
#include <benchmark/benchmark.h>

#include <memory>
#include <mutex>

#include "conformance/mesa_player.h"
#include "harness.h"
#include "rasterizer/trace.h"
#include "reproduction.h"
#include "trace_replay.h"

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

// The captured passes of one case, made when first asked for (a capture builds the case's
// fixture, which only a run that selects these benchmarks should pay for).
struct CapturedPasses {
    std::function<std::vector<uint8_t>()> capture;
    std::once_flag once;
    std::shared_ptr<const raster::Trace> trace;
    std::string mesaUnsupported;
    const raster::Trace& get() {
        std::call_once(once, [this] {
            trace = std::make_shared<const raster::Trace>(raster::readTrace(capture()));
            mesaUnsupported = conformance::mesaUnsupported(*trace);
        });
        return *trace;
    }
};

void registerPasses(const demos::BenchCase& c, const std::vector<int>& threadCounts) {
    auto passes = std::make_shared<CapturedPasses>();
    passes->capture = c.capture;
    for (int t : threadCounts) {
        const std::string suffix = "/threads:" + std::to_string(t);
        benchmark::RegisterBenchmark((c.name + "_passes/retroglass" + suffix).c_str(),
                                     [passes, t](benchmark::State& s) {
                                         runTraceOnOurs(s, passes->get(), Path::Fast, t);
                                     })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((c.name + "_passes/llvmpipe" + suffix).c_str(),
                                     [passes, t](benchmark::State& s) {
                                         passes->get();
                                         if (!passes->mesaUnsupported.empty()) {
                                             s.SkipWithError(("Mesa lacks " + passes->mesaUnsupported).c_str());
                                             return;
                                         }
                                         runTraceOnMesa(s, passes->trace, t);
                                     })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
    }
}

// Registered once `retroglass bench` has read its thread counts (harness.h).
const bool registered = addWorkloads([](const std::vector<int>& threadCounts) {
    for (const demos::Reproduction* r : demos::reproductions())
        for (const demos::BenchCase& c : r->benchCases()) {
            if (c.capture) registerPasses(c, threadCounts);
            for (int t : threadCounts)
                for (bool peer : {false, true}) {
                    if (peer && !c.setupPeer) continue;
                    std::string name = c.name + "/" + (peer ? c.peer : std::string("retroglass")) +
                                       "/threads:" + std::to_string(t);
                    benchmark::RegisterBenchmark(name.c_str(), [c, t, peer](benchmark::State& s) {
                        runCase(s, c, t, peer);
                    })->Unit(benchmark::kMillisecond)->UseRealTime();
                }
        }
});

}  // namespace
}  // namespace rg::bench
