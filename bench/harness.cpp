#include "harness.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace rg::bench {

namespace {

int gAllThreads = 0;

struct OursOnly {
    std::string workload, why;
};
std::vector<OursOnly> gOursOnly;

const char* const kPeers[] = {"llvmpipe", "embree"};

// Replaces the second '/'-separated field of `name` by `impl`; empty when there is none.
std::string withImplementation(const std::string& name, const std::string& impl) {
    size_t a = name.find('/');
    if (a == std::string::npos) return {};
    size_t b = name.find('/', a + 1);
    return name.substr(0, a + 1) + impl + (b == std::string::npos ? "" : name.substr(b));
}

std::string implementationOf(const std::string& name) {
    size_t a = name.find('/');
    if (a == std::string::npos) return {};
    size_t b = name.find('/', a + 1);
    return name.substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1);
}

// Console output as usual, and a copy of each run's throughput for the ratio table: every
// repetition's, of which median() takes the middle.
class RatioReporter : public benchmark::ConsoleReporter {
  public:
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            if (run.error_occurred || run.run_type != Run::RT_Iteration) continue;
            auto it = run.counters.find("items_per_second");
            if (it != run.counters.end())
                samples[run.benchmark_name()].push_back(double(it->second.value));
        }
        ConsoleReporter::ReportRuns(runs);
    }
    std::map<std::string, std::vector<double>> samples;

    // The median throughput of each benchmark (the mean of the middle two for an even
    // count): one slow repetition, a burst of load on a shared machine, moves it little.
    std::map<std::string, double> medians() const {
        std::map<std::string, double> out;
        for (auto [name, v] : samples) {
            std::sort(v.begin(), v.end());
            const size_t n = v.size();
            out[name] = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
        }
        return out;
    }
};

}  // namespace

int allThreads() {
    if (gAllThreads > 0) return gAllThreads;
    unsigned n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : int(n);
}

void noteOursOnly(const std::string& workload, const std::string& why) {
    gOursOnly.push_back({workload, why});
}

int run(const Options& options, const char* argv0) {
    if (options.threads > 0) gAllThreads = options.threads;
    std::string filter = options.filter;
    if (!options.trace.empty()) {
        registerTraceBenchmarks(options.trace, options.referencePath);
        // The built-in workloads are registered too (at start-up); --trace runs only the
        // trace's unless a filter says otherwise.
        if (filter.empty()) filter = "^trace:";
    }
    std::vector<std::string> args = {argv0};
    if (!filter.empty()) args.push_back("--benchmark_filter=" + filter);
    if (options.minTime > 0)
        args.push_back("--benchmark_min_time=" + std::to_string(options.minTime));
    if (options.repetitions < 1)
        throw Error("bench: --repetitions must be at least 1 (got " +
                    std::to_string(options.repetitions) + ")");
    if (options.repetitions > 1) {
        // Ours and the peer run in a random order, repetition by repetition, so a stretch
        // of load on the machine falls on both sides rather than on whichever ran then.
        args.push_back("--benchmark_repetitions=" + std::to_string(options.repetitions));
        args.push_back("--benchmark_enable_random_interleaving=true");
    }
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    int argc = int(argv.size());
    benchmark::Initialize(&argc, argv.data());

    RatioReporter reporter;
    size_t count = benchmark::RunSpecifiedBenchmarks(&reporter);
    if (count == 0) {
        std::fprintf(stderr, "retroglass bench: no benchmark matches the filter '%s'\n",
                     filter.c_str());
        return 1;
    }

    // Ratio table: ours over each peer run in the same process, medians over repetitions.
    const std::map<std::string, double> throughput = reporter.medians();
    nlohmann::json ratios = nlohmann::json::array();
    std::printf("\n%-60s %14s %14s %8s\n", "workload (ours vs peer)", "ours items/s",
                "peer items/s", "ratio");
    for (const auto& [name, ours] : throughput) {
        if (implementationOf(name) != "retroglass") continue;
        for (const char* peer : kPeers) {
            auto it = throughput.find(withImplementation(name, peer));
            if (it == throughput.end() || it->second <= 0) continue;
            double ratio = ours / it->second;
            std::printf("%-60s %14.4g %14.4g %8.2f\n", (name + " vs " + peer).c_str(), ours,
                        it->second, ratio);
            ratios.push_back({{"benchmark", name},
                              {"peer", peer},
                              {"ours_items_per_second", ours},
                              {"peer_items_per_second", it->second},
                              {"ratio", ratio}});
        }
    }
    nlohmann::json oursOnly = nlohmann::json::array();
    for (const OursOnly& o : gOursOnly) {
        std::printf("%-60s ours only: %s\n", o.workload.c_str(), o.why.c_str());
        oursOnly.push_back({{"workload", o.workload}, {"why", o.why}});
    }
    if (!options.jsonPath.empty()) {
        nlohmann::json out;
        out["throughput_items_per_second"] = throughput;
        out["repetitions"] = options.repetitions;
        out["samples_items_per_second"] = reporter.samples;  // each repetition's, in run order
        out["ratios"] = ratios;
        out["ours_only"] = oursOnly;
        std::ofstream f(options.jsonPath);
        if (!f) {
            std::fprintf(stderr, "retroglass bench: cannot write %s\n", options.jsonPath.c_str());
            return 1;
        }
        f << out.dump(2) << "\n";
    }
    benchmark::Shutdown();
    return 0;
}

}  // namespace rg::bench
