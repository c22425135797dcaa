// Procedural shapes: closed, oriented outwards, normals consistent with winding.
#include <gtest/gtest.h>

#include <numbers>

#include <glm/gtc/matrix_transform.hpp>

#include "raycore/accel.h"
#include "raycore/builtin_scenes.h"
#include "raycore/mesh_io.h"
#include "raycore/shapes.h"

namespace rg::ray {
namespace {

// Signed volume by the divergence theorem: positive when triangles wind outwards.
double signedVolume(const Mesh& m) {
    double v = 0.0;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                   c = m.positions[m.indices[3 * t + 2]];
        v += glm::dot(a, glm::cross(b, c)) / 6.0;
    }
    return v;
}

double windingAgreement(const Mesh& m) {
    int agree = 0, total = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        glm::vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                  c = m.positions[m.indices[3 * t + 2]];
        glm::vec3 ng = glm::cross(b - a, c - a);
        if (glm::length(ng) == 0.0f) continue;
        glm::vec3 ns = m.normals[m.indices[3 * t]] + m.normals[m.indices[3 * t + 1]] +
                       m.normals[m.indices[3 * t + 2]];
        ++total;
        agree += glm::dot(ng, ns) > 0.0f;
    }
    return total ? double(agree) / total : 0.0;
}

TEST(Shapes, SphereIsClosedWithTheRightVolume) {
    Mesh m = makeSphere(1.0f, 128, 64);
    EXPECT_TRUE(isClosedManifold(m));
    EXPECT_NEAR(signedVolume(m), 4.0 / 3.0 * std::numbers::pi, 0.01);
    EXPECT_EQ(windingAgreement(m), 1.0);
}

TEST(Shapes, CubeTorusCylinderAreClosedAndOutward) {
    Mesh cube = makeCube(1.0f);
    EXPECT_TRUE(isClosedManifold(cube));
    EXPECT_NEAR(signedVolume(cube), 8.0, 1e-5);
    EXPECT_EQ(windingAgreement(cube), 1.0);
    Mesh torus = makeTorus(1.0f, 0.25f, 128, 64);
    EXPECT_TRUE(isClosedManifold(torus));
    // 2π²Rr²
    EXPECT_NEAR(signedVolume(torus), 2.0 * std::numbers::pi * std::numbers::pi * 0.0625, 0.005);
    EXPECT_EQ(windingAgreement(torus), 1.0);
    Mesh cyl = makeCylinder(0.5f, 2.0f, 256);
    EXPECT_TRUE(isClosedManifold(cyl));
    EXPECT_NEAR(signedVolume(cyl), std::numbers::pi * 0.25 * 2.0, 0.002);
    EXPECT_EQ(windingAgreement(cyl), 1.0);
}

TEST(Shapes, ChessPiecesAndCupAreClosedSolids) {
    for (const char* k : {"pawn", "rook", "knight", "bishop", "queen", "king"}) {
        Mesh m = makeChessPiece(k);
        EXPECT_TRUE(isClosedManifold(m)) << k;
        EXPECT_GT(signedVolume(m), 0.0) << k;
        EXPECT_EQ(windingAgreement(m), 1.0) << k;
    }
    Scene s;
    s.materials.push_back({});
    addCup(s, 0, glm::mat4(1.0f));
    EXPECT_TRUE(isClosedManifold(s.meshes[0]));
    EXPECT_GT(signedVolume(s.meshes[0]), 0.0);
}

TEST(Shapes, ChessSceneHas32PiecesAndASphere) {
    Scene s = makeBuiltinScene("chess");
    int pieces = 0;
    for (const Object& o : s.objects)
        if (o.name.rfind("white_", 0) == 0 || o.name.rfind("black_", 0) == 0) ++pieces;
    EXPECT_EQ(pieces, 32);
    EXPECT_GE(s.findObject("glass_sphere"), 0);
    EXPECT_GE(s.findObject("board"), 0);
    EXPECT_TRUE(validateScene(s).empty());  // every glass piece is closed
}

// A ray inside a piece heading down meets the piece's own base first, a glass-air face,
// and then the board kChessRestGap below it. With the base in the board's plane the two are
// at the same distance and Embree's closest hit took either, pixel by pixel (the pieces
// were black with speckles in every ray-traced reference of the chess set).
TEST(Shapes, ChessPiecesRestAboveTheBoardSoTheirBasesAreGlassAirFaces) {
    const Scene s = makeBuiltinScene("chess");
    const Accel accel(s);
    const int board = s.findObject("board");
    ASSERT_GE(board, 0);
    int pieces = 0, rays = 0;
    for (size_t o = 0; o < s.objects.size(); ++o) {
        const Object& ob = s.objects[o];
        if (ob.name.rfind("white_", 0) != 0 && ob.name.rfind("black_", 0) != 0) continue;
        ++pieces;
        for (int k = 0; k < 8; ++k)
            for (float slant : {0.0f, 0.3f, 0.6f, 0.9f}) {
                const float a = 2.0f * std::numbers::pi_v<float> * float(k) / 8.0f;
                Ray r;
                r.origin = glm::vec3(ob.transform * glm::vec4(0.08f * std::cos(a), 0.03f, 0.08f * std::sin(a), 1.0f));
                r.dir = glm::normalize(glm::vec3(slant * std::cos(a + 1.0f), -1.0f, slant * std::sin(a + 1.0f)));
                const Hit base = accel.intersect(r);
                ASSERT_TRUE(base.valid()) << ob.name;
                ASSERT_EQ(base.object, o) << ob.name << ": a ray down from inside its base met '"
                                          << s.objects[base.object].name << "' first";
                const SurfacePoint sp = accel.surface(r, base);
                EXPECT_FALSE(sp.frontFace) << ob.name;
                EXPECT_NEAR(sp.p.y, kChessRestGap, 1e-5f) << ob.name;
                Ray below;
                below.dir = r.dir;
                below.origin = accel.offsetOrigin(sp, r.dir);
                const Hit h = accel.intersect(below);
                ASSERT_TRUE(h.valid()) << ob.name;
                EXPECT_EQ(h.object, uint32_t(board)) << ob.name;
                // The gap, less the origin's offset below the base.
                EXPECT_GT(h.t * -r.dir.y, 0.5f * kChessRestGap) << ob.name;
                EXPECT_LE(h.t * -r.dir.y, kChessRestGap) << ob.name;
                ++rays;
            }
    }
    EXPECT_EQ(pieces, 32);
    EXPECT_EQ(rays, 32 * 32);
}

// validateScene warns when a glass object's flat face lies in the plane of another
// object's face turned towards it (the chess pieces' bug, for users' scenes), and only then.
TEST(Shapes, GlassRestingInAnotherFacesPlaneIsWarnedAbout) {
    auto sceneWith = [](float lift, glm::vec3 offset, MaterialType cubeType, bool wall) {
        Scene s;
        s.name = "contact";
        Material glass;
        glass.name = "cube_material";
        glass.type = cubeType;
        glass.ior = 1.5f;
        Material clay;
        clay.name = "clay";
        const uint32_t gm = s.addMaterial(glass), cm = s.addMaterial(clay);
        // A floor slab with its top at y = 0, 8 wide, and a wall slab with its face at x = 2.
        s.addObject("floor", s.addMesh(makeCube(1.0f)), cm,
                    glm::scale(glm::translate(glm::mat4(1.0f), {0.0f, -0.5f, 0.0f}), {4.0f, 0.5f, 4.0f}));
        if (wall)
            s.addObject("wall", s.addMesh(makeCube(1.0f)), cm,
                        glm::scale(glm::translate(glm::mat4(1.0f), {2.5f, 2.0f, 0.0f}), {0.5f, 2.0f, 4.0f}));
        // A cube of half size 0.5 resting on the floor (its bottom at y = lift).
        s.addObject("cube", s.addMesh(makeCube(0.5f)), gm,
                    glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.5f + lift, 0.0f) + offset));
        return s;
    };
    auto mentions = [](const std::vector<std::string>& w, const std::string& a, const std::string& b) {
        for (const std::string& m : w)
            if (m.find("'" + a + "'") != std::string::npos && m.find("'" + b + "'") != std::string::npos) return true;
        return false;
    };
    {
        const auto w = validateScene(sceneWith(0.0f, {}, MaterialType::Glass, false));
        ASSERT_EQ(w.size(), 1u);
        EXPECT_TRUE(mentions(w, "cube", "floor")) << w[0];
        EXPECT_NE(w[0].find("y = 0"), std::string::npos) << w[0];
    }
    // Lifted well past the tracer's offset: nothing. Within it: still the same plane.
    EXPECT_TRUE(validateScene(sceneWith(0.01f, {}, MaterialType::Glass, false)).empty());
    EXPECT_EQ(validateScene(sceneWith(1e-6f, {}, MaterialType::Glass, false)).size(), 1u);
    // A mirror is never entered; glass beside the floor, in its plane but off it, touches nothing.
    EXPECT_TRUE(validateScene(sceneWith(0.0f, {}, MaterialType::Mirror, false)).empty());
    EXPECT_TRUE(validateScene(sceneWith(0.0f, {6.0f, 0.0f, 0.0f}, MaterialType::Glass, false)).empty());
    // Against a wall (its face at x = 2, the cube's side at x = 2) as well as on the floor.
    {
        const auto w = validateScene(sceneWith(0.0f, {1.5f, 0.0f, 0.0f}, MaterialType::Glass, true));
        EXPECT_EQ(w.size(), 2u);
        EXPECT_TRUE(mentions(w, "cube", "wall"));
        EXPECT_TRUE(mentions(w, "cube", "floor"));
    }
    // A glass sphere resting on the floor touches it at a point: its pole's few triangles
    // (512 × 256: the first ring 4e-5 above the floor, inside the tracer's offset) in the plane
    // are under the 1 % the check lets be.
    {
        Scene s = sceneWith(0.0f, {6.0f, 0.0f, 0.0f}, MaterialType::Glass, false);
        Material glass;
        glass.type = MaterialType::Glass;
        s.addObject("ball", s.addMesh(makeSphere(0.5f, 512, 256)), s.addMaterial(glass),
                    glm::translate(glm::mat4(1.0f), {0.0f, 0.5f, 0.0f}));
        EXPECT_TRUE(validateScene(s).empty()) << validateScene(s)[0];
    }
    // raycore's chess set before 2026-11-28: every piece on the board.
    {
        Scene s = makeBuiltinScene("chess");
        for (Object& o : s.objects)
            if (o.name.rfind("white_", 0) == 0 || o.name.rfind("black_", 0) == 0)
                o.transform = glm::translate(glm::mat4(1.0f), {0.0f, -kChessRestGap, 0.0f}) * o.transform;
        const auto w = validateScene(s);
        EXPECT_EQ(w.size(), 32u);
        EXPECT_TRUE(mentions(w, "white_pawn0", "board"));
    }
}

TEST(Shapes, RoomFacesPointInwards) {
    Mesh room = makeRoom({-1, 0, -2}, {3, 4, 5});
    EXPECT_EQ(room.parts.size(), 6u);
    EXPECT_TRUE(isClosedManifold(room));
    EXPECT_LT(signedVolume(room), 0.0);  // seen from inside
    EXPECT_EQ(windingAgreement(room), 1.0);
}

TEST(Shapes, BunnyLoadsClosed) {
    Mesh m = loadMesh(dataDir() / "bunny.obj");
    EXPECT_EQ(m.positions.size(), 1839u);
    EXPECT_EQ(m.triangleCount(), 3674u);
    EXPECT_TRUE(isClosedManifold(m));
    EXPECT_GT(signedVolume(m), 0.0);
}

}  // namespace
}  // namespace rg::ray

namespace rg::ray {
namespace {

TEST(Shapes, AreaWeightedCentroidOfSymmetricShapes) {
    // A cube's faces balance at its centre; a cube moved by t has its centroid at t.
    Mesh cube = makeCube(1.0f);
    glm::vec3 c = areaWeightedCentroid(cube);
    EXPECT_NEAR(glm::length(c), 0.0f, 1e-6f);
    transformMesh(cube, glm::mat4(glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 0), glm::vec4(0, 0, 1, 0),
                                  glm::vec4(2, 3, 4, 1)));
    c = areaWeightedCentroid(cube);
    EXPECT_NEAR(c.x, 2.0f, 1e-5f);
    EXPECT_NEAR(c.y, 3.0f, 1e-5f);
    EXPECT_NEAR(c.z, 4.0f, 1e-5f);
    // A room's floor part alone sits on the floor.
    Mesh room = makeRoom({-1, 0, -1}, {1, 2, 1});
    EXPECT_NEAR(areaWeightedCentroid(room, room.findPart("floor")).y, 0.0f, 1e-6f);
    EXPECT_NEAR(areaWeightedCentroid(room).y, 1.0f, 1e-6f);
}

}  // namespace
}  // namespace rg::ray
