// The scenes of Davis & Wyman 2007 (004 §4) as raycore scenes, shared by the emulated
// passes and the reference tracer: one glass object (the refractor), the nearby diffuse
// geometry, an environment. The paper's models are substituted (docs/attribution.md):
//
//   kitchen   Figure 10, Table 1 row 1: the Stanford bunny in glass in a room with the Utah
//             teapot (both as in the paper).
//   statue    Figure 9's "Buddha in front of Venus in the Uffizi": a glass statue (the
//             Stanford armadillo from Debian's libcgal-demo, cgal:armadillo) in front of a
//             diffuse human figure (cgal:man) in a gallery-like world (blender:interior).
//   dragon    Figure 1, Table 1 row 3: the Chinese dragon (cgal:ChineseDragon-10kv, its
//             small holes filled) before a Macbeth-style colour chart, world blender:studio.
//   prism     Figures 8 and 11: a thick glass block turned so that most paths reflect
//             totally, in blender:courtyard (no nearby geometry).
#pragma once

#include <string>
#include <vector>

#include "raycore/camera.h"
#include "raycore/scene.h"

namespace rg::tir {

struct TirScene {
    ray::Scene scene;
    uint32_t refractor = 0;   // Scene::objects index of the glass object
    ray::Camera camera;       // the view the figures use
    std::string substitutes;  // which model stands for which of the paper's
    std::vector<std::string> warnings;  // e.g. an open refractor mesh
};

std::vector<std::string> tirSceneNames();
// A built-in scene by name. `paper`: the paper-quality models (finer meshes).
TirScene makeTirScene(const std::string& name, bool paper = false);
// A user's scene file (docs/scene-format.md) or a raycore built-in scene: the refractor is
// its first glass object (rg::Error when it has none; a warning when its mesh is open),
// the camera its first camera or viewpoint.
TirScene tirSceneFromFile(const std::string& fileOrName);

// The refractor's index of refraction (rg::Error when ≤ 0 or not finite).
float refractorIor(const TirScene& s);

}  // namespace rg::tir
