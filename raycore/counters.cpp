// Ray counters.
#include "raycore/counters.h"

#include <cstdio>

namespace rg::ray {

const char* rayKindName(RayKind k) {
    switch (k) {
        case RayKind::Primary: return "primary";
        case RayKind::Reflection: return "reflection";
        case RayKind::Refraction: return "refraction";
        case RayKind::Shadow: return "shadow";
        case RayKind::Continuation: return "continuation";
        case RayKind::Count: break;
    }
    return "?";
}

uint64_t RayCounts::total() const {
    uint64_t t = 0;
    for (uint64_t v : n) t += v;
    return t;
}

void RenderCounters::add(const RayCounts& c) {
    for (size_t i = 0; i < c.n.size(); ++i) n_[i].fetch_add(c.n[i], std::memory_order_relaxed);
}

uint64_t RenderCounters::total() const {
    uint64_t t = 0;
    for (const auto& v : n_) t += v.load();
    return t;
}

std::string RenderCounters::summary() const {
    std::string s;
    char buf[96];
    for (size_t i = 0; i < n_.size(); ++i) {
        std::snprintf(buf, sizeof buf, "%s%s %llu", i ? ", " : "", rayKindName(RayKind(i)),
                      (unsigned long long)n_[i].load());
        s += buf;
    }
    std::snprintf(buf, sizeof buf, "; %.3f s, %.2f Mrays/s", seconds,
                  seconds > 0 ? double(total()) / seconds * 1e-6 : 0.0);
    return s + buf;
}

}  // namespace rg::ray
