// `retroglass bench`: Google Benchmark underneath, plus the ratio to the peer measured in
// the same run, which is the figure we steer by (DEVELOPERS.md, "Fast").
//
// Naming convention every benchmark follows, so the harness can pair them:
//     <workload>/<implementation>/<parameters...>
// where <implementation> is `retroglass` for ours and the peer's name otherwise
// (`llvmpipe` for Mesa's OpenGL through OSMesa, `embree` for a bare Embree loop).
// Each benchmark reports state.SetItemsProcessed() in the workload's unit (fragments,
// triangles, rays); the ratio is ours/peer in items per second.
#pragma once

#include <string>

namespace rg::bench {

struct Options {
    std::string filter;    // regular expression over benchmark names (empty: all)
    std::string jsonPath;  // Google Benchmark's JSON output plus our "ratios" (empty: none)
    double minTime = 0.0;  // seconds per benchmark (0: Google Benchmark's default)
    int threads = 0;       // "all threads" for the benchmarks (0: all cores)
};

// The thread counts benchmarks run at: 1 and `all` (deduplicated).
int allThreads();

int run(const Options& options, const char* argv0);

}  // namespace rg::bench
