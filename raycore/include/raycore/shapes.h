// Procedural shapes: the analytic primitives and the lathe, out of which the built-in
// scenes (room, cup, columns, chess set) are made. All return closed meshes unless noted,
// counter-clockwise from outside, y up, with smooth normals where the surface is smooth.
#pragma once

#include <glm/glm.hpp>

#include <vector>

#include "raycore/mesh.h"

namespace rg::ray {

Mesh makeSphere(float radius, int slices = 64, int stacks = 32);
Mesh makeCube(float halfSize);  // flat-shaded, 24 vertices, uvs per face
Mesh makeTorus(float majorRadius, float minorRadius, int majorSegments = 64,
               int minorSegments = 32);
// A closed cylinder from y=0 to y=height.
Mesh makeCylinder(float radius, float height, int segments = 48);

// Revolves a profile (x = radius ≥ 0, y = height) about the y axis. The profile runs from
// bottom to top; endpoints on the axis close the surface. Normals are smooth along the
// revolution and split at profile corners sharper than `creaseDegrees`.
Mesh makeLathe(const std::vector<glm::vec2>& profile, int segments = 48,
               float creaseDegrees = 40.0f);

// Extrudes a closed counter-clockwise polygon in the xy plane along z from -depth/2 to
// depth/2 (caps triangulated as a fan from the centroid: the polygon must be star-shaped
// around it).
Mesh makeExtrusion(const std::vector<glm::vec2>& polygon, float depth);

// A room: an axis-aligned box seen from inside, with six parts (floor, ceiling, wall_-x,
// wall_+x, wall_-z, wall_+z), uvs in metres/`uvScale` so textures tile at a fixed size.
Mesh makeRoom(glm::vec3 lo, glm::vec3 hi, float uvScale = 1.0f);

}  // namespace rg::ray
