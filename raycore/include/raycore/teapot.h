// The Utah teapot (Martin Newell, 1975) from its 32 bicubic Bézier patches (data/teapot.txt).
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "raycore/mesh.h"

namespace rg::ray {

struct TeapotPatch {
    std::string group;                  // rim, body, handle, spout, lid, bottom
    std::array<uint32_t, 16> controls;  // zero-based indices into points, row by row
};

struct TeapotPatches {
    std::vector<TeapotPatch> patches;   // 32
    std::vector<glm::vec3> points;      // 306, as in the file: z up
};

// Parses the patch file; malformed content raises rg::Error naming the file and line.
TeapotPatches loadTeapotPatches(const std::filesystem::path& path);

// Evaluates one patch at (u, v) in [0,1]², with the partial derivatives.
glm::vec3 evalBezierPatch(const TeapotPatches& t, const TeapotPatch& p, float u, float v,
                          glm::vec3* dPdu = nullptr, glm::vec3* dPdv = nullptr);

// Tessellates every patch into level×level quads (2·level² triangles), converted to y up
// ((x, y, z)_file → (x, z, −y)), normals from the patch derivatives, oriented outwards.
// Two parts: "body" (rim, body, handle, spout, bottom) then "lid". level 25 gives
// 32·2·625 = 40,000 triangles, the ~40k of 001 §6.
Mesh tessellateTeapot(const TeapotPatches& t, int level);

}  // namespace rg::ray
