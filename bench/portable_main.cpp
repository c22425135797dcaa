// The portable `retroglass` (RETROGLASS_PORTABLE_BENCH=ON): `retroglass bench` alone, for
// the pipeline, texture and programmable workloads against llvmpipe, built without
// raycore (Embree), OpenImageIO, the demos and the viewer so that tools/pack-bench.sh can
// carry it, with its shared libraries, to a machine with nothing installed. The command
// line is the full program's (bench_command.h), so the same commands work on both.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "bench_command.h"
#include "core/error.h"

int main(int argc, char** argv) {
    CLI::App app{"retroglass (portable bench): the pipeline, texture and programmable "
                 "workloads against Mesa llvmpipe, ratios measured in the same run"};
    app.require_subcommand(1);
    int threads = 0;
    app.add_option("--threads", threads, "as `bench --threads 1,N`")->check(CLI::Range(1, 1024));
    rg::bench::BenchCommand bench;
    bench.add(app, /*withTrace=*/false);
    CLI11_PARSE(app, argc, argv);
    try {
        return bench.run(threads, /*referencePath=*/false, argv[0]);
    } catch (const rg::Error& e) {
        std::fprintf(stderr, "retroglass: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "retroglass: unexpected error: %s\n", e.what());
        return 3;
    }
}
