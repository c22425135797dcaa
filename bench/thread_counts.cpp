#include "thread_counts.h"

#include <algorithm>
#include <thread>

#include "core/error.h"

namespace rg::bench {

std::vector<int> parseThreadCounts(const std::string& list) {
    auto refuse = [&](const std::string& why) {
        throw Error("thread counts '" + list + "': " + why +
                    " (expected a comma-separated list of counts from 1 to " +
                    std::to_string(kMaxThreadCount) + ", e.g. 1,2,4,8,16)");
    };
    if (list.empty()) refuse("empty list");
    std::vector<int> counts;
    size_t begin = 0;
    while (true) {
        const size_t end = std::min(list.find(',', begin), list.size());
        const std::string entry = list.substr(begin, end - begin);
        if (entry.empty()) refuse("empty entry at position " + std::to_string(counts.size() + 1));
        if (!std::all_of(entry.begin(), entry.end(), [](char c) { return c >= '0' && c <= '9'; }))
            refuse("'" + entry + "' is not a thread count");
        // At most 4 digits pass the bound check, so longer ones are refused before they
        // could overflow an int.
        const int n = entry.size() > 4 ? kMaxThreadCount + 1 : std::stoi(entry);
        if (n < 1 || n > kMaxThreadCount) refuse(entry + " is out of range");
        if (std::find(counts.begin(), counts.end(), n) != counts.end())
            refuse(entry + " is listed twice");
        counts.push_back(n);
        if (end == list.size()) break;
        begin = end + 1;
    }
    return counts;
}

int hardwareThreads() {
    const unsigned n = std::thread::hardware_concurrency();
    return n == 0 ? 1 : int(n);
}

std::vector<int> defaultThreadCounts(int all) {
    if (all <= 0) all = hardwareThreads();
    if (all == 1) return {1};
    return {1, all};
}

}  // namespace rg::bench
