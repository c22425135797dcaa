// The programs of the bench workloads, registered by name for traces
// (rasterizer/include/rasterizer/program_registry.h, docs/trace-format.md version 2), each
// with its GLSL twin for the Mesa peer. `retroglass` calls registerPrograms() at startup
// so that `retroglass replay` plays traces of these workloads; the golden-trace tool, the
// trace tests and the trace-reader fuzz target call it too. Always built (also without
// RETROGLASS_BENCH): a library of program registrations, not of benchmarks.
#pragma once

namespace rg::bench {

// "bench/binary_search" (QuadVP, BinarySearchQuadFP: the quad program the benchmark runs)
// and "bench/binary_search_scalar" (QuadVP, BinarySearchFP), both on QuadVertex
// (bench/binary_search_retroglass.h). Calling it again is a no-op.
void registerPrograms();

}  // namespace rg::bench
