// Helpers shared by the rasterizer tests: devices, vertices, frame hashes.
#pragma once

#include <string>
#include <vector>

#include "core/profile.h"
#include "rasterizer/device.h"
#include "rasterizer/trace.h"  // sha256Hex: the replay hash, one implementation

namespace rg::testing {

using raster::sha256Hex;

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
