#include "bench_command.h"

#include <CLI/CLI.hpp>

#include "core/error.h"
#include "thread_counts.h"

namespace rg::bench {

void BenchCommand::add(CLI::App& app, bool withTrace) {
    subcommand = app.add_subcommand(
        "bench", "benchmarks against the peers measured in the same run, with ratios");
    subcommand->add_option("--filter", options.filter, "regular expression over benchmark names");
    subcommand->add_option("--threads", threadList,
                           "thread counts to run every workload at, ours and the peer's "
                           "alike, e.g. 1,2,4,8,16 (default: 1 and all cores)")
        ->check(CLI::Validator(
            [](std::string& list) {
                // The parser's own message, at parse time, before any benchmark starts.
                try {
                    parseThreadCounts(list);
                    return std::string();
                } catch (const Error& e) {
                    return std::string(e.what());
                }
            },
            "LIST"));
    subcommand->add_option("--json", options.jsonPath, "write throughputs and ratios as JSON");
    subcommand->add_option("--plot", options.plotPath,
                           "write an SVG: the ratios as bars, each with its goal, and "
                           "throughput against threads for both sides, a panel per workload");
    subcommand->add_option("--min-time", options.minTime, "seconds per benchmark");
    subcommand->add_option("--repetitions", options.repetitions,
                           "runs of each benchmark, ours and the peers interleaved at random; "
                           "ratios of the medians (for a noisy machine)")
        ->check(CLI::PositiveNumber);
    if (withTrace)
        subcommand->add_option(
            "--trace", options.trace,
            "time the replay of a captured trace on ours and on Mesa llvmpipe (ours only "
            "where Mesa lacks a feature) instead of the built-in workloads");
    subcommand->fallthrough();  // `bench --trace F --path reference`: global options after it
}

int BenchCommand::run(int globalThreads, bool referencePath, const char* argv0) {
    if (!threadList.empty()) options.threads = parseThreadCounts(threadList);
    else if (globalThreads > 0) options.threads = defaultThreadCounts(globalThreads);
    options.referencePath = referencePath;
    return bench::run(options, argv0);
}

}  // namespace rg::bench
