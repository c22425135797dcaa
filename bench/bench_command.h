// The `bench` subcommand's options, shared by the full `retroglass` program
// (demos/cli/main.cpp) and the portable one (bench/portable_main.cpp), so that both take
// the same command line.
#pragma once

#include <string>

#include "harness.h"

namespace CLI {
class App;
}

namespace rg::bench {

struct BenchCommand {
    Options options;
    std::string threadList;  // `bench --threads 1,2,4` (empty: not given)
    CLI::App* subcommand = nullptr;

    // Adds `bench` and its options to `app`; `--trace` only where the build replays traces.
    void add(CLI::App& app, bool withTrace);
    // Runs the parsed command. `globalThreads`: the program's own `--threads N` before
    // `bench`, which keeps its old meaning of 1 and N when `bench --threads` lists none.
    int run(int globalThreads, bool referencePath, const char* argv0);
};

}  // namespace rg::bench
