// The Utah teapot data: counts, the lid/body split, outward normals.
#include <gtest/gtest.h>

#include <map>

#include "raycore/builtin_scenes.h"
#include "raycore/teapot.h"

namespace rg::ray {
namespace {

TeapotPatches patches() { return loadTeapotPatches(dataDir() / "teapot.txt"); }

TEST(Teapot, Has32PatchesOver306ControlPoints) {
    TeapotPatches t = patches();
    EXPECT_EQ(t.patches.size(), 32u);
    EXPECT_EQ(t.points.size(), 306u);
    std::map<std::string, int> groups;
    for (const TeapotPatch& p : t.patches) ++groups[p.group];
    EXPECT_EQ(groups["rim"], 4);
    EXPECT_EQ(groups["body"], 8);
    EXPECT_EQ(groups["handle"], 4);
    EXPECT_EQ(groups["spout"], 4);
    EXPECT_EQ(groups["lid"], 8);
    EXPECT_EQ(groups["bottom"], 4);
}

TEST(Teapot, PatchCornersInterpolateControlPoints) {
    TeapotPatches t = patches();
    for (const TeapotPatch& p : t.patches) {
        EXPECT_EQ(evalBezierPatch(t, p, 0, 0), t.points[p.controls[0]]);
        EXPECT_EQ(evalBezierPatch(t, p, 1, 1), t.points[p.controls[15]]);
    }
}

TEST(Teapot, Level25Gives40000TrianglesSplitIntoBodyAndLid) {
    Mesh m = tessellateTeapot(patches(), 25);
    EXPECT_EQ(m.triangleCount(), 40000u);  // 001 §6: ~40k triangles
    ASSERT_EQ(m.parts.size(), 2u);
    EXPECT_EQ(m.parts[0].name, "body");
    EXPECT_EQ(m.parts[1].name, "lid");
    EXPECT_EQ(m.parts[1].triangleCount, 8u * 2 * 625);  // 8 lid patches
    EXPECT_EQ(m.parts[0].triangleCount, 24u * 2 * 625);
    EXPECT_EQ(m.findPart("lid"), 1);
    validateMesh(m, "teapot");
    // Every lid triangle is above the rim (y ≥ 2.25 once z-up became y-up), the body's
    // lowest point is the bottom at y = 0.
    Bounds b = computeBounds(m);
    EXPECT_NEAR(b.lo.y, 0.0f, 1e-5f);
    EXPECT_NEAR(b.hi.y, 3.15f, 1e-5f);
    for (uint32_t t = m.parts[1].firstTriangle; t < m.triangleCount(); ++t)
        EXPECT_GE(m.positions[m.indices[t * 3]].y, 2.25f);
    EXPECT_EQ(m.partOfTriangle(0), 0u);
    EXPECT_EQ(m.partOfTriangle(39999), 1u);
}

TEST(Teapot, NormalsPointOutwardsAndAgreeWithWinding) {
    Mesh m = tessellateTeapot(patches(), 8);
    // The top of the knob faces up, the centre of the bottom faces down.
    size_t top = 0, bottom = 0;
    for (size_t i = 0; i < m.positions.size(); ++i) {
        if (m.positions[i].y > m.positions[top].y) top = i;
        if (m.positions[i].y < m.positions[bottom].y) bottom = i;
    }
    EXPECT_GT(m.normals[top].y, 0.99f);
    EXPECT_LT(m.normals[bottom].y, -0.99f);
    // Winding agrees with the vertex normals on (nearly) every non-degenerate triangle;
    // the exceptions are slivers at the degenerate lid tip and bottom centre.
    int agree = 0, total = 0;
    for (size_t t = 0; t < m.triangleCount(); ++t) {
        glm::vec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                  c = m.positions[m.indices[3 * t + 2]];
        glm::vec3 ng = glm::cross(b - a, c - a);
        if (glm::length(ng) < 1e-8f) continue;
        glm::vec3 ns = m.normals[m.indices[3 * t]] + m.normals[m.indices[3 * t + 1]] +
                       m.normals[m.indices[3 * t + 2]];
        ++total;
        agree += glm::dot(ng, ns) > 0.0f;
    }
    EXPECT_GE(agree, total * 99 / 100) << agree << " of " << total;
    // On the body's widest ring normals point away from the axis.
    for (size_t i = 0; i < m.positions.size(); ++i) {
        glm::vec3 p = m.positions[i];
        if (std::abs(p.y - 1.2f) < 0.2f && glm::length(glm::vec2(p.x, p.z)) > 1.8f &&
            std::abs(p.x) < 2.0f) {  // not the spout or handle
            EXPECT_GT(glm::dot(glm::vec2(m.normals[i].x, m.normals[i].z), glm::vec2(p.x, p.z)), 0.0f)
                << "vertex " << i;
        }
    }
}

TEST(Teapot, BuiltinTeapotInRoomSelectsLidAndBody) {
    BuiltinOptions o;
    o.teapotLevel = 4;
    Scene s = makeBuiltinScene("teapot-in-room", o);
    int teapot = s.findObject("teapot");
    ASSERT_GE(teapot, 0);
    const Mesh& m = s.meshes[s.objects[size_t(teapot)].mesh];
    EXPECT_GE(m.findPart("lid"), 0);
    EXPECT_GE(m.findPart("body"), 0);
    EXPECT_EQ(s.materials[s.objects[size_t(teapot)].material].type, MaterialType::Mirror);
    ASSERT_EQ(s.viewpointPaths.size(), 1u);
    EXPECT_EQ(s.viewpointPaths[0].count, 100u);
    EXPECT_EQ(s.viewpointPaths[0].stepDegrees, 1.0f);
    EXPECT_GE(s.findObject("room_floor"), 0);
    EXPECT_GE(s.findObject("room_wall_-x"), 0);
}

}  // namespace
}  // namespace rg::ray
