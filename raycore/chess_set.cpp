// The chessboard and the 32 glass pieces: lathe profiles (Staunton-like proportions,
// height about 1), the knight a lathe base with an extruded head.
#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "raycore/builtin_scenes.h"
#include "raycore/shapes.h"

namespace rg::ray {

namespace {

// Profiles from the axis at the bottom to the axis at the top: closed solids.
std::vector<glm::vec2> profileOf(const std::string& kind) {
    const std::vector<glm::vec2> base = {{0.0f, 0.0f}, {0.36f, 0.0f}, {0.36f, 0.06f}, {0.30f, 0.1f},
                                         {0.26f, 0.14f}};
    std::vector<glm::vec2> p = base;
    auto add = [&](std::initializer_list<glm::vec2> pts) { p.insert(p.end(), pts); };
    if (kind == "pawn") {
        add({{0.14f, 0.3f}, {0.11f, 0.42f}, {0.2f, 0.45f}, {0.1f, 0.5f}, {0.15f, 0.55f},
             {0.16f, 0.62f}, {0.12f, 0.69f}, {0.0f, 0.72f}});
    } else if (kind == "rook") {
        add({{0.2f, 0.3f}, {0.18f, 0.6f}, {0.26f, 0.62f}, {0.26f, 0.78f}, {0.18f, 0.78f},
             {0.18f, 0.72f}, {0.0f, 0.72f}});
    } else if (kind == "bishop") {
        add({{0.14f, 0.35f}, {0.1f, 0.58f}, {0.2f, 0.61f}, {0.1f, 0.65f}, {0.16f, 0.75f},
             {0.14f, 0.86f}, {0.07f, 0.93f}, {0.05f, 0.97f}, {0.0f, 1.0f}});
    } else if (kind == "queen") {
        add({{0.15f, 0.4f}, {0.1f, 0.72f}, {0.22f, 0.75f}, {0.12f, 0.8f}, {0.22f, 0.98f},
             {0.12f, 1.0f}, {0.06f, 1.06f}, {0.0f, 1.1f}});
    } else if (kind == "king") {
        add({{0.16f, 0.4f}, {0.11f, 0.78f}, {0.23f, 0.81f}, {0.13f, 0.86f}, {0.2f, 1.02f},
             {0.06f, 1.04f}, {0.06f, 1.1f}, {0.02f, 1.1f}, {0.02f, 1.22f}, {0.0f, 1.22f}});
    } else if (kind == "knight") {
        add({{0.2f, 0.24f}, {0.22f, 0.3f}, {0.0f, 0.3f}});
    } else {
        throw Error("unknown chess piece '" + kind + "' (pawn rook knight bishop queen king)");
    }
    return p;
}

}  // namespace

Mesh makeChessPiece(const std::string& kind, int segments) {
    Mesh m = makeLathe(profileOf(kind), segments);
    m.name = kind;
    if (kind == "knight") {
        // A horse's head in profile (facing +x), star-shaped about its centroid as
        // makeExtrusion requires, extruded 0.24 thick and stood on the base.
        Mesh head = makeExtrusion({{-0.18f, 0.0f}, {0.14f, 0.0f}, {0.1f, 0.22f}, {0.3f, 0.38f},
                                   {0.26f, 0.5f}, {0.05f, 0.62f}, {-0.04f, 0.7f}, {-0.12f, 0.6f},
                                   {-0.2f, 0.35f}},
                                  0.24f);
        transformMesh(head, glm::translate(glm::mat4(1.0f), {0.0f, 0.29f, 0.0f}));
        Mesh base = m;
        base.name = "base";
        m = Mesh{};
        m.name = kind;
        appendMesh(m, base, "base");
        appendMesh(m, head, "head");
    }
    m.source = {"chess_piece", kind, {}};
    if (segments != 40) m.source.params["segments"] = segments;
    return m;
}

Mesh makeChessboard(float squareSize) {
    Mesh m = makeCube(1.0f);
    transformMesh(m, glm::scale(glm::translate(glm::mat4(1.0f), {0.0f, -0.15f * squareSize, 0.0f}),
                                {4.0f * squareSize, 0.15f * squareSize, 4.0f * squareSize}));
    m.name = "chessboard";
    m.source = {"chessboard", "", {{"square_size", squareSize}}};
    return m;
}

void addChessSet(Scene& scene, uint32_t whiteGlass, uint32_t blackGlass, int segments) {
    const char* backRank[8] = {"rook", "knight", "bishop", "queen", "king", "bishop", "knight", "rook"};
    std::vector<std::string> kinds = {"pawn", "rook", "knight", "bishop", "queen", "king"};
    std::vector<uint32_t> meshOf(kinds.size());
    for (size_t i = 0; i < kinds.size(); ++i) meshOf[i] = scene.addMesh(makeChessPiece(kinds[i], segments));
    auto meshFor = [&](const std::string& k) {
        for (size_t i = 0; i < kinds.size(); ++i)
            if (kinds[i] == k) return meshOf[i];
        return meshOf[0];
    };
    for (int side = 0; side < 2; ++side) {
        const uint32_t mat = side == 0 ? whiteGlass : blackGlass;
        const float back = side == 0 ? -3.5f : 3.5f, pawns = side == 0 ? -2.5f : 2.5f;
        // Knights face the opponent: white looks towards +z.
        glm::mat4 facing = glm::rotate(glm::mat4(1.0f), side == 0 ? -1.5707963f : 1.5707963f,
                                       {0.0f, 1.0f, 0.0f});
        const std::string colour = side == 0 ? "white_" : "black_";
        // Each piece rests kChessRestGap above the board, not on it. With the base in the
        // board's plane, a ray inside the glass meets the base and the board at the same
        // distance and Embree's closest hit picks either, pixel by pixel: the bodies came
        // out black with sky-blue speckles. A gap makes the base a glass-air interface, as
        // under a real piece (felt, or wood's roughness), where the rays that the flared
        // bodies send steeply down reflect totally — and as the impostors' refractor maps
        // see it. 0.01 squares: above the tracer's origin offset (1e-5 of the scene's extent
        // times 1 + the largest coordinate: 0.003 in raycore's `chess` with its 60-wide
        // floor), below anything an image shows.
        for (int file = 0; file < 8; ++file) {
            float x = -3.5f + float(file);
            scene.addObject(colour + backRank[file] + std::to_string(file), meshFor(backRank[file]), mat,
                            glm::translate(glm::mat4(1.0f), {x, kChessRestGap, back}) * facing);
            scene.addObject(colour + "pawn" + std::to_string(file), meshFor("pawn"), mat,
                            glm::translate(glm::mat4(1.0f), {x, kChessRestGap, pawns}));
        }
    }
}

}  // namespace rg::ray
