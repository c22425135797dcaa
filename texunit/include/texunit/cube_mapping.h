// Cube-map mapping: face selection and face coordinates from an unnormalized direction,
// exactly as the ARB_texture_cube_map table (docs/hardware.md, "Cube mapping").
#pragma once

#include <glm/vec3.hpp>

#include "texunit/texture.h"

namespace rg::tex {

struct CubeCoord {
    CubeFace face;
    float s, t;  // in [0, 1] on the face
};

// ARB_texture_cube_map, section 3.8.6 table:
//   major axis  face  sc   tc   ma
//   +rx         +X    −rz  −ry  rx
//   −rx         −X    +rz  −ry  rx
//   +ry         +Y    +rx  +rz  ry
//   −ry         −Y    +rx  −rz  ry
//   +rz         +Z    +rx  −ry  rz
//   −rz         −Z    −rx  −ry  rz
//   s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2.
// Ties (|rx| = |ry| or = |rz|, the spec leaves them open) go to X before Y before Z; a
// zero component's sign is taken as positive (−0 included). The zero vector maps to +X
// at (0.5, 0.5). No normalization: the direction's length never enters.
CubeCoord selectCubeFace(const glm::vec3& r);
// The (s, t) of `r` on a given face (same table row, |ma| of that face's axis): used for
// the quad's LOD, which measures all four pixels on pixel 0's face.
CubeCoord projectOntoCubeFace(CubeFace face, const glm::vec3& r);
// Inverse for round-trip tests: a direction (|major axis| = 1) for (face, s, t).
glm::vec3 cubeFaceDirection(CubeFace face, float s, float t);

}  // namespace rg::tex
