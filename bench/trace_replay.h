// One captured trace (docs/trace-format.md) replayed per iteration, on ours and on Mesa
// llvmpipe: `retroglass bench --trace FILE` (bench_trace.cpp) and the passes a reproduction's
// frame captures (BenchCase::capture, bench_papers.cpp). What one replay includes is said
// at the top of bench_trace.cpp.
#pragma once

#include <memory>

#include "core/path.h"

namespace benchmark {
class State;
}
namespace rg::raster {
struct Trace;
}

namespace rg::bench {

// Ours: a fresh Device, its textures and every command, wall-clock manual time.
void runTraceOnOurs(benchmark::State& state, const raster::Trace& trace, Path path, int threads);
// llvmpipe in the peer child (mesa_peer.h), manual time; the caller has checked
// conformance::mesaUnsupported(trace).
void runTraceOnMesa(benchmark::State& state, const std::shared_ptr<const raster::Trace>& trace,
                    int threads);

}  // namespace rg::bench
