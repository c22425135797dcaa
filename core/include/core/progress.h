// Progress of long work: a bar with an ETA on a terminal, silence when stderr is not one
// (CI logs, pipes). Thread-safe: workers call advance() from any thread.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace rg {

class Progress {
  public:
    Progress(std::string label, uint64_t total);
    ~Progress();  // finishes the line
    void advance(uint64_t n = 1);
    void finish();
    static bool enabledOnThisTerminal();

  private:
    void draw(uint64_t done, bool final);
    std::string label_;
    uint64_t total_;
    std::atomic<uint64_t> done_{0};
    bool enabled_;
    bool finished_ = false;
    std::mutex mutex_;
    std::chrono::steady_clock::time_point start_, lastDraw_;
};

}  // namespace rg
