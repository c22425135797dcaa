// Counters: rays cast by kind and time spent, summed over a render. Tracers count into a
// per-task RayCounts (plain integers, no sharing) and add it to the shared RenderCounters
// once per image row, so counting costs nothing per ray and totals do not depend on the
// thread schedule.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>

namespace rg::ray {

enum class RayKind : uint32_t { Primary, Reflection, Refraction, Shadow, Continuation, Count };
const char* rayKindName(RayKind k);

struct RayCounts {
    std::array<uint64_t, size_t(RayKind::Count)> n{};
    void add(RayKind k, uint64_t c = 1) { n[size_t(k)] += c; }
    uint64_t total() const;
};

class RenderCounters {
  public:
    void add(const RayCounts& c);
    uint64_t count(RayKind k) const { return n_[size_t(k)].load(); }
    uint64_t total() const;
    double seconds = 0.0;  // wall time of the render that filled it
    std::string summary() const;  // "primary 1234, reflection ..., 2.1 Mrays/s"

  private:
    std::array<std::atomic<uint64_t>, size_t(RayKind::Count)> n_{};
};

}  // namespace rg::ray
