// The scene of Dancsik & Minarik (002 §8) as a raycore scene, shared by the emulated passes
// and the ray-traced reference: a chessboard with two full sets of glass pieces and a glass
// sphere standing on it, under a sky, one piece moving. The paper gives no colours, index,
// lights, camera or sphere placement; ours (impostor_scene.cpp) are raycore's `chess`
// scene's, with the sphere moved onto the board and the pieces' tessellation raised
// towards the paper's triangle count.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "raycore/camera.h"
#include "raycore/scene.h"

namespace rg::impostors {

struct ImpostorScene {
    ray::Scene scene;             // the mover at the start of its path
    std::vector<uint32_t> glass;  // Scene::objects with a glass or mirror material, in order
    int mover = -1;               // Scene::objects index of the moving object; −1: none
    glm::vec3 moverPath{0.0f};    // its displacement from the start to the end of its path
    ray::Camera camera;           // Figure 10 (left): the whole scene
    ray::Camera closeUp;          // Figure 9: the mover seen through the sphere
    std::string description;      // what stands for what of the paper's scene
    std::vector<std::string> warnings;
    int64_t vertices = 0, faces = 0;  // the meshes as placed (the paper: 30,838 and 47,404)

    // The mover's object transform at u ∈ [0, 1] along its path.
    glm::mat4 moverTransform(float u) const;
    // The scene with the mover at u (what the reference tracer sees).
    ray::Scene at(float u) const;
};

struct ChessOptions {
    int segments = 56;          // lathe segments of the pieces
    int sphereSlices = 64;      // the glass sphere's tessellation (slices × slices/2)
    bool mirrorMover = false;   // Figure 9: the moving pawn is a mirror
    // Only these objects (and the board, the mover and the sphere) when not empty: the small
    // scenes of the tests and golden traces.
    std::vector<std::string> keep;
};
// The §8 scene: mover the white d-pawn, d2 → d4.
ImpostorScene makeChessScene(const ChessOptions& options = {});

// A user's scene (docs/scene-format.md, or a raycore built-in name): its glass and mirror
// objects get impostors; `mover` names the object that moves (empty: the last of them),
// along +x by one unit. rg::Error for a scene without a glass or mirror object, a mover
// that does not exist or is not glass or mirror, or a scene without a camera.
ImpostorScene impostorSceneFromFile(const std::string& fileOrName, const std::string& mover = {});

// Recomputes `glass`, `vertices` and `faces` after the scene's objects changed (the mover
// must be set again by name).
void indexGlass(ImpostorScene& s);

// Marks `name` the mover (rg::Error naming the scene's glass objects when it is not one).
void setMover(ImpostorScene& s, const std::string& name);

}  // namespace rg::impostors
