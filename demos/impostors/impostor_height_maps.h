// 002 §6's refractor height map of a mesh: "Taking a picture of the piece with an orthogonal
// camera perpendicular to the plane of symmetry and storing the distances of the surface points
// from the plane in a map, we would actually get a height map … Besides the distances, we need
// the normal vectors as well." Built on the CPU with raycore's Embree tracer, one orthographic
// ray per texel (the "picture"), then uploaded to the device as an RGBA32F texture.
#pragma once

#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "impostor_height_search.h"
#include "raycore/mesh.h"

namespace rg::impostors {

struct HeightMap {
    int size = 0;
    HeightFrame frame;             // in the frame about `centre` (the refractor map's)
    std::vector<glm::vec4> texels;  // size² rows from tHi down: (unit normal in (s, t, h), height); empty (0, 0, 0, 0)
    int coveredTexels = 0;
};

// The mesh's height map over its plane of symmetry, in its model frame moved to `centre` (the
// mesh's box centre, where its refractor distance map sits). The plane: z = 0 of the model
// (every piece of raycore's chess set is a lathe about the model's y axis, and the knight's head
// is extruded symmetrically about z = 0); the billboard turns about the model's y axis where
// the mesh's footprint holds it (x = z = 0), else about the box's centre. The texture domain is
// the mesh's reach from that axis (max √(x² + z²)) across s and its y range along t, padded by
// two texels on every side so that the box's faces read as empty (a bisection's end there is
// outside); hMax 1 % beyond the highest stored height.
HeightMap buildHeightMap(const ray::Mesh& mesh, const glm::vec3& centre, int size, int steps = 8);

}  // namespace rg::impostors
