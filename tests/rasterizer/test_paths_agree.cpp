// Two paths, one answer: the reference path and the fast path (tiles, threads, span fill,
// specialised quad loops) must give the same framebuffer bytes and the same counters for
// any input, and the fast path the same bytes for any thread count.
//
// Reproduce a failure: the message names the seed, session and draw; run
//   build-raster/bin/test_rasterizer --gtest_filter='PathsAgree.*'
// with RETROGLASS_PATHS_SEED=<seed> in the environment to replay that session alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <tbb/global_control.h>

#include "raster_test_util.h"

namespace rg::testing {
namespace {

using namespace rg::raster;

// The two triangles of each cell of a grid of gx × gy cells whose (gx + 1) × (gy + 1)
// vertices are numbered row by row: (a, b, d) and (a, d, c) with b right of a, c below.
std::vector<uint32_t> gridTriangles(int gx, int gy) {
    std::vector<uint32_t> indices;
    for (int j = 0; j < gy; ++j)
        for (int i = 0; i < gx; ++i) {
            const uint32_t a = uint32_t(j * (gx + 1) + i), b = a + 1, c = a + uint32_t(gx) + 1,
                           d = c + 1;
            indices.insert(indices.end(), {a, b, d, a, d, c});
        }
    return indices;
}

// The view and projection of the mesh tests: a perspective camera at z = −3 with its
// near plane at 0.5 (z < −2.5 is clipped, z < −3 behind the eye), or window pixels with y
// down.
std::pair<glm::mat4, glm::mat4> meshCamera(bool perspective, int w, int h) {
    if (perspective)
        return {glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 3.0f)),
                glm::perspectiveLH_ZO(1.0f, float(w) / float(h), 0.5f, 20.0f)};
    return {glm::mat4(1.0f), glm::orthoLH_ZO(0.0f, float(w), float(h), 0.0f, 0.0f, 1.0f)};
}

// The geometry counters of `c` added to `sum`.
void addGeometry(Counters& sum, const Counters& c) {
    sum.trianglesDrawn += c.trianglesDrawn;
    sum.trianglesCulled += c.trianglesCulled;
    sum.trianglesClipped += c.trianglesClipped;
    sum.trianglesInvalid += c.trianglesInvalid;
}

// The colour and depth bytes and the counters of the two devices, or where they differ.
::testing::AssertionResult sameFrameAndCounters(const Device& ref, const Device& fast,
                                                const std::string& where) {
    const Framebuffer &a = ref.framebuffer(), &b = fast.framebuffer();
    if (std::memcmp(a.color().data(), b.color().data(), a.color().size_bytes()) != 0 ||
        !std::equal(a.depth().begin(), a.depth().end(), b.depth().begin()))
        return ::testing::AssertionFailure()
               << "paths differ after " << where << ": " << firstDifference(a, b);
    if (!sameCounters(ref.counters(), fast.counters()))
        return ::testing::AssertionFailure()
               << "counters differ after " << where << "\nreference:\n"
               << ref.counters().toString() << "fast:\n" << fast.counters().toString();
    return ::testing::AssertionSuccess();
}

// One session: a pair of devices receiving the same `draws` random commands.
int texturedDraws = 0;

void runSession(uint64_t seed, int draws, int& totalDraws, Counters& sum) {
    Rng r(seed);
    const int sizes[][2] = {{97, 71}, {64, 64}, {130, 33}, {17, 9}, {200, 150}};
    const auto& sz = sizes[r.i(0, 4)];
    const int w = sz[0], h = sz[1];
    const Profile& prof = profile(r.p(0.7) ? ProfileId::GeForce256 : ProfileId::GeForce8800);
    const DepthFormat fmt = DepthFormat(r.i(0, 2));
    Device ref(prof, w, h, fmt, {Path::Reference, 1});
    Device fast(prof, w, h, fmt, {Path::Fast, r.i(1, 3)});  // 1: the unbinned loop
    Device* both[2] = {&ref, &fast};
    const Rgba8 background{r.byte(), r.byte(), r.byte(), r.byte()};
    for (Device* d : both) d->clear(true, background, true, 1.0f);
    for (int k = 0; k < draws; ++k, ++totalDraws) {
        const std::string where = "seed " + std::to_string(seed) + " draw " + std::to_string(k) +
                                  " (" + std::to_string(w) + "x" + std::to_string(h) + ", " +
                                  std::string(prof.name) + ")";
        PipelineState s = randomState(r);
        Viewport vp{0, 0, w, h, 0.0f, 1.0f};
        if (r.p(0.2)) {
            vp.x = r.i(0, w - 1);
            vp.y = r.i(0, h - 1);
            vp.width = r.i(1, w - vp.x);
            vp.height = r.i(1, h - vp.y);
            vp.minZ = r.f(0.0f, 0.5f);
            vp.maxZ = r.f(0.5f, 1.0f);
        }
        Rect sc{r.i(-5, w), r.i(-5, h), r.i(0, w), r.i(0, h)};
        glm::mat4 proj = r.p(0.7) ? glm::perspectiveLH_ZO(r.f(0.5f, 2.0f), r.f(0.5f, 2.0f),
                                                          r.f(0.1f, 1.0f), r.f(5.0f, 50.0f))
                                  : glm::orthoLH_ZO(-3.0f, 3.0f, -3.0f, 3.0f, -1.0f, 8.0f);
        glm::mat4 view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 3.0f));
        glm::mat4 world = glm::rotate(glm::mat4(1.0f), r.f(0.0f, 6.28f), glm::vec3(0.3f, 1.0f, 0.1f));
        const VertexSpace space = r.p(0.5) ? VertexSpace::Pretransformed : VertexSpace::Untransformed;
        const Primitive prim = Primitive(r.i(0, 2));
        const int n = r.i(3, 12);
        std::vector<Vertex> verts;
        for (int i = 0; i < n; ++i) {
            int kind = r.p(0.6) ? 0 : r.i(1, 5);
            verts.push_back(randomVertex(r, space, kind, w, h, verts.empty() ? nullptr : &verts.back()));
        }
        std::vector<uint32_t> indices;
        if (r.p(0.3))
            for (int i = 0; i < r.i(3, 15); ++i) indices.push_back(uint32_t(r.i(0, n - 1)));
        // Sometimes a texture stage that reads only the diffuse, specular and factor
        // colours: not pass-through, so the quads go through FragmentQuad, helper pixels
        // and TextureUnits::shadeQuad on both paths.
        tex::StageState stage;
        if (r.p(0.2)) {
            const tex::TextureOp ops[] = {tex::TextureOp::Modulate, tex::TextureOp::Add,
                                          tex::TextureOp::SelectArg1, tex::TextureOp::Subtract};
            const uint8_t args[] = {tex::arg::Diffuse, tex::arg::Specular, tex::arg::TFactor};
            stage.colorOp = ops[r.i(0, 3)];
            stage.colorArg1 = args[r.i(0, 2)];
            stage.colorArg2 = args[r.i(0, 2)];
            stage.alphaOp = tex::TextureOp::SelectArg1;
            stage.alphaArg1 = args[r.i(0, 2)];
        }
        const Rgba8 factor{r.byte(), r.byte(), r.byte(), r.byte()};
        const bool doClear = r.p(0.03);
        const Rgba8 clearColor{r.byte(), r.byte(), r.byte(), r.byte()};
        const float clearDepth = r.f(0.0f, 1.0f);

        texturedDraws += stage.colorOp != tex::TextureOp::Disable;
        for (Device* d : both) {
            d->setState(s);
            d->setViewport(vp);
            d->setScissor(sc);
            d->setTransforms(world, view, proj);
            d->textureUnits().setStage(0, stage);
            d->textureUnits().setTextureFactor(factor);
            if (doClear) d->clear(true, clearColor, true, clearDepth);
            d->draw(prim, space, verts, indices);
        }
        if (std::memcmp(ref.framebuffer().color().data(), fast.framebuffer().color().data(),
                        ref.framebuffer().color().size_bytes()) != 0 ||
            ref.framebuffer().depth().size() != fast.framebuffer().depth().size() ||
            !std::equal(ref.framebuffer().depth().begin(), ref.framebuffer().depth().end(),
                        fast.framebuffer().depth().begin())) {
            FAIL() << "paths differ after " << where << ": "
                   << firstDifference(ref.framebuffer(), fast.framebuffer());
        }
        ASSERT_TRUE(sameCounters(ref.counters(), fast.counters()))
            << "counters differ after " << where << "\nreference:\n"
            << ref.counters().toString() << "fast:\n" << fast.counters().toString();
    }
    const Counters& c = ref.counters();
    sum.trianglesSubmitted += c.trianglesSubmitted;
    sum.trianglesClipped += c.trianglesClipped;
    sum.trianglesInvalid += c.trianglesInvalid;
    sum.trianglesCulled += c.trianglesCulled;
    sum.trianglesDrawn += c.trianglesDrawn;
    sum.fragmentsGenerated += c.fragmentsGenerated;
    sum.fragmentsWritten += c.fragmentsWritten;
    sum.blendOps += c.blendOps;
    EXPECT_EQ(c.trianglesSubmitted, c.trianglesInvalid + c.trianglesCulled + c.trianglesDrawn)
        << "seed " << seed;
}

TEST(PathsAgree, TenThousandRandomDrawsGiveIdenticalBytesAndCounters) {
    int total = 0;
    Counters sum;
    if (const char* one = std::getenv("RETROGLASS_PATHS_SEED")) {
        runSession(std::strtoull(one, nullptr, 10), 250, total, sum);
        return;
    }
    for (uint64_t seed = 1; total < 10000 && !HasFatalFailure(); ++seed)
        runSession(seed, 250, total, sum);
    EXPECT_GE(total, 10000);
    // The random input must have reached every outcome, or the comparison proves little.
    EXPECT_GT(sum.trianglesClipped, 1000u);
    EXPECT_GT(sum.trianglesInvalid, 1000u);
    EXPECT_GT(sum.trianglesCulled, 1000u);
    EXPECT_GT(sum.trianglesDrawn, 10000u);
    EXPECT_GT(sum.fragmentsWritten, 1000000u);
    EXPECT_GT(sum.blendOps, 100000u);
    EXPECT_GT(texturedDraws, 1000);
    std::printf("[ stats    ] %s", sum.toString().c_str());
}

// Dense meshes of triangles a pixel or two across, the case the fast path sends through
// its single-quad kernel and its batched triangle setup: jittered grids at random
// positions (some crossing the target's edges), random states, both vertex spaces, and
// 1–3 threads. The random draws above rarely make triangles this small.
TEST(PathsAgree, DenseMeshesOfTinyTrianglesGiveIdenticalBytesAndCounters) {
    int draws = 0;
    uint64_t drawn = 0;
    for (uint64_t seed = 1; seed <= 60 && !HasFatalFailure(); ++seed) {
        Rng r(7000 + seed);
        const int w = r.i(9, 90), h = r.i(9, 70);
        const DepthFormat fmt = DepthFormat(r.i(0, 2));
        Device ref(profile(ProfileId::GeForce256), w, h, fmt, {Path::Reference, 1});
        Device fast(profile(ProfileId::GeForce256), w, h, fmt, {Path::Fast, r.i(1, 3)});
        const Rgba8 background{r.byte(), r.byte(), r.byte(), r.byte()};
        for (Device* d : {&ref, &fast}) d->clear(true, background, true, 1.0f);
        for (int k = 0; k < 20; ++k, ++draws) {
            PipelineState s = randomState(r);
            if (r.p(0.5)) s.cull = CullMode::None;
            const VertexSpace space = r.p(0.5) ? VertexSpace::Pretransformed : VertexSpace::Untransformed;
            // Cells of `cell` pixels, vertices jittered by up to `jitter` pixels.
            const float cell = r.p(0.5) ? 2.0f : r.f(0.3f, 3.0f);
            const float jitter = r.p(0.4) ? 0.0f : r.f(0.0f, 0.6f);
            const float x0 = r.f(-4.0f, float(w) - 8.0f), y0 = r.f(-4.0f, float(h) - 8.0f);
            const int gx = r.i(1, 24), gy = r.i(1, 24);
            const bool flatW = r.p(0.5);
            std::vector<Vertex> verts;
            for (int j = 0; j <= gy; ++j)
                for (int i = 0; i <= gx; ++i) {
                    Vertex v;
                    float x = x0 + cell * float(i) + (jitter > 0 ? r.f(-jitter, jitter) : 0.0f);
                    float y = y0 + cell * float(j) + (jitter > 0 ? r.f(-jitter, jitter) : 0.0f);
                    if (r.p(0.5)) x = std::round(x), y = std::round(y);  // on pixel corners
                    const float z = r.f(0.0f, 1.0f), q = flatW ? 1.0f : r.f(0.2f, 3.0f);
                    if (space == VertexSpace::Pretransformed) {
                        v.position = {x, y, z, q};
                    } else {  // object space through the orthographic window transform below
                        v.position = {x, y, z, 1.0f};
                    }
                    v.diffuse = randomColor(r);
                    v.specular = Rgba8{r.byte(), r.byte(), r.byte(), r.byte()};
                    verts.push_back(v);
                }
            std::vector<uint32_t> indices;
            for (int j = 0; j < gy; ++j)
                for (int i = 0; i < gx; ++i) {
                    const uint32_t a = uint32_t(j * (gx + 1) + i), b = a + 1,
                                   c = a + uint32_t(gx) + 1, d = c + 1;
                    if (r.p(0.5))
                        indices.insert(indices.end(), {a, b, d, a, d, c});
                    else
                        indices.insert(indices.end(), {a, b, c, b, d, c});
                }
            const Rect scissor{r.i(0, w / 2), r.i(0, h / 2), w, h};
            for (Device* d : {&ref, &fast}) {
                d->setState(s);
                d->setViewport(Viewport{0, 0, w, h, 0.0f, 1.0f});
                d->setScissor(scissor);
                d->setTransforms(glm::mat4(1.0f), glm::mat4(1.0f),
                                 glm::orthoLH_ZO(0.0f, float(w), float(h), 0.0f, 0.0f, 1.0f));
                d->draw(Primitive::TriangleList, space, verts, indices);
            }
            const std::string where = "seed " + std::to_string(seed) + " draw " + std::to_string(k);
            ASSERT_TRUE(sameFrameAndCounters(ref, fast, where));
        }
        drawn += ref.counters().trianglesDrawn;
    }
    EXPECT_EQ(draws, 1200);
    EXPECT_GT(drawn, 100000u);
}

// Meshes of thousands of small triangles of untransformed, untextured vertices, the draws
// the fast path splits into one band of rows per thread (drawInBands, RowBand): grids in
// mesh order (the band selection's eight-triangle steps), shuffled (no locality), without
// indices and as strips (the scalar selection), some crossing the near plane, with a NaN
// or a far-out vertex (the clipper, whose triangles the first band counts), culling,
// scissors and viewports that leave bands empty, on 2–8 threads.
TEST(PathsAgree, MeshesDrawnInBandsOfRowsGiveIdenticalBytesAndCounters) {
    tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
    int draws = 0;
    Counters sum;
    for (uint64_t seed = 1; seed <= 24 && !HasFatalFailure(); ++seed) {
        Rng r(9100 + seed);
        const int w = r.i(24, 220), h = r.i(16, 170);
        const DepthFormat fmt = DepthFormat(r.i(0, 2));
        const int threads = std::array{2, 3, 4, 8}[size_t(r.i(0, 3))];
        Device ref(profile(ProfileId::GeForce256), w, h, fmt, {Path::Reference, 1});
        Device fast(profile(ProfileId::GeForce256), w, h, fmt, {Path::Fast, threads});
        const Rgba8 background{r.byte(), r.byte(), r.byte(), r.byte()};
        for (Device* d : {&ref, &fast}) d->clear(true, background, true, 1.0f);
        for (int k = 0; k < 4; ++k, ++draws) {
            PipelineState s = randomState(r);
            const bool perspective = r.p(0.35);
            // A grid of gx × gy cells, two triangles each, at least 4,096 triangles.
            const int gx = r.i(24, 96), gy = 2048 / gx + r.i(1, 24);
            const float cell = r.f(0.3f, 3.0f) * (perspective ? 4.0f / float(w) : 1.0f);
            const float x0 = perspective ? -0.5f * cell * float(gx) : r.f(-20.0f, float(w) - 10.0f);
            const float y0 = perspective ? -0.5f * cell * float(gy) : r.f(-40.0f, float(h) - 10.0f);
            std::vector<Vertex> verts;
            for (int j = 0; j <= gy; ++j)
                for (int i = 0; i <= gx; ++i) {
                    Vertex v;
                    const float x = x0 + cell * float(i) + r.f(-0.3f, 0.3f) * cell;
                    const float y = y0 + cell * float(j) + r.f(-0.3f, 0.3f) * cell;
                    // Perspective: the camera at z = −3, near plane 0.5: z < −2.5 is
                    // clipped, z < −3 behind the eye.
                    const float z = perspective ? (r.p(0.02) ? r.f(-3.5f, -2.4f) : r.f(-1.0f, 2.0f))
                                                : r.f(0.0f, 1.0f);
                    v.position = {x, y, z, 1.0f};
                    v.diffuse = randomColor(r);
                    v.specular = Rgba8{r.byte(), r.byte(), r.byte(), r.byte()};
                    verts.push_back(v);
                }
            if (r.p(0.2)) verts[size_t(r.i(0, int(verts.size()) - 1))].position.y = weird(r);
            if (r.p(0.2)) verts[size_t(r.i(0, int(verts.size()) - 1))].position.x = r.f(-1e5f, 1e5f);
            std::vector<uint32_t> indices = gridTriangles(gx, gy);
            Primitive prim = Primitive::TriangleList;
            const int order = r.i(0, 9);
            if (order >= 6 && order <= 7) {  // the triangles in random order
                std::vector<uint32_t> shuffled(indices.size());
                std::vector<uint32_t> tri(indices.size() / 3);
                for (uint32_t t = 0; t < tri.size(); ++t) tri[t] = t;
                std::shuffle(tri.begin(), tri.end(), r.g);
                for (size_t t = 0; t < tri.size(); ++t)
                    for (int e = 0; e < 3; ++e) shuffled[3 * t + size_t(e)] = indices[3 * tri[t] + size_t(e)];
                indices = std::move(shuffled);
            } else if (order == 8) {  // no indices: the vertices of each triangle in turn
                std::vector<Vertex> expanded;
                for (uint32_t i : indices) expanded.push_back(verts[i]);
                verts = std::move(expanded);
                indices.clear();
            } else if (order == 9) {  // a strip zigzagging along the grid's rows
                prim = r.p(0.5) ? Primitive::TriangleStrip : Primitive::TriangleFan;
                std::vector<uint32_t> strip;
                for (int j = 0; j < gy; j += 2)
                    for (int i = 0; i <= gx; ++i)
                        strip.insert(strip.end(), {uint32_t(j * (gx + 1) + i),
                                                   uint32_t((j + 1) * (gx + 1) + i)});
                indices = std::move(strip);
            }
            Viewport vp{0, 0, w, h, 0.0f, 1.0f};
            if (r.p(0.2)) {
                vp.y = r.i(0, h / 2);
                vp.height = r.i(1, h - vp.y);
            }
            const Rect scissor{r.i(-5, w / 2), r.i(-5, h / 2), r.i(0, w), r.i(0, h)};
            const auto [view, proj] = meshCamera(perspective, w, h);
            for (Device* d : {&ref, &fast}) {
                d->setState(s);
                d->setViewport(vp);
                d->setScissor(scissor);
                d->setTransforms(glm::mat4(1.0f), view, proj);
                d->draw(prim, VertexSpace::Untransformed, verts, indices);
            }
            const std::string where = "seed " + std::to_string(seed) + " draw " +
                                      std::to_string(k) + " (" + std::to_string(threads) +
                                      " threads, order " + std::to_string(order) + ")";
            ASSERT_TRUE(sameFrameAndCounters(ref, fast, where));
            addGeometry(sum, ref.counters());
        }
    }
    EXPECT_EQ(draws, 96);
    // Every kind of triangle the bands count differently came up.
    EXPECT_GT(sum.trianglesDrawn, 100000u);
    EXPECT_GT(sum.trianglesCulled, 10000u);
    EXPECT_GT(sum.trianglesClipped, 10u);
    EXPECT_GT(sum.trianglesInvalid, 0u);
}

// D3DFVF_XYZ | D3DFVF_DIFFUSE vertices draw what toVertex of each draws: the reference
// path fed Vertex records against the fast path fed the 16-byte records directly (the
// compact vertex pass, its clipping fallback, flat colours from the records; meshes large
// enough for bands) and against the reference path fed the 16-byte records (converted).
TEST(PathsAgree, XyzDiffuseVerticesDrawWhatTheirVerticesDraw) {
    tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 4);
    int draws = 0;
    Counters sum;
    for (uint64_t seed = 1; seed <= 16 && !HasFatalFailure(); ++seed) {
        Rng r(9300 + seed);
        const int w = r.i(16, 160), h = r.i(16, 120);
        const DepthFormat fmt = DepthFormat(r.i(0, 2));
        const int threads = r.i(1, 4);
        Device refFull(profile(ProfileId::GeForce256), w, h, fmt, {Path::Reference, 1});
        Device refXyz(profile(ProfileId::GeForce256), w, h, fmt, {Path::Reference, 1});
        Device fastXyz(profile(ProfileId::GeForce256), w, h, fmt, {Path::Fast, threads});
        const Rgba8 background{r.byte(), r.byte(), r.byte(), r.byte()};
        for (Device* d : {&refFull, &refXyz, &fastXyz}) d->clear(true, background, true, 1.0f);
        for (int k = 0; k < 6; ++k, ++draws) {
            const PipelineState s = randomState(r);
            const bool perspective = r.p(0.5);
            // Small random draws, or a grid of more than 4,096 triangles.
            const bool mesh = r.p(0.4);
            const int gx = r.i(24, 80), gy = 2048 / gx + r.i(1, 16);
            std::vector<VertexXyzDiffuse> xyz;
            std::vector<uint32_t> indices;
            Primitive prim = Primitive(r.i(0, 2));
            if (mesh) {
                prim = Primitive::TriangleList;
                const float cell = perspective ? 4.0f / float(gx) : r.f(0.5f, 2.5f);
                for (int j = 0; j <= gy; ++j)
                    for (int i = 0; i <= gx; ++i) {
                        VertexXyzDiffuse v;
                        const float x = cell * (float(i) + r.f(-0.3f, 0.3f)), y = cell * (float(j) + r.f(-0.3f, 0.3f));
                        v.position = perspective ? glm::vec3(x - 2.0f, y - 2.0f, r.p(0.02) ? r.f(-3.5f, -2.4f) : r.f(-1.0f, 2.0f))
                                                 : glm::vec3(x - 10.0f, y - 10.0f, r.f(0.0f, 1.0f));
                        v.diffuse = randomColor(r);
                        xyz.push_back(v);
                    }
                indices = gridTriangles(gx, gy);
            } else {
                const int n = r.i(3, 40);
                for (int i = 0; i < n; ++i) {
                    VertexXyzDiffuse v;
                    v.position = perspective ? glm::vec3(r.f(-2.5f, 2.5f), r.f(-2.5f, 2.5f), r.f(-4.0f, 4.0f))
                                             : glm::vec3(r.f(-10.0f, float(w) + 10.0f), r.f(-10.0f, float(h) + 10.0f), r.f(-0.2f, 1.2f));
                    v.diffuse = randomColor(r);
                    xyz.push_back(v);
                }
                if (r.p(0.3))
                    for (int i = 0; i < r.i(3, 30); ++i) indices.push_back(uint32_t(r.i(0, n - 1)));
            }
            if (r.p(0.2)) xyz[size_t(r.i(0, int(xyz.size()) - 1))].position.x = weird(r);
            std::vector<Vertex> full(xyz.size());
            for (size_t i = 0; i < xyz.size(); ++i) full[i] = toVertex(xyz[i]);
            const auto [view, proj] = meshCamera(perspective, w, h);
            const Rect scissor{r.i(-5, w / 2), r.i(-5, h / 2), r.i(0, w), r.i(0, h)};
            for (Device* d : {&refFull, &refXyz, &fastXyz}) {
                d->setState(s);
                d->setScissor(scissor);
                d->setTransforms(glm::mat4(1.0f), view, proj);
            }
            refFull.draw(prim, VertexSpace::Untransformed, full, indices);
            refXyz.draw(prim, xyz, indices);
            fastXyz.draw(prim, xyz, indices);
            const std::string where = "seed " + std::to_string(seed) + " draw " +
                                      std::to_string(k) + " (" + std::to_string(threads) +
                                      " threads" + (mesh ? ", mesh" : "") + ")";
            ASSERT_TRUE(sameFrameAndCounters(refFull, fastXyz, where + ", fast path"));
            ASSERT_TRUE(sameFrameAndCounters(refFull, refXyz, where + ", reference path"));
            addGeometry(sum, refFull.counters());
        }
    }
    EXPECT_EQ(draws, 96);
    EXPECT_GT(sum.trianglesDrawn, 50000u);
    EXPECT_GT(sum.trianglesClipped, 10u);
    EXPECT_GT(sum.trianglesInvalid, 0u);
}

// The same frame from the fast path on 1, 2, 3 and 8 threads and from the reference path:
// one SHA-256, one set of counters.
const char* const kPinnedHashes[3] = {
    "3cdea34eb5543cdc35d45791105b71d927cf6f955c2a7cac7b43dfaec2b2f36e/"
    "bf1033b07f0a4f11eedb86334ef889cb3ca6ae3eb0d9b2a78fe5b3afa7858521",
    "d4cca1fde67231ce3ddf297023990db7abdaa1d4198251290cbd7041bc837777/"
    "71865ea0bb42b59e9191a8b07667f2ced80c49ffa2e040baba894e16f58f2cce",
    "03d293eb256c7ef403ce451f81107745619045601a4e297e2e95483c45a5bf82/"
    "54949d64fdd57789fd46d1ecbb298010278b8b87d8495c0c22b77b485fb0dd21"};

TEST(ThreadCountDeterminism, SameBytesAndCountersOnAnyThreadCount) {
    // Let TBB run more workers than cores, so that 3 and 8 threads really are 3 and 8.
    tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 8);
    for (int scene = 0; scene < 3; ++scene) {
        Rng r(1000 + scene);
        PipelineState s;
        s.cull = CullMode::None;
        s.blend = 1;
        s.srcBlend = scene == 2 ? BlendFactor::One : BlendFactor::SrcAlpha;
        s.dstBlend = scene == 2 ? BlendFactor::One : BlendFactor::InvSrcAlpha;
        s.depthFunc = scene == 1 ? CompareFunc::Less : CompareFunc::Always;
        s.shade = scene == 2 ? ShadeMode::Flat : ShadeMode::Gouraud;
        std::vector<Vertex> verts;
        for (int i = 0; i < 3 * 1500; ++i) {
            Vertex v;
            float cx = r.f(-20, 340), cy = r.f(-20, 260);  // triangles up to ~80 pixels
            if (i % 3) cx = verts[i - 1].position.x + r.f(-80, 80), cy = verts[i - 1].position.y + r.f(-80, 80);
            v.position = {cx, cy, r.f(0, 1), r.f(0.2f, 2.0f)};
            v.diffuse = {r.byte(), r.byte(), r.byte(), r.byte()};
            verts.push_back(v);
        }
        std::string expectedHash;
        Counters expected;
        for (int threads : {0, 1, 2, 3, 8}) {  // 0: the reference path
            Device dev(profile(ProfileId::GeForce256), 320, 240, DepthFormat::D24,
                       {threads == 0 ? Path::Reference : Path::Fast, std::max(threads, 1)});
            dev.setState(s);
            dev.clear(true, {0, 0, 0, 255}, true, 1.0f);
            for (size_t b = 0; b < verts.size(); b += 3 * 500)
                dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed,
                         std::span<const Vertex>(verts).subspan(b, 3 * 500));
            std::string hash = frameHash(dev.framebuffer());
            if (threads == 0) {
                // Pinned as well: the same bytes from any compiler and build type
                // (docs/hardware.md, "Pinned choices"; checked with GCC Release and
                // Clang Debug).
                EXPECT_EQ(hash, kPinnedHashes[scene]) << "scene " << scene;
                expectedHash = hash;
                expected = dev.counters();
                EXPECT_GT(expected.fragmentsWritten, 50000u);
            } else {
                EXPECT_EQ(hash, expectedHash) << "scene " << scene << " threads " << threads;
                EXPECT_TRUE(sameCounters(dev.counters(), expected))
                    << "scene " << scene << " threads " << threads << "\n"
                    << dev.counters().toString();
            }
        }
    }
}

}  // namespace
}  // namespace rg::testing
