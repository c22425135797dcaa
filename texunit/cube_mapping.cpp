// Cube-map face selection (docs/hardware.md, "Cube mapping"; ARB_texture_cube_map §3.8.6).
#include <cmath>

#include "texunit/cube_mapping.h"

namespace rg::tex {

CubeCoord projectOntoCubeFace(CubeFace face, const glm::vec3& r) {
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

CubeCoord selectCubeFace(const glm::vec3& r) {
    const float ax = std::fabs(r.x), ay = std::fabs(r.y), az = std::fabs(r.z);
    CubeFace face;
    // Ties: X before Y before Z (>=), and a zero component counts as positive.
    if (ax >= ay && ax >= az)
        face = r.x >= 0.0f ? CubeFace::PositiveX : CubeFace::NegativeX;
    else if (ay >= az)
        face = r.y >= 0.0f ? CubeFace::PositiveY : CubeFace::NegativeY;
    else
        face = r.z >= 0.0f ? CubeFace::PositiveZ : CubeFace::NegativeZ;
    return projectOntoCubeFace(face, r);
}

glm::vec3 cubeFaceDirection(CubeFace face, float s, float t) {
    const float sc = 2.0f * s - 1.0f, tc = 2.0f * t - 1.0f;
    switch (face) {
        case CubeFace::PositiveX: return {1.0f, -tc, -sc};
        case CubeFace::NegativeX: return {-1.0f, -tc, sc};
        case CubeFace::PositiveY: return {sc, 1.0f, tc};
        case CubeFace::NegativeY: return {sc, -1.0f, -tc};
        case CubeFace::PositiveZ: return {sc, -tc, 1.0f};
        case CubeFace::NegativeZ: return {-sc, -tc, -1.0f};
    }
    return {1.0f, 0.0f, 0.0f};
}

}  // namespace rg::tex
