// Dual-paraboloid environment maps after Heidrich & Seidel, "View-independent environment
// maps", Graphics Hardware 1998 (docs/hardware.md, "Paraboloid mapping").
//
// The front map covers directions with z ≥ 0, the back map z < 0. A unit direction v
// maps on the front to (x, y) = (vx, vy)/(1 + vz), on the back to (vx, vy)/(1 − vz),
// s = (x + 1)/2, t = (y + 1)/2. The hardware did this with the texture matrix and the
// projective divide (paraboloidTextureMatrix + q divide), one map per pass with the side
// chosen by the sign of z; sampleDualParaboloid() is the direct twin and must agree.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/color.h"
#include "texunit/sampler.h"

namespace rg::tex {

enum class ParaboloidSide : uint8_t { Front, Back };

struct ParaboloidCoord {
    ParaboloidSide side;
    float s, t;
};

// vz ≥ 0 (the rz = 0 rim included) is the front.
ParaboloidSide paraboloidSide(const glm::vec3& v);
// Direct mapping; `v` need not be normalized (it is normalized here).
ParaboloidCoord directionToParaboloid(const glm::vec3& v);
// Inverse: the unit direction of (side, s, t); valid for (2s−1)² + (2t−1)² ≤ 1.
glm::vec3 paraboloidToDirection(ParaboloidSide side, float s, float t);
// Texture matrix that takes a unit reflection vector (rx, ry, rz, 1) to homogeneous
// (s·q, t·q, 0, q) of `side`; the stage's q divide finishes the mapping. The back map is
// not mirrored: a rim direction (x, y, 0) lands on the same (s, t) in both maps.
glm::mat4 paraboloidTextureMatrix(ParaboloidSide side);
// Direct dual-paraboloid sampler: picks the side, maps and samples `front` or `back`.
Rgba8 sampleDualParaboloid(const Texture& front, const Texture& back, const SamplerState& s,
                           const glm::vec3& v, int32_t lambda);

}  // namespace rg::tex
