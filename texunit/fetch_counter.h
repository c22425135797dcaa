// Internal: the texel-fetch counter shared by the threads that call shadeQuad. One
// relaxed atomic per quad and stage on a single cache line would bounce that line between
// cores on every quad; each thread adds to its own padded shard instead, and counters()
// sums the shards (a count, so the order of the additions does not matter).
//
// A thread that owns its shard index outright (claimed from a process-wide bitmap for the
// thread's lifetime, so no other live thread writes that shard of any counter) adds with
// a plain load and store: no lock prefix, which on x86 is a full barrier that drains the
// store buffer once per quad. Ownership passes between threads through the bitmap's
// acquire/release, so a later owner continues from the earlier one's value. Threads
// beyond kShards share the remaining shards with an atomic add, as before. The counts are
// exact either way; readers (counters(), after the draw's threads have joined) see every
// add.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>

namespace rg::tex::detail {

struct FetchCounter {
    static constexpr unsigned kShards = 64;
    struct alignas(64) Shard {
        std::atomic<uint64_t> value{0};
    };
    std::array<Shard, kShards> shards;

    // The calling thread's shard: i < kShards owned by it alone, kShards + i shared.
    static unsigned threadSlot() {
        struct Claim {
            unsigned slot;
            Claim() {
                uint64_t used = owners().load(std::memory_order_relaxed);
                for (;;) {
                    if (~used == 0) {  // all owned: share one, atomically
                        static std::atomic<unsigned> next{0};
                        slot = kShards +
                               next.fetch_add(1, std::memory_order_relaxed) % kShards;
                        return;
                    }
                    const unsigned i = unsigned(__builtin_ctzll(~used));
                    if (owners().compare_exchange_weak(used, used | (uint64_t(1) << i),
                                                       std::memory_order_acquire,
                                                       std::memory_order_relaxed)) {
                        slot = i;
                        return;
                    }
                }
            }
            ~Claim() {
                if (slot < kShards)
                    owners().fetch_and(~(uint64_t(1) << slot), std::memory_order_release);
            }
        };
        static_assert(kShards == 64, "one bit of the owners bitmap per shard");
        thread_local Claim claim;
        return claim.slot;
    }
    void add(uint64_t n) {
        const unsigned s = threadSlot();
        if (s < kShards) {
            std::atomic<uint64_t>& v = shards[s].value;
            v.store(v.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
        } else {
            shards[s - kShards].value.fetch_add(n, std::memory_order_relaxed);
        }
    }
    uint64_t total() const {
        uint64_t t = 0;
        for (const Shard& s : shards) t += s.value.load(std::memory_order_relaxed);
        return t;
    }
    void reset() {
        for (Shard& s : shards) s.value.store(0, std::memory_order_relaxed);
    }

  private:
    static std::atomic<uint64_t>& owners() {
        static std::atomic<uint64_t> bits{0};
        return bits;
    }
};

}  // namespace rg::tex::detail
