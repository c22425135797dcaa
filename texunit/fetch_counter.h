// Internal: the texel-fetch counter shared by the threads that call shadeQuad. One
// relaxed atomic per quad and stage on a single cache line would bounce that line between
// cores on every quad; each thread adds to its own padded shard instead, and counters()
// sums the shards (a count, so the order of the additions does not matter).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

namespace rg::tex::detail {

struct FetchCounter {
    static constexpr unsigned kShards = 16;
    struct alignas(64) Shard {
        std::atomic<uint64_t> value{0};
    };
    std::array<Shard, kShards> shards;

    static unsigned threadShard() {
        static std::atomic<unsigned> next{0};
        thread_local unsigned shard = next.fetch_add(1, std::memory_order_relaxed) % kShards;
        return shard;
    }
    void add(uint64_t n) { shards[threadShard()].value.fetch_add(n, std::memory_order_relaxed); }
    uint64_t total() const {
        uint64_t t = 0;
        for (const Shard& s : shards) t += s.value.load(std::memory_order_relaxed);
        return t;
    }
    void reset() {
        for (Shard& s : shards) s.value.store(0, std::memory_order_relaxed);
    }
};

}  // namespace rg::tex::detail
