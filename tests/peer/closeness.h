// How close llvmpipe's frame of a GLSL twin is to ours (tests/peer/test_tir_final_pass_mesa.cpp,
// test_impostor_peers_mesa.cpp): where both sides cover a pixel, how many of its RGB
// channels lie within `steps` 8-bit steps, their mean and largest difference. A side covers
// a pixel where its alpha is 255: the programs write alpha 1 over the clear's 0.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace rg::bench::peer_test {

struct Closeness {
    int steps = 0;
    int oursCovered = 0, mesaCovered = 0, both = 0;
    int within = 0;          // of `both`: every channel within `steps`
    double meanError = 0.0;  // of `both`: mean over pixels and RGB channels, 8-bit steps
    int maxError = 0;
};

inline Closeness compareCovered(const std::vector<uint8_t>& ours, const std::vector<uint8_t>& mesa, int steps) {
    Closeness c;
    c.steps = steps;
    double sum = 0.0;
    for (size_t i = 0; i < ours.size(); i += 4) {
        const bool o = ours[i + 3] == 255, m = mesa[i + 3] == 255;
        c.oursCovered += o;
        c.mesaCovered += m;
        if (!(o && m)) continue;
        ++c.both;
        int worst = 0;
        for (size_t k = 0; k < 3; ++k) {
            const int d = std::abs(int(ours[i + k]) - int(mesa[i + k]));
            worst = std::max(worst, d);
            sum += d;
        }
        c.maxError = std::max(c.maxError, worst);
        c.within += worst <= steps;
    }
    c.meanError = c.both ? sum / (3.0 * c.both) : 0.0;
    return c;
}

// One line for a failure message; `pixels` names what is covered ("glass pixels").
inline std::string describe(const Closeness& c, const char* pixels) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "ours %d %s, llvmpipe %d, both %d; within %d steps: %d (%.2f %%); mean error %.3f steps, largest %d",
                  c.oursCovered, pixels, c.mesaCovered, c.both, c.steps, c.within,
                  c.both ? 100.0 * c.within / c.both : 0.0, c.meanError, c.maxError);
    return buf;
}

}  // namespace rg::bench::peer_test
