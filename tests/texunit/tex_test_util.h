// Helpers shared by the texunit tests: build textures from per-texel functions.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "texunit/texture.h"

namespace rg::tex::testing {

// Uploads every level of every face of an RGBA8 texture from f(level, face, x, y, z, w).
inline std::shared_ptr<Texture> makeRgba8(
    TextureMemory& mem, TextureDesc d,
    const std::function<Rgba8(int, int, int, int, int, int)>& f) {
    d.format = TexelFormat::RGBA8;
    auto t = mem.create(d);
    for (int l = 0; l < t->levels(); ++l)
        for (int face = 0; face < t->faces(); ++face) {
            const auto& s = t->levelSize(l);
            std::vector<uint8_t> bytes;
            for (int w = 0; w < s[3]; ++w)
                for (int z = 0; z < s[2]; ++z)
                    for (int y = 0; y < s[1]; ++y)
                        for (int x = 0; x < s[0]; ++x) {
                            Rgba8 c = f(l, face, x, y, z, w);
                            bytes.insert(bytes.end(), {c.r, c.g, c.b, c.a});
                        }
            mem.upload(*t, l, face, bytes);
        }
    return t;
}

// Deterministic 32-bit hash for pseudo-random texels and states.
inline uint32_t hash32(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

struct Rng {
    uint32_t state;
    explicit Rng(uint32_t seed) : state(seed) {}
    uint32_t next() { return state = hash32(state + 0x9e3779b9U); }
    uint32_t below(uint32_t n) { return next() % n; }
    float uniform(float lo, float hi) { return lo + (hi - lo) * float(next() >> 8) / 16777216.0f; }
};

}  // namespace rg::tex::testing
