// Meshes from Debian's libcgal-demo package, by name ("cgal:armadillo"): the package ships
// CGAL's test data as /usr/share/doc/libcgal-dev/data.tar.gz, whose data/meshes/*.off hold
// well-known models (the Stanford armadillo and bunny, a Chinese dragon, a human figure…).
// They are read from the installed package at run time, never copied into the repository
// (docs/attribution.md has their provenance).
#pragma once

#include <filesystem>
#include <string>

#include "raycore/mesh.h"

namespace rg::ray {

// The archive: $RETROGLASS_CGAL_DATA when set, else the package's path.
std::filesystem::path cgalDataArchive();
// data/meshes/<name>.off from the archive, through loadMesh (extracted once into
// $XDG_CACHE_HOME/retroglass/cgal, else ~/.cache/retroglass/cgal). rg::Error naming the
// package when the archive is missing, and the mesh when the archive has no such member.
Mesh loadCgalMesh(const std::string& name);

// Closes the holes of a mesh: every loop of boundary edges (edges of one triangle only) is
// fanned from its first vertex, wound so that each boundary edge gets its opposite. Returns
// the number of triangles added. (ChineseDragon-10kv has 6 boundary edges.)
int fillHoles(Mesh& mesh);

}  // namespace rg::ray
