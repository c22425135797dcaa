// Draw batches on the fixed-function device (Device::beginBatch / endBatch): a batch gives
// the bytes and counters of the same draws issued one by one, on every path and thread
// count, while the caller reuses its vertex array and rebinds state and textures between
// draws; what a batch cannot defer is refused with an error naming the batch, and the
// batch goes on.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "raster_test_util.h"
#include "texunit/texture.h"

namespace rg::testing {
namespace {

using namespace rg::raster;

// One draw and everything it sets first.
struct Command {
    PipelineState state;
    Viewport vp;
    Rect scissor;
    glm::mat4 world{1.0f}, view{1.0f}, proj{1.0f};
    VertexSpace space = VertexSpace::Pretransformed;
    Primitive prim = Primitive::TriangleList;
    std::vector<Vertex> verts;
    std::vector<uint32_t> indices;
    bool xyzDiffuse = false;  // issued as D3DFVF_XYZ | D3DFVF_DIFFUSE vertices
    int texture = -1;         // into Session::textures; -1: no texture stage
    tex::StageState stage;
    Rgba8 factor;
};

struct Session {
    int w = 0, h = 0;
    const Profile* prof = nullptr;
    DepthFormat depth = DepthFormat::None;
    Rgba8 background;
    std::vector<std::shared_ptr<tex::Texture>> textures;
    std::vector<Command> commands;
    std::vector<size_t> batchEnds;  // a batch ends (and a pass begins) before these commands
};

// A long strip of thin triangles back and forth across the target: more than two chunks
// of the fast path's setup (kChunk = 1024), so one batched draw spans several chunks.
std::vector<Vertex> stripAcross(Rng& r, int w, int h) {
    std::vector<Vertex> v;
    const int n = 2400;
    for (int k = 0; k < n; ++k) {
        const float t = float(k / 2) / float(n / 2);
        const float x = std::fmod(t * 3.0f, 1.0f) * float(w) + r.f(-0.5f, 0.5f);
        const float y = float(h) * (std::floor(t * 3.0f) + (k % 2 ? 0.9f : 0.1f)) / 3.0f;
        v.push_back(tv(x, y, r.f(0.0f, 1.0f), 1.0f, randomColor(r)));
    }
    return v;
}

Session makeSession(uint64_t seed, tex::TextureMemory& mem) {
    Rng r(seed);
    Session s;
    const int sizes[][2] = {{97, 71}, {160, 130}, {130, 33}, {200, 150}};
    s.w = sizes[seed % 4][0];
    s.h = sizes[seed % 4][1];
    s.prof = &profile(r.p(0.7) ? ProfileId::GeForce256 : ProfileId::GeForce8800);
    s.depth = DepthFormat(r.i(0, 2));
    s.background = {r.byte(), r.byte(), r.byte(), r.byte()};
    for (int k = 0; k < 3; ++k) {
        const int tw = 1 << r.i(2, 5), th = 1 << r.i(2, 5);
        auto t = mem.create({tex::TextureTarget::Texture2D, tex::TexelFormat::RGBA8, tw, th, 1, 1, 1});
        std::vector<uint8_t> bytes(size_t(tw) * size_t(th) * 4);
        for (uint8_t& b : bytes) b = r.byte();
        mem.upload(*t, 0, 0, bytes);
        s.textures.push_back(std::move(t));
    }
    const int draws = 70;
    for (int k = 0; k < draws; ++k) {
        if (k > 0 && r.p(0.08)) s.batchEnds.push_back(size_t(k));
        Command c;
        c.state = randomState(r);
        c.vp = Viewport{0, 0, s.w, s.h, 0.0f, 1.0f};
        if (r.p(0.15)) {
            c.vp.x = r.i(0, s.w - 1);
            c.vp.y = r.i(0, s.h - 1);
            c.vp.width = r.i(1, s.w - c.vp.x);
            c.vp.height = r.i(1, s.h - c.vp.y);
        }
        c.scissor = Rect{r.i(-5, s.w), r.i(-5, s.h), r.i(0, s.w), r.i(0, s.h)};
        c.proj = glm::perspectiveLH_ZO(r.f(0.5f, 2.0f), r.f(0.5f, 2.0f), r.f(0.1f, 1.0f), r.f(5.0f, 50.0f));
        c.view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 3.0f));
        c.world = glm::rotate(glm::mat4(1.0f), r.f(0.0f, 6.28f), glm::vec3(0.3f, 1.0f, 0.1f));
        const int kind = r.i(0, 9);
        if (kind == 0) {  // a long strip
            c.space = VertexSpace::Pretransformed;
            c.prim = Primitive::TriangleStrip;
            c.verts = stripAcross(r, s.w, s.h);
        } else {  // a few triangles, as lightfield's eye points and most small draws
            c.space = r.p(0.5) ? VertexSpace::Pretransformed : VertexSpace::Untransformed;
            c.prim = Primitive(r.i(0, 2));
            const int n = r.i(3, 12);
            for (int i = 0; i < n; ++i) {
                const int vk = r.p(0.8) ? 0 : r.i(1, 5);
                c.verts.push_back(randomVertex(r, c.space, vk, s.w, s.h,
                                               c.verts.empty() ? nullptr : &c.verts.back()));
            }
            if (r.p(0.3))
                for (int i = 0, m = r.i(3, 15); i < m; ++i) c.indices.push_back(uint32_t(r.i(0, n - 1)));
            c.xyzDiffuse = c.space == VertexSpace::Untransformed && r.p(0.3);
        }
        if (!c.xyzDiffuse && r.p(0.4)) {
            // GL MODULATE of a random texture (the whole-quad cascades) or a stage mixing it
            // with the factor colour (the generic stage loop).
            c.texture = r.i(0, 2);
            c.stage.colorOp = r.p(0.5) ? tex::TextureOp::Modulate : tex::TextureOp::Add;
            c.stage.colorArg1 = tex::arg::Texture;
            c.stage.colorArg2 = r.p(0.5) ? tex::arg::Diffuse : tex::arg::TFactor;
            c.stage.alphaOp = tex::TextureOp::Modulate;
            c.stage.alphaArg1 = tex::arg::Texture;
            c.stage.alphaArg2 = tex::arg::Diffuse;
            for (Vertex& v : c.verts) v.tex[0] = {r.f(-0.5f, 1.5f), r.f(-0.5f, 1.5f), 0.0f, 1.0f};
        }
        c.factor = {r.byte(), r.byte(), r.byte(), r.byte()};
        s.commands.push_back(std::move(c));
    }
    return s;
}

struct Frame {
    std::vector<uint8_t> color;
    std::vector<uint32_t> depth;
    Counters counters;
    std::vector<PassRecord> passes;
};

// The session on a fresh device. Batched: a batch per run of commands between
// batchEnds, each run in its own pass. The vertices go through one array the caller
// overwrites with NaNs after each draw, as a renderer reuses its buffers: a batch that
// kept the caller's vertices instead of copies would draw those.
Frame render(const Session& s, Path path, int threads, bool batched) {
    Device dev(*s.prof, s.w, s.h, s.depth, {path, threads});
    dev.beginFrame();
    dev.beginPass("pass 0");
    dev.clear(true, s.background, true, 1.0f);
    if (batched) dev.beginBatch();
    std::vector<Vertex> verts;
    std::vector<VertexXyzDiffuse> xyz;
    std::vector<uint32_t> indices;
    size_t nextEnd = 0;
    for (size_t k = 0; k < s.commands.size(); ++k) {
        if (nextEnd < s.batchEnds.size() && s.batchEnds[nextEnd] == k) {
            ++nextEnd;
            if (batched) dev.endBatch();
            dev.beginPass("pass " + std::to_string(nextEnd));
            if (batched) dev.beginBatch();
        }
        const Command& c = s.commands[k];
        dev.setState(c.state);
        dev.setViewport(c.vp);
        dev.setScissor(c.scissor);
        dev.setTransforms(c.world, c.view, c.proj);
        tex::TextureUnits& tu = dev.textureUnits();
        tu.setStage(0, c.texture >= 0 ? c.stage : tex::StageState{});
        tu.setTexture(0, c.texture >= 0 ? s.textures[size_t(c.texture)] : nullptr);
        tu.setTextureFactor(c.factor);
        indices = c.indices;
        if (c.xyzDiffuse) {
            xyz.clear();
            for (const Vertex& v : c.verts)
                xyz.push_back({glm::vec3(v.position), v.diffuse});
            dev.draw(c.prim, xyz, indices);
        } else {
            verts = c.verts;
            dev.draw(c.prim, c.space, verts, indices);
        }
        const float nan = std::numeric_limits<float>::quiet_NaN();
        for (Vertex& v : verts) v.position = {nan, nan, nan, nan};
        for (VertexXyzDiffuse& v : xyz) v.position = {nan, nan, nan};
        for (uint32_t& i : indices) i = 0;
    }
    // Unbound before the batch runs: a batch that read the device's units instead of
    // its copies would draw untextured.
    dev.textureUnits().setStage(0, tex::StageState{});
    dev.textureUnits().setTexture(0, nullptr);
    if (batched) dev.endBatch();
    dev.endFrame();
    const Framebuffer& fb = dev.framebuffer();
    Frame f;
    f.color.assign(reinterpret_cast<const uint8_t*>(fb.color().data()),
                   reinterpret_cast<const uint8_t*>(fb.color().data()) + fb.color().size_bytes());
    f.depth.assign(fb.depth().begin(), fb.depth().end());
    f.counters = dev.counters();
    f.passes = dev.passes();
    return f;
}

TEST(DrawBatch, GivesTheBytesAndCountersOfDrawingOneByOne) {
    uint64_t written = 0, textured = 0, strips = 0;
    for (uint64_t seed = 1; seed <= 10; ++seed) {
        tex::TextureMemory mem(profile(ProfileId::GeForce256));
        const Session s = makeSession(seed, mem);
        for (const Command& c : s.commands) {
            textured += c.texture >= 0;
            strips += c.verts.size() > 1000;
        }
        // The oracle: the draws one by one on the reference path (tests/rasterizer's
        // analytic suites and PathsAgree check it and the fast path).
        const Frame expect = render(s, Path::Reference, 1, false);
        written += expect.counters.fragmentsWritten;
        const std::pair<Path, int> runs[] = {
            {Path::Fast, 1}, {Path::Fast, 2}, {Path::Fast, 3}, {Path::Reference, 2}};
        for (const auto& [path, threads] : runs) {
            const std::string where = "seed " + std::to_string(seed) + ", " +
                                      (path == Path::Fast ? "fast" : "reference") + " path, " +
                                      std::to_string(threads) + " thread(s)";
            const Frame got = render(s, path, threads, true);
            EXPECT_TRUE(got.color == expect.color) << where << ": colour bytes differ";
            EXPECT_TRUE(got.depth == expect.depth) << where << ": depth differs";
            EXPECT_TRUE(sameCounters(got.counters, expect.counters))
                << where << "\nbatched:\n" << got.counters.toString() << "one by one:\n"
                << expect.counters.toString();
            ASSERT_EQ(got.passes.size(), expect.passes.size()) << where;
            for (size_t p = 0; p < got.passes.size(); ++p)
                EXPECT_EQ(got.passes[p].drawCalls, expect.passes[p].drawCalls) << where << ", pass " << p;
        }
    }
    // The sessions must reach what a batch could get wrong.
    EXPECT_GT(written, 200000u);
    EXPECT_GT(textured, 150u);
    EXPECT_GT(strips, 40u);
}

TEST(DrawBatch, WhatCannotBeDeferredIsRefusedAndTheBatchGoesOn) {
    Device dev(geforce256(), 32, 32, DepthFormat::None, {Path::Fast, 2});
    dev.setState(plainState());
    dev.clear(true, {0, 0, 0, 255}, false, 1.0f);
    EXPECT_THROW(dev.endBatch(), InvalidState);  // none open
    dev.beginBatch();
    const std::vector<Vertex> tri = {tv(0, 0, 0.5f, 1, {255, 0, 0, 255}), tv(32, 0, 0.5f, 1, {255, 0, 0, 255}),
                                     tv(0, 32, 0.5f, 1, {255, 0, 0, 255})};
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
    const std::vector<Rgba8> pixels(4, Rgba8{1, 2, 3, 4});
    const std::pair<const char*, std::function<void()>> refused[] = {
        {"clear", [&] { dev.clear(true, {9, 9, 9, 9}, false, 1.0f); }},
        {"drawPixels", [&] { dev.drawPixels(0, 0, 2, 2, pixels); }},
        {"copyPixels", [&] { dev.copyPixels(0, 0, 2, 2, 4, 4); }},
        {"readPixels", [&] { dev.readPixels(0, 0, 2, 2); }},
        {"beginFrame", [&] { dev.beginFrame(); }},
        {"beginPass", [&] { dev.beginPass("x"); }},
        {"endFrame", [&] { dev.endFrame(); }},
        {"setPath", [&] { dev.setPath(Path::Reference); }},
        {"setThreads", [&] { dev.setThreads(1); }},
        {"setFragmentObserver", [&] { dev.setFragmentObserver([](const tex::FragmentQuad&, uint8_t) {}); }},
        {"setPassObserver", [&] { dev.setPassObserver([](const PassRecord&, const Framebuffer&) {}); }},
        {"setRecorder", [&] { dev.setRecorder(nullptr); }},
        {"beginBatch", [&] { dev.beginBatch(); }},
    };
    for (const auto& [what, call] : refused) {
        try {
            call();
            ADD_FAILURE() << what << " inside a batch was accepted";
        } catch (const InvalidState& e) {
            EXPECT_NE(std::string(e.what()).find("batch"), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    }
    // A bad draw is refused at issue, as outside a batch, and not recorded.
    const std::vector<uint32_t> bad = {0, 1, 7};
    EXPECT_THROW(dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri, bad), InvalidState);
    EXPECT_TRUE(dev.batching());
    EXPECT_EQ(dev.framebuffer().pixel(2, 2), (Rgba8{0, 0, 0, 255}));  // not drawn yet
    dev.endBatch();
    EXPECT_FALSE(dev.batching());
    EXPECT_EQ(dev.framebuffer().pixel(2, 2), (Rgba8{255, 0, 0, 255}));
    EXPECT_EQ(dev.framebuffer().pixel(30, 30), (Rgba8{0, 0, 0, 255}));
    EXPECT_EQ(dev.counters().drawCalls, 1u);
    EXPECT_EQ(dev.counters().trianglesDrawn, 1u);
}

TEST(DrawBatch, AScopeLeftByAnExceptionStillDrawsWhatWasIssued) {
    Device dev(geforce256(), 16, 16, DepthFormat::None, {Path::Fast, 2});
    dev.setState(plainState());
    dev.clear(true, {0, 0, 0, 0}, false, 1.0f);
    const std::vector<Vertex> quad = {tv(0, 0), tv(16, 0), tv(0, 16), tv(16, 16)};
    try {
        DrawBatch batch(dev);
        dev.draw(Primitive::TriangleStrip, VertexSpace::Pretransformed, quad);
        dev.draw(Primitive::TriangleStrip, VertexSpace::Pretransformed, quad);
        throw std::runtime_error("the scope ends early");
    } catch (const std::runtime_error&) {
    }
    EXPECT_FALSE(dev.batching());
    EXPECT_EQ(countIf(dev.framebuffer(), [](Rgba8 p) { return p == Rgba8{255, 255, 255, 255}; }), 256);
    EXPECT_EQ(dev.counters().trianglesDrawn, 4u);
}

}  // namespace
}  // namespace rg::testing
