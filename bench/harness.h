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
#include <vector>

namespace rg::bench {

struct Options {
    std::string filter;    // regular expression over benchmark names (empty: all)
    std::string jsonPath;  // Google Benchmark's JSON output plus our "ratios" (empty: none)
    std::string plotPath;  // the ratio bars and the scaling panels as SVG (empty: none)
    double minTime = 0.0;  // seconds per benchmark (0: Google Benchmark's default)
    int repetitions = 1;   // runs of each benchmark, interleaved at random; ratios of medians
    // Every workload runs at each of these counts, ours and the peer's alike (empty: 1 and
    // all cores; thread_counts.h parses `--threads 1,2,4`).
    std::vector<int> threads;
    std::string trace;     // a captured trace: time its replay on ours and on Mesa instead
    bool referencePath = false;  // ours on the reference path (the trace benchmark only)
};

// Each bench_*.cpp hands over a function that registers its workloads at the given thread
// counts, as `const bool registered = addWorkloads(...)`. They are called by run() once the
// command line is read: the counts come from `--threads`, which static initialisation, when
// the files' initialisers run, comes too early to see. Returns true.
using RegisterWorkloads = void (*)(const std::vector<int>& threadCounts);
bool addWorkloads(RegisterWorkloads registerWorkloads);

int run(const Options& options, const char* argv0);

// `retroglass bench --trace FILE` (bench_trace.cpp): registers the replay of FILE on ours
// and on llvmpipe, named trace:<file stem>/<implementation>/threads:N for each count, one
// item per replay. Throws rg::Error when the file is not a readable trace.
void registerTraceBenchmarks(const std::string& file, bool referencePath,
                             const std::vector<int>& threadCounts);

// A workload only ours can run (e.g. a trace using what Mesa lacks): printed under the
// ratio table and kept in the JSON output instead of a ratio.
void noteOursOnly(const std::string& workload, const std::string& why);

}  // namespace rg::bench
