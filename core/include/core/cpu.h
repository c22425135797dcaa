// Which of our run-time-selected kernels this process uses.
#pragma once

#include <cstdlib>

namespace rg {

// True when the CPU has AVX2 and RETROGLASS_NO_AVX2 is not set (any value). Every AVX2
// kernel (rasterizer spans, texture filters, programmable quads, raycore's surfaces, pem's
// inference products) sits beside an SSE2 or plain twin that gives the same bits; the
// variable selects the twins on an AVX2 machine, so tests and users can hold one to the
// other end to end. Read once per process.
inline bool avx2Enabled() {
    static const bool has = __builtin_cpu_supports("avx2") && !std::getenv("RETROGLASS_NO_AVX2");
    return has;
}

}  // namespace rg
