// Helpers shared by the rasterizer tests: devices, vertices, frame hashes.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/profile.h"
#include "rasterizer/device.h"
#include "rasterizer/trace.h"  // sha256Hex: the replay hash, one implementation

namespace rg::testing {

using raster::sha256Hex;

// Seeded draws for the randomized tests (std::mt19937_64; the same cases on every run).
struct Rng {
    std::mt19937_64 g;
    explicit Rng(uint64_t seed) : g(seed) {}
    int i(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(g); }
    int64_t i64(int64_t lo, int64_t hi) { return std::uniform_int_distribution<int64_t>(lo, hi)(g); }
    float f(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(g); }
    bool p(double prob) { return std::bernoulli_distribution(prob)(g); }
    uint8_t byte() { return uint8_t(i(0, 255)); }
};

inline raster::Vertex tv(float x, float y, float z = 0.5f, float rhw = 1.0f,
                         Rgba8 diffuse = {255, 255, 255, 255}, Rgba8 specular = {0, 0, 0, 0}) {
    raster::Vertex v;
    v.position = {x, y, z, rhw};
    v.diffuse = diffuse;
    v.specular = specular;
    return v;
}

// A state with nothing enabled that could hide a pixel: no culling, no depth test.
inline raster::PipelineState plainState() {
    raster::PipelineState s;
    s.cull = raster::CullMode::None;
    s.depthTest = 0;
    s.depthWrite = 0;
    return s;
}

inline std::string frameHash(const raster::Framebuffer& fb) {
    std::string h = sha256Hex(fb.color().data(), fb.color().size_bytes());
    if (!fb.depth().empty()) h += "/" + sha256Hex(fb.depth().data(), fb.depth().size_bytes());
    return h;
}

inline int countIf(const raster::Framebuffer& fb, auto pred) {
    int n = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) n += pred(fb.pixel(x, y)) ? 1 : 0;
    return n;
}

inline const Profile& geforce256() { return profile(ProfileId::GeForce256); }

}  // namespace rg::testing
