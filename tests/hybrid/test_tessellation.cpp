// 000 §5's adaptive tessellation: the output conforms (no t-junction: every edge lies in at
// most two triangles, once each way, and no vertex lies inside an edge used once), every
// leaf of the subdivision stops for one of the paper's reasons, no vertex is traced
// twice, and the ring triangulation has no zero-area piece.
#include <gtest/gtest.h>

#include "core/error.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <map>
#include <numbers>
#include <set>

#include "adaptive_tessellation.h"
#include "hybrid_renderer.h"
#include "hybrid_test_scenes.h"
#include "lens_scene.h"

namespace rg::hybrid {
namespace {

struct BallView {
    LensScene scene;
    ray::Camera camera;
    ScreenSpace screen;
    BallView(int slices, int stacks)
        : scene(test::ballAndBox(slices, stacks), LensSceneOptions{}),
          camera(scene.scene().viewpointPaths[0].at(0)) {
        screen.width = 320;
        screen.height = 240;
        screen.viewProjection = viewProjection(camera, screen.width, screen.height);
        screen.eye = camera.eye;
    }
    AdaptiveMesh run(float tau, size_t lens = 0) {
        TessellationSettings t;
        t.tau = tau;
        const LensObject& L = scene.objects()[lens];
        return tessellateAdaptively(L, *L.local, scene.visibility(), screen, t);
    }
};

glm::vec2 window(const ScreenSpace& s, const glm::vec3& p) {
    glm::vec4 c = s.viewProjection * glm::vec4(p, 1.0f);
    return {(c.x / c.w * 0.5f + 0.5f) * float(s.width), (0.5f - c.y / c.w * 0.5f) * float(s.height)};
}

// Undirected edges by position, with how often each direction occurs.
std::map<std::pair<uint32_t, uint32_t>, std::pair<int, int>> edgeUse(const AdaptiveMesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, std::pair<int, int>> use;
    for (size_t t = 0; t < m.indices.size(); t += 3)
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = m.positionId[m.indices[t + size_t(e)]];
            const uint32_t b = m.positionId[m.indices[t + size_t((e + 1) % 3)]];
            auto& u = use[{std::min(a, b), std::max(a, b)}];
            (a < b ? u.first : u.second) += 1;
        }
    return use;
}

TEST(AdaptiveTessellation, OutputConformsEveryInteriorEdgeInExactlyTwoTriangles) {
    BallView s(24, 12);
    for (float tau : {2.0f, 3.0f, 5.0f}) {
        const AdaptiveMesh m = s.run(tau);
        ASSERT_GT(m.stats.splits4 + m.stats.splits3 + m.stats.splits2, 0) << "nothing was split";
        ASSERT_GT(m.stats.tjunctionPolygons, 0) << "no t-junction to remove at τ " << tau;
        const auto use = edgeUse(m);
        // Positions of every output vertex, to find one lying inside an edge.
        std::map<uint32_t, glm::vec3> at;
        for (uint32_t v : m.indices) at[m.positionId[v]] = m.positions[v];
        int interior = 0, boundary = 0;
        for (const auto& [e, n] : use) {
            ASSERT_LE(n.first, 1) << "an edge used twice the same way (overlap) at τ " << tau;
            ASSERT_LE(n.second, 1) << "an edge used twice the same way (overlap) at τ " << tau;
            if (n.first + n.second == 2) {
                ++interior;
                continue;
            }
            ++boundary;
            // A boundary edge (used by one triangle) must not carry another vertex: that
            // would be a t-junction of the neighbour across it.
            const glm::vec3 a = at[e.first], b = at[e.second];
            const float len = glm::length(b - a);
            for (const auto& [id, p] : at) {
                if (id == e.first || id == e.second) continue;
                const float t = glm::dot(p - a, b - a) / (len * len);
                if (t <= 1e-4f || t >= 1.0f - 1e-4f) continue;
                const float off = glm::length(a + t * (b - a) - p);
                ASSERT_GT(off, 1e-5f * len) << "t-junction: a vertex inside a boundary edge at τ " << tau;
            }
        }
        EXPECT_GT(interior, 3 * boundary) << "mostly interior edges expected";
        // The front-facing region's boundary is the silhouette: every boundary edge lies on
        // a base edge between a front and a back face, i.e. its ends face the eye at
        // grazing angles — checked here only as a count bound: the ball's silhouette ring.
        EXPECT_LT(boundary, 64 * 24) << "τ " << tau;
    }
}

TEST(AdaptiveTessellation, EveryLeafStopsForOneOfThePapersReasons) {
    BallView s(24, 12);
    const float tau = 3.0f;
    TessellationSettings ts;
    const AdaptiveMesh m = s.run(tau);
    const float cosT = std::cos(ts.exitAngleDegrees * std::numbers::pi_v<float> / 180.0f);
    ASSERT_FALSE(m.leaves.empty());
    int same = 0, small = 0, occluded = 0;
    for (size_t t = 0; t < m.leaves.size(); t += 3) {
        const uint32_t v[3] = {m.leaves[t], m.leaves[t + 1], m.leaves[t + 2]};
        for (uint32_t x : v) ASSERT_TRUE(m.traced[x]) << "a leaf vertex was never traced";
        const bool allHidden = !m.traces[v[0]].visible && !m.traces[v[1]].visible && !m.traces[v[2]].visible;
        const bool agree = !tracesDiffer(m.traces[v[0]], m.traces[v[1]], cosT) &&
                           !tracesDiffer(m.traces[v[1]], m.traces[v[2]], cosT) &&
                           !tracesDiffer(m.traces[v[2]], m.traces[v[0]], cosT);
        bool allShort = true;
        for (int e = 0; e < 3; ++e)
            allShort = allShort && glm::length(window(s.screen, m.positions[v[(e + 1) % 3]]) -
                                               window(s.screen, m.positions[v[e]])) < tau;
        ASSERT_TRUE(allHidden || agree || allShort) << "leaf " << t / 3 << " should have split";
        same += agree;
        small += !agree && allShort;
        occluded += allHidden && !agree && !allShort;
    }
    EXPECT_GT(same, 0);
    EXPECT_GT(small, 0);
    EXPECT_EQ(m.stats.leavesCapped, 0);
}

TEST(AdaptiveTessellation, NoVertexIsTracedTwice) {
    BallView s(24, 12);
    const AdaptiveMesh m = s.run(2.0f);
    int64_t traced = 0;
    std::set<std::tuple<uint32_t, float, float, float>> seen;
    for (size_t v = 0; v < m.positions.size(); ++v) {
        if (!m.traced[v]) continue;
        ++traced;
        const auto key = std::make_tuple(m.positionId[v], m.normals[v].x, m.normals[v].y, m.normals[v].z);
        ASSERT_TRUE(seen.insert(key).second) << "two traced vertices with one position and normal";
    }
    EXPECT_EQ(traced, m.stats.verticesTraced());
    // One visibility ray per traced vertex.
    EXPECT_EQ(int64_t(m.stats.rays.n[size_t(ray::RayKind::Primary)]), traced);
}

TEST(AdaptiveTessellation, ASmallerTauTracesMoreVerticesAndBackFacesAreNotTraced) {
    BallView s(24, 12);
    const AdaptiveMesh fine = s.run(2.0f), coarse = s.run(6.0f), huge = s.run(1e6f);
    EXPECT_GT(fine.stats.verticesTraced(), coarse.stats.verticesTraced());
    EXPECT_GT(coarse.stats.verticesTraced(), huge.stats.verticesTraced());
    // τ beyond the screen: no split at all, only the front faces' vertices are traced.
    EXPECT_EQ(huge.stats.midpointsTraced, 0);
    EXPECT_LT(huge.stats.baseVerticesTraced, int64_t(s.scene.objects()[0].positions.size()));
    EXPECT_EQ(huge.stats.outputTriangles, huge.stats.frontTriangles);
}

TEST(AdaptiveTessellation, RefusesTauAtOrBelowZero) {
    BallView s(12, 6);
    for (float tau : {0.0f, -1.0f, std::nanf("")}) EXPECT_THROW(s.run(tau), Error);
}

TEST(EdgeHash, FindsInsertsGrowsAndListsAnEdgesVertices) {
    EdgeHash h(2);
    EXPECT_EQ(h.find(1, 2), EdgeHash::kNone);
    h.insert(1, 2, 10);       // edge 1–2 split at 10
    h.insert(10, 2, 11);      // its half 10–2 split at 11
    for (uint32_t i = 100; i < 1100; ++i) h.insert(i, i + 1, i + 5000);  // grows
    EXPECT_EQ(h.find(2, 1), 10u);
    EXPECT_EQ(h.find(2, 10), 11u);
    EXPECT_EQ(h.find(600, 601), 5600u);
    EXPECT_THROW(h.insert(2, 1, 12), Error);
    std::vector<uint32_t> along;
    h.edgeVertices(1, 2, along);
    EXPECT_EQ(along, (std::vector<uint32_t>{1, 10, 11}));
    along.clear();
    h.edgeVertices(2, 1, along);
    EXPECT_EQ(along, (std::vector<uint32_t>{2, 11, 10}));
}

TEST(TriangulateRing, CoversTheTriangleWithoutZeroAreaPiecesOrTJunctions) {
    // Corners 0, 1, 2; edge 0 carries 3 and 4, edge 1 carries 5, edge 2 none.
    std::vector<glm::vec3> p = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}};
    std::vector<uint32_t> ring = {0, 3, 4, 1, 5, 2};
    std::vector<uint8_t> mask = {0b101, 0b001, 0b001, 0b011, 0b010, 0b110};
    std::vector<uint32_t> out;
    triangulateRing(ring, mask, p, out);
    ASSERT_EQ(out.size(), 3u * (ring.size() - 2));
    float area = 0;
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (size_t t = 0; t < out.size(); t += 3) {
        const glm::vec3 n = glm::cross(p[out[t + 1]] - p[out[t]], p[out[t + 2]] - p[out[t]]);
        ASSERT_GT(n.z, 1e-6f) << "zero area or flipped";
        area += 0.5f * n.z;
        for (int e = 0; e < 3; ++e) ++directed[{out[t + size_t(e)], out[t + size_t((e + 1) % 3)]}];
    }
    EXPECT_FLOAT_EQ(area, 8.0f);
    // Each ring side is used once, forwards; each inner edge once each way.
    for (size_t i = 0; i < ring.size(); ++i)
        EXPECT_EQ((directed[{ring[i], ring[(i + 1) % ring.size()]}]), 1);
    for (const auto& [e, n] : directed) {
        EXPECT_EQ(n, 1);
        const bool side = std::find(ring.begin(), ring.end(), e.first) != ring.end() &&
                          ring[(std::find(ring.begin(), ring.end(), e.first) - ring.begin() + 1) % ring.size()] == e.second;
        if (!side) EXPECT_EQ((directed[{e.second, e.first}]), 1) << "inner edge used one way only";
    }
}

TEST(PathsDiffer, LengthChoiceDirectionAndValidity) {
    ray::PathSummary a;
    a.valid = true;
    a.length = 2;
    a.events = 0b01;
    a.exitRay.dir = {0, 0, 1};
    ray::PathSummary b = a;
    const float cos3 = std::cos(3.0f * std::numbers::pi_v<float> / 180.0f);
    EXPECT_FALSE(pathsDiffer(a, b, cos3));
    b.exitRay.dir = glm::normalize(glm::vec3(std::tan(2.9f * std::numbers::pi_v<float> / 180.0f), 0, 1));
    EXPECT_FALSE(pathsDiffer(a, b, cos3));
    b.exitRay.dir = glm::normalize(glm::vec3(std::tan(3.1f * std::numbers::pi_v<float> / 180.0f), 0, 1));
    EXPECT_TRUE(pathsDiffer(a, b, cos3));
    b = a;
    b.events = 0b11;  // the second interface refracts instead of reflecting
    EXPECT_TRUE(pathsDiffer(a, b, cos3));
    b = a;
    b.length = 3;
    EXPECT_TRUE(pathsDiffer(a, b, cos3));
    b = a;
    b.valid = false;
    EXPECT_TRUE(pathsDiffer(a, b, cos3));
    a.valid = false;
    EXPECT_FALSE(pathsDiffer(a, b, cos3)) << "two dead paths agree";
}

}  // namespace
}  // namespace rg::hybrid
