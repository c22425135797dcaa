// The thread counts `retroglass bench --threads 1,2,4,8,16` runs every workload at, ours
// and the peer's alike. Apart from the harness so that the parser is tested without
// Google Benchmark or a peer (tests/bench/test_thread_counts.cpp).
#pragma once

#include <string>
#include <vector>

namespace rg::bench {

// The most threads a count may ask for: far past any machine we run on, and small enough
// that a typo (`--threads 1,20000`) is refused instead of starting 20,000 threads.
inline constexpr int kMaxThreadCount = 1024;

// "1,2,4" → {1, 2, 4}, in the order given. Throws rg::Error, naming the list and the
// entry, for an empty list or entry (`2,,3`), anything but decimal digits (`a,b`, `-1`,
// `2.5`), 0 or more than kMaxThreadCount, and a count given twice (which would register
// two benchmarks of one name).
std::vector<int> parseThreadCounts(const std::string& list);

// The counts when `--threads` lists none: 1 and `all` (the machine's hardware threads
// when 0), once each.
std::vector<int> defaultThreadCounts(int all);

// The machine's hardware threads (std::thread::hardware_concurrency, 1 when unknown).
int hardwareThreads();

}  // namespace rg::bench
