// The demo interface's helpers (demo.h): parameters, the orbit rig, the inspector's images.
#include "demo.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace rg::viewer {

Param& findParam(std::vector<Param>& params, const std::string& name) {
    for (Param& p : params)
        if (p.name == name) return p;
    throw Error("unknown parameter '" + name + "'");
}

double paramValue(const std::vector<Param>& params, const std::string& name) {
    for (const Param& p : params)
        if (p.name == name) return p.value;
    throw Error("unknown parameter '" + name + "'");
}

OrbitRig orbitAround(const ray::Camera& camera, float minFactor, float maxFactor) {
    OrbitRig r;
    r.start = camera;
    r.start.name = "start";
    const float d = glm::length(r.start.eye - r.start.target);
    r.minDistance = minFactor * d;
    r.maxDistance = maxFactor * d;
    return r;
}

std::vector<Rgba8> displayTarget(const TargetImage& t, int width, int height, std::string* range) {
    if (range) range->clear();
    std::vector<Rgba8> out(size_t(width) * size_t(height));
    if (t.width <= 0 || t.height <= 0 || t.values.size() != size_t(t.width) * size_t(t.height)) return out;
    // The finite range of what is shown (Float: every channel of RGB; Depth: x below 1, the
    // cleared far plane shown as white apart).
    float lo = 1e30f, hi = -1e30f;
    if (t.kind == TargetImage::Kind::Float || t.kind == TargetImage::Kind::Depth)
        for (const glm::vec4& v : t.values)
            for (int c = 0; c < (t.kind == TargetImage::Kind::Float ? 3 : 1); ++c)
                if (std::isfinite(v[c]) && !(t.kind == TargetImage::Kind::Depth && v[c] >= 1.0f))
                    lo = std::min(lo, v[c]), hi = std::max(hi, v[c]);
    if (lo > hi) lo = 0.0f, hi = 1.0f;
    const float scale = hi > lo ? 1.0f / (hi - lo) : 1.0f;
    if (range && (t.kind == TargetImage::Kind::Float || t.kind == TargetImage::Kind::Depth)) {
        char b[96];
        std::snprintf(b, sizeof b, "%g … %g", double(lo), double(hi));
        *range = b;
    }
    auto byte = [](float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const int tx = std::min(t.width - 1, x * t.width / width), ty = std::min(t.height - 1, y * t.height / height);
            const glm::vec4 v = t.values[size_t(ty) * size_t(t.width) + size_t(tx)];
            glm::vec3 c(0.0f);
            switch (t.kind) {
                case TargetImage::Kind::Color8: c = glm::vec3(v); break;
                case TargetImage::Kind::Float: c = (glm::vec3(v) - lo) * scale; break;
                case TargetImage::Kind::Depth: c = glm::vec3(v.x >= 1.0f ? 1.0f : (v.x - lo) * scale); break;
                case TargetImage::Kind::Normal: {
                    const glm::vec3 n(v);
                    c = (n.x == 0 && n.y == 0 && n.z == 0) ? glm::vec3(0.0f) : 0.5f + 0.5f * n;
                    break;
                }
            }
            out[size_t(y) * size_t(width) + size_t(x)] = {byte(c.x), byte(c.y), byte(c.z), 255};
        }
    return out;
}

}  // namespace rg::viewer
