// Dual-paraboloid maps (docs/hardware.md, "Paraboloid mapping"; Heidrich & Seidel 1998).
#include <cmath>

#include "texunit/paraboloid_mapping.h"

namespace rg::tex {

ParaboloidSide paraboloidSide(const glm::vec3& v) {
    return v.z >= 0.0f ? ParaboloidSide::Front : ParaboloidSide::Back;
}

ParaboloidCoord directionToParaboloid(const glm::vec3& v) {
    float len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
    glm::vec3 u = len > 0.0f ? v / len : glm::vec3(0.0f, 0.0f, 1.0f);
    ParaboloidSide side = paraboloidSide(u);
    // Front: (x, y) = (ux, uy)/(1 + uz); back: (ux, uy)/(1 − uz). Both denominators are
    // ≥ 1 on their own hemisphere, so no division blows up.
    float d = side == ParaboloidSide::Front ? 1.0f + u.z : 1.0f - u.z;
    return {side, (u.x / d + 1.0f) * 0.5f, (u.y / d + 1.0f) * 0.5f};
}

glm::vec3 paraboloidToDirection(ParaboloidSide side, float s, float t) {
    // The paraboloid z = ½ − ½(x² + y²) reflects (0, 0, ∓1) into
    // (2x, 2y, ±(1 − x² − y²)) / (1 + x² + y²).
    float x = 2.0f * s - 1.0f, y = 2.0f * t - 1.0f;
    float r2 = x * x + y * y;
    float z = (1.0f - r2) / (1.0f + r2);
    return {2.0f * x / (1.0f + r2), 2.0f * y / (1.0f + r2), side == ParaboloidSide::Front ? z : -z};
}

glm::mat4 paraboloidTextureMatrix(ParaboloidSide side) {
    // Column-major glm: M·(rx, ry, rz, 1) = (½rx + ½σrz + ½, ½ry + ½σrz + ½, 0, σrz + 1)
    // with σ = +1 front, −1 back; dividing by q gives (rx/(1 + σrz) + 1)/2.
    const float sg = side == ParaboloidSide::Front ? 1.0f : -1.0f;
    glm::mat4 m(0.0f);
    m[0][0] = 0.5f;       // s += ½ rx
    m[1][1] = 0.5f;       // t += ½ ry
    m[2][0] = 0.5f * sg;  // s += ½σ rz
    m[2][1] = 0.5f * sg;  // t += ½σ rz
    m[2][3] = sg;         // q += σ rz
    m[3][0] = 0.5f;       // s += ½
    m[3][1] = 0.5f;       // t += ½
    m[3][3] = 1.0f;       // q += 1
    return m;
}

Rgba8 sampleDualParaboloid(const Texture& front, const Texture& back, const SamplerState& s,
                           const glm::vec3& v, int32_t lambda) {
    ParaboloidCoord c = directionToParaboloid(v);
    const Texture& t = c.side == ParaboloidSide::Front ? front : back;
    TapList taps;
    gatherTaps(t, s, glm::vec4(c.s, c.t, 0.0f, 0.0f), lambda, taps);
    return resolveTaps(t, s, taps);
}

}  // namespace rg::tex
