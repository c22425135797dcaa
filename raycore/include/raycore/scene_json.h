// The JSON scene format (docs/scene-format.md, example data/scenes/example.json): objects
// (built-in shapes, built-in objects such as the teapot, or mesh files), transforms,
// materials, textures, cameras, lights, environment, viewpoint paths.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "raycore/scene.h"

namespace rg::ray {

// Paths inside the file are relative to the file's folder. Unknown keys are warnings
// (collected in *warnings when given, else printed to stderr); unknown materials, missing
// files, malformed JSON and bad values raise rg::Error naming the file and the entry.
Scene loadSceneJson(const std::filesystem::path& path, std::vector<std::string>* warnings = nullptr);
Scene parseSceneJson(const std::string& text, const std::filesystem::path& baseDir,
                     const std::string& what, std::vector<std::string>* warnings = nullptr);

// Writes the scene back; meshes are written by their MeshSource (generator or file).
std::string sceneToJson(const Scene& scene);
void saveSceneJson(const Scene& scene, const std::filesystem::path& path);

// A .json file, a built-in scene name, or the stem of a scene shipped in data/scenes/
// ("forest"); rg::Error listing the known names otherwise.
Scene loadSceneByName(const std::string& fileOrName, std::vector<std::string>* warnings = nullptr);

}  // namespace rg::ray
