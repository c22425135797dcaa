// Cube-map face selection (docs/hardware.md, "Cube mapping"; ARB_texture_cube_map §3.8.6).
#include <cmath>

#include "cube_select.h"
#include "texunit/cube_mapping.h"

namespace rg::tex {

CubeCoord projectOntoCubeFace(CubeFace face, const glm::vec3& r) {
    return detail::projectOntoCubeFace(face, r);
}
CubeCoord selectCubeFace(const glm::vec3& r) { return detail::selectCubeFace(r); }

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
