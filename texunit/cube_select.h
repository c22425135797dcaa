// Internal: cube-face selection as inline functions for the per-quad path; the public
// selectCubeFace()/projectOntoCubeFace() in cube_mapping.cpp are these
// (docs/hardware.md, "Cube mapping").
#pragma once

#include <cmath>

#include "texunit/cube_mapping.h"

namespace rg::tex::detail {

inline CubeCoord projectOntoCubeFace(CubeFace face, const glm::vec3& r) {
    // The spec's table, one row per face: (sc, tc, ma).
    float sc = 0, tc = 0, ma = 0;
    switch (face) {
        case CubeFace::PositiveX: sc = -r.z; tc = -r.y; ma = r.x; break;
        case CubeFace::NegativeX: sc = r.z; tc = -r.y; ma = r.x; break;
        case CubeFace::PositiveY: sc = r.x; tc = r.z; ma = r.y; break;
        case CubeFace::NegativeY: sc = r.x; tc = -r.z; ma = r.y; break;
        case CubeFace::PositiveZ: sc = r.x; tc = -r.y; ma = r.z; break;
        case CubeFace::NegativeZ: sc = -r.x; tc = -r.y; ma = r.z; break;
    }
    float a = std::fabs(ma);
    if (!(a > 0.0f)) return {face, 0.5f, 0.5f};  // zero (or NaN) major axis: face centre
    // (sc/|ma| + 1)/2 in this order of operations, the spec's formula literally.
    return {face, (sc / a + 1.0f) * 0.5f, (tc / a + 1.0f) * 0.5f};
}

inline CubeCoord selectCubeFace(const glm::vec3& r) {
    const float ax = std::fabs(r.x), ay = std::fabs(r.y), az = std::fabs(r.z);
    CubeFace face;
    // Ties: X before Y before Z (>=), and a zero component counts as positive.
    if (ax >= ay && ax >= az)
        face = r.x >= 0.0f ? CubeFace::PositiveX : CubeFace::NegativeX;
    else if (ay >= az)
        face = r.y >= 0.0f ? CubeFace::PositiveY : CubeFace::NegativeY;
    else
        face = r.z >= 0.0f ? CubeFace::PositiveZ : CubeFace::NegativeZ;
    return detail::projectOntoCubeFace(face, r);
}

}  // namespace rg::tex::detail
