// Meshes from files through assimp (OBJ, PLY, glTF, and whatever else it reads).
#pragma once

#include <filesystem>

#include "raycore/mesh.h"

namespace rg::ray {

// All meshes of the file merged into one, one part per file mesh, triangulated, with
// normals generated where the file has none. Missing, empty or malformed files and
// non-finite positions raise rg::Error naming the file and the problem.
Mesh loadMesh(const std::filesystem::path& path);

}  // namespace rg::ray
