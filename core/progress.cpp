#include "core/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace rg {

bool Progress::enabledOnThisTerminal() { return isatty(fileno(stderr)) != 0; }

Progress::Progress(std::string label, uint64_t total)
    : label_(std::move(label)),
      total_(total == 0 ? 1 : total),
      enabled_(enabledOnThisTerminal()),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_) {}

Progress::~Progress() { finish(); }

void Progress::advance(uint64_t n) {
    uint64_t done = done_.fetch_add(n) + n;
    if (!enabled_) return;
    auto now = std::chrono::steady_clock::now();
    std::lock_guard lock(mutex_);
    if (now - lastDraw_ < std::chrono::milliseconds(100) && done < total_) return;
    lastDraw_ = now;
    draw(done, false);
}

void Progress::finish() {
    std::lock_guard lock(mutex_);
    if (finished_) return;
    finished_ = true;
    if (enabled_) {
        draw(done_.load(), true);
        std::fputc('\n', stderr);
    }
}

void Progress::draw(uint64_t done, bool final) {
    double fraction = std::min(1.0, double(done) / double(total_));
    double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    double eta = fraction > 0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    constexpr int kWidth = 30;
    int filled = int(fraction * kWidth);
    std::string bar(size_t(filled), '#');
    bar.append(size_t(kWidth - filled), '.');
    std::fprintf(stderr, "\r%s [%s] %llu/%llu  %5.1fs  %s %5.1fs ", label_.c_str(), bar.c_str(),
                 (unsigned long long)std::min(done, total_), (unsigned long long)total_,
                 elapsed, final ? "done" : "ETA", final ? elapsed : eta);
    std::fflush(stderr);
}

}  // namespace rg
