// The fast path's four-triangle setup (rasterizer/setup_simd.cpp) against the reference
// setup (setupTriangle through clipAndSetup), field by field and bit for bit, on random
// triangles: every cull mode, both subpixel precisions, flat and Gouraud, perspective and
// linear colours, depth on and off, texture sets and partial (programmable) sets, edges
// through sample points (the top-left rule), tiny, sliver, collinear and repeated-vertex
// (exact-zero area) triangles, huge ones at the guard band, boxes cut by the clip rect,
// and vertices the SIMD lanes must hand to clipAndSetup (invalid, outside a clip plane,
// non-finite z or 1/w) in their place in the order.
//
// The SSE2 instantiation runs as SetupSimd.WithoutAvx2 (RETROGLASS_NO_AVX2=1).
// Reproduce a failure: the message names the seed and round; run
//   build/bin/test_rasterizer --gtest_filter='SetupSimd.*'
// with RETROGLASS_SETUP_SEED=<seed> to replay it.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "core/error.h"
#include "core/profile.h"
#include "pipeline.h"
#include "raster_test_util.h"
#include "rasterizer/device.h"
#include "rasterizer/framebuffer.h"
#include "texunit/texture_units.h"

namespace rg::testing {
namespace {

using namespace rg::raster;
using namespace rg::raster::detail;

template <class T>
bool sameBits(const T& a, const T& b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// Empty when equal, else the first differing field.
std::string differingField(const SetupTriangle& a, const SetupTriangle& b) {
#define RG_FIELD(f) \
    if (!sameBits(a.f, b.f)) return #f;
    RG_FIELD(A) RG_FIELD(B) RG_FIELD(C)
    RG_FIELD(minX) RG_FIELD(minY) RG_FIELD(maxX) RG_FIELD(maxY)
    RG_FIELD(x0) RG_FIELD(y0) RG_FIELD(zc) RG_FIELD(zdx) RG_FIELD(zdy)
    RG_FIELD(invW.c) RG_FIELD(invW.dx) RG_FIELD(invW.dy) RG_FIELD(quadCoverage)
    RG_FIELD(colorC) RG_FIELD(colorDx) RG_FIELD(colorDy)
    RG_FIELD(flatDiffuse) RG_FIELD(flatSpecular) RG_FIELD(texPlanes)
#undef RG_FIELD
    return {};
}

// A vertex whose snapped position is (sx, sy); the window position is what snapping would
// have come from (only its finiteness matters to setup).
ProcessedVertex vertexAt(Rng& r, int s, int64_t sx, int64_t sy, bool constantW) {
    ProcessedVertex v;
    v.sx = sx;
    v.sy = sy;
    v.wx = float(double(sx) / double(int64_t{1} << s));
    v.wy = float(double(sy) / double(int64_t{1} << s));
    v.wz = r.p(0.1) ? 0.5f : r.f(0.0f, 1.0f);
    v.invW = constantW ? 1.0f : r.f(0.01f, 4.0f);
    v.clip = glm::vec4(v.wx, v.wy, v.wz, 1.0f) / v.invW;
    for (int a = 0; a < kColorAttrs; ++a) v.attr[a] = float(r.i64(0, 255));
    for (int a = kColorAttrs; a < kMaxAttrs; ++a) v.attr[a] = r.f(-8.0f, 8.0f);
    v.outcode = 0;
    v.valid = true;
    return v;
}

// The reference path's setup of a draw's triangles: clipAndSetup per triangle, flat
// colours from the provoking vertex, as the reference rasterizer calls it.
void referenceSetup(const DrawContext& dc, Primitive prim, uint32_t triangles,
                    const std::vector<uint32_t>& indices, const std::vector<Vertex>& verts,
                    const ProcessedVertex* pv, std::vector<SetupTriangle>& out,
                    std::vector<Plane>& pool, GeometryCounters& gc) {
    for (uint32_t t = 0; t < triangles; ++t) {
        const std::array<uint32_t, 3> tv = triangleVertices(prim, t);
        const uint32_t a = indices.empty() ? tv[0] : indices[tv[0]];
        const uint32_t b = indices.empty() ? tv[1] : indices[tv[1]];
        const uint32_t c = indices.empty() ? tv[2] : indices[tv[2]];
        const Rgba8 flatD = dc.gouraud ? Rgba8{} : verts[a].diffuse;
        const Rgba8 flatS = dc.gouraud ? Rgba8{} : verts[a].specular;
        clipAndSetup(dc, pv[a], pv[b], pv[c], flatD, flatS, out, pool, gc);
    }
}

// The same triangles, field for field, and the same counts.
void expectSameSetup(const std::vector<SetupTriangle>& ref, const std::vector<SetupTriangle>& fast,
                     const GeometryCounters& refGc, const GeometryCounters& fastGc,
                     const std::string& where) {
    ASSERT_EQ(ref.size(), fast.size()) << where;
    ASSERT_EQ(refGc.submitted, fastGc.submitted) << where;
    ASSERT_EQ(refGc.culled, fastGc.culled) << where;
    ASSERT_EQ(refGc.clipped, fastGc.clipped) << where;
    ASSERT_EQ(refGc.drawn, fastGc.drawn) << where;
    ASSERT_EQ(refGc.invalid, fastGc.invalid) << where;
    for (size_t k = 0; k < ref.size(); ++k)
        ASSERT_EQ(differingField(ref[k], fast[k]), "") << where << ", triangle " << k;
}

void runRounds(uint64_t seed, int rounds) {
    Rng r(seed);
    tex::TextureUnits tu;
    for (int round = 0; round < rounds; ++round) {
        // ---- a random draw context -------------------------------------------------------
        const int s = r.p(0.5) ? 4 : 8;
        const int W = int(r.i64(8, 700)), H = int(r.i64(8, 500));
        Framebuffer fb(W, H, r.p(0.5) ? DepthFormat::D24 : DepthFormat::None);
        PipelineState st;
        st.cull = CullMode(r.i64(0, 2));
        st.shade = r.p(0.8) ? ShadeMode::Gouraud : ShadeMode::Flat;
        st.perspectiveColor = uint8_t(r.p(0.7));
        st.specularEnable = uint8_t(r.p(0.3));
        st.depthTest = uint8_t(r.p(0.6));
        st.scissorTest = uint8_t(r.p(0.3));
        Viewport vp{0, 0, W, H, 0.0f, 1.0f};
        Rect scissor{int32_t(r.i64(-20, W)), int32_t(r.i64(-20, H)), int32_t(r.i64(0, W)),
                     int32_t(r.i64(0, H))};
        DrawContext dc = makeDrawContext(st, fb, tu, Path::Fast, VertexSpace::Untransformed,
                                         vp, scissor, s);
        // Texture-coordinate sets (and the programmable pipeline's partial sets) as setup
        // sees them: numTexSets and numAttrs.
        const int texChoice = int(r.i64(0, 3));
        if (texChoice == 1) {
            dc.numTexSets = int(r.i64(1, tex::kMaxTexCoordSets));
            dc.numAttrs = kColorAttrs + 4 * dc.numTexSets;
            dc.needSpecular = true;
        } else if (texChoice == 2) {
            dc.numTexSets = 1;
            dc.numAttrs = kColorAttrs + int(r.i64(1, 4 * tex::kMaxTexCoordSets));
        }

        // ---- random vertices -------------------------------------------------------------
        const int64_t one = int64_t{1} << s, half = one >> 1;
        const int64_t guard = int64_t(kGuardBandPixels) << s;
        const bool constantW = r.p(0.3);
        std::vector<ProcessedVertex> pv;
        std::vector<Vertex> verts;
        const int kind = int(r.i64(0, 3));
        const int n = int(r.i64(3, 90));
        int64_t cx = r.i64(-40 * one, int64_t(W + 40) * one), cy = r.i64(-40 * one, int64_t(H + 40) * one);
        for (int k = 0; k < n; ++k) {
            int64_t sx, sy;
            switch (kind) {
                case 0:  // tiny: within a few pixels of a centre
                    sx = cx + r.i64(-3 * one, 3 * one);
                    sy = cy + r.i64(-3 * one, 3 * one);
                    break;
                case 1:  // on the pixel-centre grid: edges through samples (top-left rule)
                    sx = cx + (r.i64(-4, 4) << s) + (r.p(0.8) ? half : 0);
                    sy = cy + (r.i64(-4, 4) << s) + (r.p(0.8) ? half : 0);
                    sx -= sx & (one - 1), sy -= sy & (one - 1);
                    sx += half, sy += half;
                    break;
                case 2:  // anywhere in the guard band
                    sx = r.i64(-guard, guard);
                    sy = r.i64(-guard, guard);
                    break;
                default:  // the target and around it
                    sx = r.i64(-64 * one, int64_t(W + 64) * one);
                    sy = r.i64(-64 * one, int64_t(H + 64) * one);
                    break;
            }
            if (k >= 2 && r.p(0.08)) {  // collinear with the previous two: zero area
                sx = 2 * pv[k - 1].sx - pv[k - 2].sx;
                sy = 2 * pv[k - 1].sy - pv[k - 2].sy;
                if (std::abs(sx) > guard || std::abs(sy) > guard) sx = pv[k - 1].sx, sy = pv[k - 1].sy;
            }
            if (k >= 1 && r.p(0.05)) sx = pv[k - 1].sx, sy = pv[k - 1].sy;  // repeated
            if (k >= 1 && r.p(0.1)) sy = pv[k - 1].sy;  // a horizontal edge
            if (k >= 1 && r.p(0.1)) sx = pv[k - 1].sx;  // a vertical edge
            ProcessedVertex v = vertexAt(r, s, sx, sy, constantW);
            // Vertices the SIMD lanes must hand to clipAndSetup.
            const double odd = r.f(0.0f, 1.0f);
            if (odd < 0.02) v.valid = false;
            else if (odd < 0.04) v.wz = std::numeric_limits<float>::quiet_NaN();
            else if (odd < 0.06) v.invW = std::numeric_limits<float>::infinity();
            else if (odd < 0.08) v.wx = -std::numeric_limits<float>::infinity();
            else if (odd < 0.10) v.outcode = 1u << r.i64(0, 5);
            v.unclipped = unclippedVertex(v);
            pv.push_back(v);
            Vertex sv;
            sv.diffuse = Rgba8{uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)),
                               uint8_t(r.i64(0, 255))};
            sv.specular = Rgba8{uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)),
                                uint8_t(r.i64(0, 255))};
            verts.push_back(sv);
        }
        // Clipped vertices keep the clip position of their window position, so that the
        // clipper has something consistent to cut (the result is compared, not judged).
        const Primitive prim = Primitive(r.i64(0, 2));
        std::vector<uint32_t> indices;
        if (r.p(0.7)) {
            const int count = int(r.i64(3, 120));
            for (int k = 0; k < count; ++k) indices.push_back(uint32_t(r.i64(0, n - 1)));
        }
        const uint32_t vertexCount = uint32_t(indices.empty() ? pv.size() : indices.size());
        const uint32_t triangles = triangleCount(prim, vertexCount);

        // ---- the reference: clipAndSetup per triangle, as the reference path calls it --
        std::vector<SetupTriangle> ref, fast;
        std::vector<Plane> refPool, fastPool;
        GeometryCounters refGc, fastGc;
        referenceSetup(dc, prim, triangles, indices, verts, pv.data(), ref, refPool, refGc);
        // ---- the fast setup, in one call and split at a random point -------------------
        const uint32_t split = triangles ? uint32_t(r.i64(0, triangles)) : 0;
        setupTrianglesFast(dc, prim, 0, split, indices, verts, pv.data(), fast, fastPool, fastGc);
        setupTrianglesFast(dc, prim, split, triangles, indices, verts, pv.data(), fast, fastPool,
                           fastGc);

        std::ostringstream whereText;  // (not operator+: GCC 12's -Wrestrict false alarm)
        whereText << "seed " << seed << ", round " << round;
        const std::string where = whereText.str();
        ASSERT_NO_FATAL_FAILURE(expectSameSetup(ref, fast, refGc, fastGc, where));
        ASSERT_EQ(refPool.size(), fastPool.size()) << where;
        for (size_t k = 0; k < refPool.size(); ++k)
            ASSERT_TRUE(sameBits(refPool[k].c, fastPool[k].c) &&
                        sameBits(refPool[k].dx, fastPool[k].dx) &&
                        sameBits(refPool[k].dy, fastPool[k].dy))
                << where << ", texture plane " << k;
    }
}

TEST(SetupSimd, FourTriangleLanesEqualTheReferenceSetupFieldByField) {
    if (const char* s = std::getenv("RETROGLASS_SETUP_SEED")) {
        runRounds(std::strtoull(s, nullptr, 10), 1);
        return;
    }
    for (uint64_t seed = 1; seed <= 6000; ++seed) {
        runRounds(seed, 1);
        if (::testing::Test::HasFatalFailure()) return;
    }
}

// The lanes must keep the reference's culling counts exactly: a known case per rule.
TEST(SetupSimd, CullModesAndZeroAreaAreCountedLikeTheReference) {
    tex::TextureUnits tu;
    Framebuffer fb(64, 64, DepthFormat::None);
    for (CullMode cull : {CullMode::None, CullMode::CW, CullMode::CCW}) {
        PipelineState st;
        st.cull = cull;
        DrawContext dc = makeDrawContext(st, fb, tu, Path::Fast, VertexSpace::Untransformed,
                                         Viewport{0, 0, 64, 64, 0.0f, 1.0f}, Rect{}, 4);
        Rng r(7);
        auto at = [&](int x, int y) { return vertexAt(r, 4, int64_t(x) << 4, int64_t(y) << 4, true); };
        // clockwise on screen (y down), counter-clockwise, zero area (collinear), zero area
        // (repeated vertex), outside the target.
        std::vector<ProcessedVertex> pv = {at(2, 2), at(20, 2), at(2, 20),   // CW
                                           at(2, 2), at(2, 20), at(20, 2),   // CCW
                                           at(1, 1), at(5, 5), at(9, 9),     // collinear
                                           at(3, 3), at(3, 3), at(9, 4),     // repeated
                                           at(-9, -9), at(-2, -9), at(-9, -2)};  // outside
        for (ProcessedVertex& v : pv) v.unclipped = unclippedVertex(v);
        std::vector<Vertex> verts(pv.size());
        std::vector<SetupTriangle> out;
        std::vector<Plane> pool;
        GeometryCounters gc;
        setupTrianglesFast(dc, Primitive::TriangleList, 0, 5, {}, verts, pv.data(), out, pool, gc);
        const uint64_t drawn = cull == CullMode::None ? 2 : 1;
        EXPECT_EQ(gc.submitted, 5u);
        EXPECT_EQ(gc.drawn, drawn) << int(cull);
        EXPECT_EQ(gc.culled, 5 - drawn) << int(cull);
        ASSERT_EQ(out.size(), drawn);
        // Every drawn triangle is rasterized clockwise: vertex 0 first, area > 0.
        for (const SetupTriangle& t : out) {
            EXPECT_EQ(t.minX, 2);
            EXPECT_EQ(t.minY, 2);
            EXPECT_EQ(t.A[0] * t.B[1] - t.A[1] * t.B[0] > 0, true);
        }
    }
}

// The eight-vertex pass (processVerticesFast) against processVertexInto, field by field:
// random perspective and orthographic transforms and viewports, points behind the eye,
// near the w = 0 plane, far outside the guard band, and NaN/Inf positions.
TEST(SetupSimd, EightVertexLanesEqualTheScalarVertexStage) {
    tex::TextureUnits tu;
    Rng r(11);
    for (int round = 0; round < 400; ++round) {
        const int W = int(r.i64(8, 700)), H = int(r.i64(8, 500));
        Framebuffer fb(W, H, DepthFormat::None);
        PipelineState st;
        const Viewport vp{int32_t(r.i64(0, W / 2)), int32_t(r.i64(0, H / 2)), int32_t(r.i64(1, W / 2)),
                          int32_t(r.i64(1, H / 2)), r.f(0.0f, 0.5f), r.f(0.5f, 1.0f)};
        const int s = r.p(0.5) ? 4 : 8;
        const DrawContext dc = makeDrawContext(st, fb, tu, Path::Fast,
                                               VertexSpace::Untransformed, vp, Rect{}, s);
        glm::mat4 m = r.p(0.5) ? glm::perspectiveLH_ZO(r.f(0.3f, 2.0f), r.f(0.5f, 2.0f),
                                                       r.f(0.01f, 1.0f), r.f(2.0f, 100.0f))
                               : glm::orthoLH_ZO(0.0f, float(W), float(H), 0.0f, 0.0f, 1.0f);
        for (int c = 0; c < 4; ++c)
            for (int k = 0; k < 4; ++k)
                if (r.p(0.1)) m[c][k] += r.f(-1.0f, 1.0f);
        const int n = int(r.i64(0, 70));
        std::vector<Vertex> verts(size_t(n) + 3);
        for (Vertex& v : verts) {
            const float span = r.p(0.2) ? 1e6f : r.p(0.5) ? 4.0f : float(W);
            v.position = {r.f(-span, span), r.f(-span, span), r.f(-span, span), 1.0f};
            if (r.p(0.1)) v.position.z = 0.0f;
            const float odd = r.f(0.0f, 1.0f);
            if (odd < 0.03f) v.position.x = std::numeric_limits<float>::quiet_NaN();
            else if (odd < 0.06f) v.position.y = std::numeric_limits<float>::infinity();
            else if (odd < 0.08f) v.position.z = 3e38f;
            v.diffuse = Rgba8{uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)),
                              uint8_t(r.i64(0, 255))};
            v.specular = Rgba8{uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)),
                               uint8_t(r.i64(0, 255))};
        }
        const glm::mat4 wv(1.0f);
        const glm::mat3 nm(1.0f);
        std::vector<ProcessedVertex> ref(verts.size()), fast(verts.size());
        for (size_t k = 0; k < verts.size(); ++k) processVertexInto(dc, m, wv, nm, verts[k], ref[k]);
        const size_t begin = size_t(r.i64(0, 3));
        for (size_t k = 0; k < begin; ++k) fast[k] = ref[k];
        processVerticesFast(dc, m, wv, nm, verts, begin, verts.size(), fast.data());
        for (size_t k = 0; k < verts.size(); ++k) {
            const ProcessedVertex &a = ref[k], &b = fast[k];
            const std::string where = "round " + std::to_string(round) + ", vertex " +
                                      std::to_string(k);
            EXPECT_TRUE(sameBits(a.clip, b.clip)) << where;
            EXPECT_TRUE(sameBits(a.wx, b.wx) && sameBits(a.wy, b.wy) && sameBits(a.wz, b.wz) &&
                        sameBits(a.invW, b.invW))
                << where;
            EXPECT_EQ(a.sx, b.sx) << where;
            EXPECT_EQ(a.sy, b.sy) << where;
            EXPECT_EQ(a.outcode, b.outcode) << where;
            EXPECT_EQ(a.valid, b.valid) << where;
            EXPECT_EQ(a.unclipped, b.unclipped) << where;
            for (int c = 0; c < kColorAttrs; ++c) EXPECT_TRUE(sameBits(a.attr[c], b.attr[c])) << where;
            if (::testing::Test::HasFailure()) return;
        }
    }
}

// The compact records (FastVertex: processVerticesCompact, setupTrianglesCompact) against
// the reference vertex stage and setup: every record field against processVertexInto's,
// and every SetupTriangle and counter against clipAndSetup on processVertexInto's vertices.
// Random transforms, viewports, scissors and states; small triangles on screen, some
// reaching past the guard band or behind the eye (the records' clipAndSetup fallback,
// which recomputes the full vertices) and NaN/Inf positions; the vertex pass and the
// setup each split at a random point.
TEST(SetupSimd, CompactVertexRecordsGiveTheReferenceSetup) {
    tex::TextureUnits tu;
    Rng r(23);
    uint64_t clipped = 0, drawn = 0, culled = 0, invalid = 0;
    for (int round = 0; round < 1500; ++round) {
        const int W = int(r.i64(8, 700)), H = int(r.i64(8, 500));
        Framebuffer fb(W, H, r.p(0.5) ? DepthFormat::D24 : DepthFormat::None);
        PipelineState st;
        st.cull = CullMode(r.i64(0, 2));
        st.shade = r.p(0.8) ? ShadeMode::Gouraud : ShadeMode::Flat;
        st.perspectiveColor = uint8_t(r.p(0.7));
        st.specularEnable = uint8_t(r.p(0.3));
        st.depthTest = uint8_t(r.p(0.6));
        st.scissorTest = uint8_t(r.p(0.3));
        const Viewport vp{int32_t(r.i64(0, W / 2)), int32_t(r.i64(0, H / 2)), int32_t(r.i64(1, W)),
                          int32_t(r.i64(1, H)), r.f(0.0f, 0.5f), r.f(0.5f, 1.0f)};
        const Rect scissor{int32_t(r.i64(-20, W)), int32_t(r.i64(-20, H)), int32_t(r.i64(0, W)),
                           int32_t(r.i64(0, H))};
        const int s = r.p(0.5) ? 4 : 8;
        const DrawContext dc = makeDrawContext(st, fb, tu, Path::Fast,
                                               VertexSpace::Untransformed, vp, scissor, s);
        ASSERT_TRUE(compactVertices(dc));
        const bool persp = r.p(0.5);
        glm::mat4 m = persp ? glm::perspectiveLH_ZO(r.f(0.3f, 2.0f), r.f(0.5f, 2.0f),
                                                    r.f(0.01f, 1.0f), r.f(2.0f, 100.0f))
                            : glm::orthoLH_ZO(0.0f, float(W), float(H), 0.0f, 0.0f, 1.0f);
        if (r.p(0.3))
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 4; ++k)
                    if (r.p(0.1)) m[c][k] += r.f(-0.5f, 0.5f);
        const int n = int(r.i64(3, 90));
        std::vector<Vertex> verts(static_cast<size_t>(n));
        float cx = persp ? r.f(-1.0f, 1.0f) : r.f(0.0f, float(W));
        float cy = persp ? r.f(-1.0f, 1.0f) : r.f(0.0f, float(H));
        const float step = persp ? 0.02f : 3.0f;
        for (Vertex& v : verts) {
            // A walk of small steps: small triangles, now and then a far point.
            cx += r.f(-step, step);
            cy += r.f(-step, step);
            const float z = persp ? r.f(1.0f, 3.0f) : r.f(0.0f, 1.0f);  // inside near and far
            v.position = {cx, cy, z, 1.0f};
            if (persp) v.position = {cx * z, cy * z, z, 1.0f};
            const float odd = r.f(0.0f, 1.0f);
            if (odd < 0.02f) v.position.x = std::numeric_limits<float>::quiet_NaN();
            else if (odd < 0.03f) v.position.y = std::numeric_limits<float>::infinity();
            else if (odd < 0.06f) v.position.x = r.f(-1e6f, 1e6f);
            else if (odd < 0.08f) v.position.z = -r.f(0.0f, 5.0f);  // behind the eye
            else if (odd < 0.09f) v.position.z = 1e4f;  // past the far plane
            v.diffuse = Rgba8{uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)),
                              uint8_t(r.i64(0, 255))};
            v.specular = Rgba8{uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)),
                               uint8_t(r.i64(0, 255))};
        }
        const glm::mat4 wv(1.0f);
        const glm::mat3 nm(1.0f);
        const std::string where = "round " + std::to_string(round);

        // ---- the vertex records --------------------------------------------------------
        std::vector<ProcessedVertex> pv(verts.size());
        for (size_t k = 0; k < verts.size(); ++k) processVertexInto(dc, m, wv, nm, verts[k], pv[k]);
        std::vector<FastVertex> fv(verts.size());
        const size_t vsplit = size_t(r.i64(0, n));
        processVerticesCompact(dc, m, wv, nm, VertexSource{verts, {}}, 0, vsplit, fv.data());
        processVerticesCompact(dc, m, wv, nm, VertexSource{verts, {}}, vsplit, verts.size(), fv.data());
        for (size_t k = 0; k < verts.size(); ++k) {
            const ProcessedVertex& a = pv[k];
            const FastVertex& b = fv[k];
            ASSERT_EQ(a.sx, int64_t(b.sx)) << where << ", vertex " << k;
            ASSERT_EQ(a.sy, int64_t(b.sy)) << where << ", vertex " << k;
            ASSERT_TRUE(sameBits(a.wz, b.wz) && sameBits(a.invW, b.invW)) << where << ", " << k;
            ASSERT_EQ(a.unclipped, b.unclipped == 1u) << where << ", vertex " << k;
            ASSERT_TRUE(b.diffuse == verts[k].diffuse && b.specular == verts[k].specular);
        }

        // ---- setup -----------------------------------------------------------------------
        const Primitive prim = Primitive(r.i64(0, 2));
        std::vector<uint32_t> indices;
        if (r.p(0.6)) {
            const int count = int(r.i64(3, 120));
            uint32_t base = 0;
            for (int k = 0; k < count; ++k) {
                base = uint32_t(std::clamp<int64_t>(int64_t(base) + r.i64(-2, 3), 0, n - 1));
                indices.push_back(base);
            }
        }
        const uint32_t vertexCount = uint32_t(indices.empty() ? pv.size() : indices.size());
        const uint32_t triangles = triangleCount(prim, vertexCount);
        std::vector<SetupTriangle> ref, fast;
        std::vector<Plane> refPool, fastPool;
        GeometryCounters refGc, fastGc;
        referenceSetup(dc, prim, triangles, indices, verts, pv.data(), ref, refPool, refGc);
        const uint32_t split = triangles ? uint32_t(r.i64(0, triangles)) : 0;
        setupTrianglesCompact(dc, prim, 0, split, indices, VertexSource{verts, {}}, fv.data(), m, wv, nm, fast,
                              fastPool, fastGc);
        setupTrianglesCompact(dc, prim, split, triangles, indices, VertexSource{verts, {}}, fv.data(), m, wv, nm,
                              fast, fastPool, fastGc);
        ASSERT_NO_FATAL_FAILURE(expectSameSetup(ref, fast, refGc, fastGc, where));
        ASSERT_EQ(refPool.size(), fastPool.size()) << where;
        clipped += refGc.clipped;
        drawn += refGc.drawn;
        culled += refGc.culled;
        invalid += refGc.invalid;
    }
    // The rounds reach every branch: SIMD lanes, the clipping fallback, culling, invalid.
    EXPECT_GT(drawn, 5000u);
    EXPECT_GT(clipped, 1000u);
    EXPECT_GT(culled, 1000u);
    EXPECT_GT(invalid, 1000u);
    std::printf("compact records: %llu drawn, %llu clipped, %llu culled, %llu invalid\n",
                (unsigned long long)drawn, (unsigned long long)clipped,
                (unsigned long long)culled, (unsigned long long)invalid);
}

// Draws of more triangles than one batch of chunks holds (the fast path sets up and
// rasterizes 1024-triangle chunks in batches of at least 8; device.cpp) and, on one
// thread, chunks whose vertices are transformed just before them: overlapping blended
// triangles, so that any change of order would change bytes, through indices that grow
// along the mesh (interleaved vertex transform) and random ones (all vertices at the first
// chunk), against the reference on 1, 2 and 3 threads.
TEST(PathsAgree, DrawsOfSeveralChunkBatchesGiveIdenticalBytesOnAnyThreadCount) {
    tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 3);
    Rng r(5);
    const int W = 160, H = 120;
    std::vector<Vertex> verts;
    float x = W / 2, y = H / 2;  // a random walk: neighbours in vertex order lie close
    for (int k = 0; k < 9000; ++k) {
        x = std::fmod(x + r.f(-3.0f, 3.0f) + W + 16.0f, W + 16.0f);
        y = std::fmod(y + r.f(-3.0f, 3.0f) + H + 16.0f, H + 16.0f);
        Vertex v;
        v.position = {x - 8.0f, y - 8.0f, r.f(0.0f, 1.0f), 1.0f};
        v.diffuse = Rgba8{uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)), uint8_t(r.i64(0, 255)),
                          uint8_t(r.i64(0, 255))};
        verts.push_back(v);
    }
    for (bool randomIndices : {false, true}) {
        // Triangles of nearby vertices (a few pixels; a few cross the whole target where the
        // walk wraps), 3 × 9000 = 27,000 of them: 27 chunks.
        std::vector<uint32_t> indices;
        for (uint32_t k = 0; k < 3 * 9000; ++k) {
            const uint32_t base = randomIndices ? uint32_t(r.i64(0, 8999)) : k / 3;
            indices.push_back(base);
            indices.push_back(uint32_t(std::min<int64_t>(8999, base + r.i64(1, 3))));
            indices.push_back(uint32_t(std::min<int64_t>(8999, base + r.i64(1, 5))));
        }
        PipelineState st;
        st.cull = CullMode::None;
        st.shade = ShadeMode::Gouraud;
        st.blend = 1;
        st.srcBlend = BlendFactor::SrcAlpha;
        st.dstBlend = BlendFactor::InvSrcAlpha;
        st.depthTest = 0;
        std::string expected;
        Counters expectedCounters;
        for (int threads : {0, 1, 2, 3}) {  // 0: the reference path
            Device dev(profile(ProfileId::GeForce256), W, H, DepthFormat::None,
                       {threads == 0 ? Path::Reference : Path::Fast, std::max(threads, 1)});
            dev.setState(st);
            dev.setTransforms(glm::mat4(1.0f), glm::mat4(1.0f),
                              glm::orthoLH_ZO(0.0f, float(W), float(H), 0.0f, 0.0f, 1.0f));
            dev.beginFrame();
            dev.clear(true, Rgba8{10, 20, 30, 40}, false, 1.0f);
            dev.draw(Primitive::TriangleList, VertexSpace::Untransformed, verts, indices);
            const Framebuffer& fb = dev.framebuffer();
            const std::string bytes(reinterpret_cast<const char*>(fb.color().data()),
                                    fb.color().size_bytes());
            if (threads == 0) {
                expected = bytes;
                expectedCounters = dev.counters();
                EXPECT_GT(expectedCounters.fragmentsWritten, 100000u);
                continue;
            }
            EXPECT_TRUE(bytes == expected) << threads << " threads, random indices "
                                           << randomIndices;
            EXPECT_EQ(dev.counters().trianglesDrawn, expectedCounters.trianglesDrawn);
            EXPECT_EQ(dev.counters().fragmentsWritten, expectedCounters.fragmentsWritten);
            EXPECT_EQ(dev.counters().blendOps, expectedCounters.blendOps);
        }
    }
}

// The index check (a vectorized maximum, then a search only when it fails): a draw with
// an index past its vertices is refused before it counts or writes anything, and the
// message names the first bad index, wherever it lies (in the first 16, in the middle of
// a long list, at the very end), on both paths.
TEST(PathsAgree, AnIndexPastTheVerticesIsRefusedNamingTheFirstOne) {
    std::vector<Vertex> verts(3);
    verts[0].position = {-1.0f, -1.0f, 0.5f, 1.0f};
    verts[1].position = {1.0f, -1.0f, 0.5f, 1.0f};
    verts[2].position = {0.0f, 1.0f, 0.5f, 1.0f};
    for (Path path : {Path::Reference, Path::Fast})
        for (size_t at : {size_t(1), size_t(1000), size_t(2999)}) {
            Device dev(profile(ProfileId::GeForce256), 32, 32, DepthFormat::None, {path, 1});
            std::vector<uint32_t> indices(3000);
            for (size_t k = 0; k < indices.size(); ++k) indices[k] = uint32_t(k % 3);
            indices[at] = 3;                          // the first bad one: named
            if (at + 1 < indices.size()) indices[at + 1] = 7;  // a larger one after it
            std::string message;
            try {
                dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, verts, indices);
            } catch (const InvalidState& e) {
                message = e.what();
            }
            EXPECT_NE(message.find("index 3 is past the 3 vertices"), std::string::npos)
                << "at " << at << ": '" << message << "'";
            EXPECT_EQ(dev.counters().drawCalls, 0u);
            indices[at] = 2;  // now only the 7 (or nothing) is wrong
            message.clear();
            try {
                dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, verts, indices);
            } catch (const InvalidState& e) {
                message = e.what();
            }
            if (at + 1 < indices.size())
                EXPECT_NE(message.find("index 7 is past"), std::string::npos) << message;
            else
                EXPECT_EQ(message, "") << "a valid draw was refused";
        }
}

}  // namespace
}  // namespace rg::testing
