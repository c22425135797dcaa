// The procedural patterns. Walls, floor and ceiling of the PEM room need detail worth
// reflecting (001 §6): bricks and wood give sharp edges whose distortion in the teapot
// shows errors in an inferred environment map at a glance.
#include <cmath>

#include "raycore/texture_procedural.h"

namespace rg::ray {

glm::vec3 checkerPattern(glm::vec2 uv, float scale, glm::vec3 a, glm::vec3 b) {
    long i = long(std::floor(uv.x * scale)), j = long(std::floor(uv.y * scale));
    return ((i + j) & 1) == 0 ? a : b;
}

glm::vec3 bricksPattern(glm::vec2 uv, float scale, glm::vec3 brick, glm::vec3 mortar) {
    // One brick is 1/scale wide and half that high; odd rows shift by half a brick.
    float row = uv.y * scale * 2.0f;
    float rowIndex = std::floor(row);
    float col = uv.x * scale + (long(rowIndex) & 1 ? 0.5f : 0.0f);
    float fy = row - rowIndex, fx = col - std::floor(col);
    const float mortarHalf = 0.04f;  // of a row height: 8% mortar lines
    if (fy < mortarHalf || fy > 1.0f - mortarHalf || fx < mortarHalf * 0.5f ||
        fx > 1.0f - mortarHalf * 0.5f)
        return mortar;
    // Per-brick shade variation from the brick's integer coordinates (a fixed hash, so the
    // pattern is deterministic).
    uint32_t h = uint32_t(long(rowIndex)) * 73856093u ^ uint32_t(long(std::floor(col))) * 19349663u;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    float shade = 0.8f + 0.2f * float(h & 1023u) / 1023.0f;
    return brick * shade;
}

glm::vec3 woodRingsPattern(glm::vec2 uv, float scale, glm::vec3 light, glm::vec3 dark) {
    glm::vec2 d = uv - glm::vec2(0.5f);
    float r = std::sqrt(d.x * d.x + d.y * d.y) * scale;
    float angle = std::atan2(d.y, d.x);
    r += 0.15f * std::sin(angle * 5.0f) + 0.1f * std::sin(uv.x * 17.0f);
    float f = r - std::floor(r);
    float t = std::pow(0.5f + 0.5f * std::cos(f * 6.2831853f), 3.0f);
    return glm::mix(light, dark, t);
}

glm::vec3 gradientPattern(glm::vec2 uv, glm::vec3 a, glm::vec3 b) {
    float t = uv.y < 0.0f ? 0.0f : (uv.y > 1.0f ? 1.0f : uv.y);
    return glm::mix(a, b, t);
}

}  // namespace rg::ray
