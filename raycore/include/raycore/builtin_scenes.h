// Built-in scenes and objects, made procedurally or from data/ (teapot.txt, bunny.obj).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "raycore/scene.h"

namespace rg::ray {

// The data/ folder: $RETROGLASS_DATA_DIR when set, else the source tree's data/.
std::filesystem::path dataDir();

struct BuiltinOptions {
    int teapotLevel = 25;  // 25 → 40,000 triangles (001 §6)
};

// Names accepted by makeBuiltinScene:
//   teapot-in-room   mirror teapot (object "teapot", parts "body" and "lid") in a textured
//                    room; viewpoint path "circle" at 1° per view, 100 views (001 §6)
//   glass-teapot     glass teapot, mirror cup, ring of columns, distant walls (000 §6)
//   chess            8×8 chessboard, 32 glass lathe pieces and a glass sphere
//   glass-cube       a glass cube in a white environment (the TIR test scene)
//   mirror-sphere    a mirror sphere in a constant environment
//   bunny, torus, sphere, cube   one object on a checker floor
std::vector<std::string> builtinSceneNames();
// Raises rg::Error naming the scene for an unknown name.
Scene makeBuiltinScene(const std::string& name, const BuiltinOptions& options = {});

// Building blocks, each added to `scene`; they return the object index.
uint32_t addTeapot(Scene& scene, int level, uint32_t material, const glm::mat4& transform);
// Six objects named <prefix>floor, <prefix>ceiling, <prefix>wall_-x, … each with its own
// textured diffuse material (bricks, checker, wood rings, gradient) so that every wall is
// recognisable in a reflection. Returns the first of the six.
uint32_t addRoom(Scene& scene, glm::vec3 lo, glm::vec3 hi, const std::string& prefix = "room_");
uint32_t addCup(Scene& scene, uint32_t material, const glm::mat4& transform);
void addColumnRing(Scene& scene, glm::vec3 center, float radius, int count, float height,
                   uint32_t material);
// The 32 pieces on their squares (white on ranks 1–2 at z < 0), lathes of `segments`,
// their bases kChessRestGap above the board's top (y = 0): see chess_set.cpp.
inline constexpr float kChessRestGap = 0.01f;
void addChessSet(Scene& scene, uint32_t whiteGlass, uint32_t blackGlass, int segments = 40);
// The 8×8 board: a slab 8·squareSize wide whose top face carries uvs [0,1]² (a checker
// texture with scale 8 draws the squares), top face at y = 0.
Mesh makeChessboard(float squareSize);
// The six lathe profiles and the knight (lathe base + extruded head), height ≈ 1, the
// lathes with `segments` around the axis (the built-in scene's 40; the impostors
// reproduction picks the count that matches its paper's triangle count).
Mesh makeChessPiece(const std::string& kind, int segments = 40);  // pawn rook knight bishop queen king

}  // namespace rg::ray
