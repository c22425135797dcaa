// Draw batches on the programmable device (ProgrammableDevice::beginBatch / endBatch): a
// batch gives the bytes and counters of the same draws issued one by one on the reference
// path, whatever changes between its draws, and refuses what cannot be deferred.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/profile.h"
#include "rasterizer/programmable_device.h"
#include "rasterizer/trace.h"
#include "texunit/texture.h"

namespace rg::raster {
namespace {

using tex::TexelFormat;
using tex::TextureDesc;

const Profile& g80() { return profile(ProfileId::GeForce8800); }

struct BatchVertex {
    glm::vec4 position;  // clip space
    glm::vec4 a;
};

struct BatchVP {
    static constexpr int kVaryings = 1;
    glm::vec4 offset{0.0f};  // a uniform: changed by the caller between draws
    glm::vec4 operator()(const BatchVertex& v, Varyings& out) const {
        out[0] = v.a;
        return v.position + offset;
    }
};

// Unit 0 (rebound between draws) at varying 0, scaled by a uniform the caller changes
// after each draw: a batch that kept a reference to the caller's program instead of a copy
// would shade every draw with the last value.
struct BatchFP {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    glm::vec4 tint{1.0f};
    void operator()(FragmentContext& f) const {
        const glm::vec4 a = f.varying(0);
        if (a.w > 0.9f) {
            f.discard();
            return;
        }
        f.output(0, f.sample(0, 0) * tint + a * 0.25f);
    }
};

struct BatchPointFP {  // point sprites: the point coordinate
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const {
        const glm::vec2 pc = f.pointCoord();
        f.output(0, glm::vec4(pc.x, pc.y, f.varying(0).z, 0.5f));
    }
};

struct ThrowingVP {
    static constexpr int kVaryings = 1;
    glm::vec4 operator()(const BatchVertex&, Varyings&) const { throw std::runtime_error("vertex program failed"); }
};

struct Scene {
    static constexpr int W = 197, H = 141;  // several 64² tiles, ragged edges
    tex::TextureMemory memory{g80()};
    std::array<std::shared_ptr<tex::Texture>, 3> textures;
    struct Draw {
        std::vector<BatchVertex> vertices;
        std::vector<uint32_t> indices;
        bool points = false;
        ProgramState state;
        int texture = 0;
        bool viewport = false, scissor = false;
        glm::vec4 tint{1.0f}, offset{0.0f};
    };
    std::vector<Draw> draws;

    explicit Scene(uint32_t seed) {
        std::mt19937 rng(seed);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        for (size_t k = 0; k < textures.size(); ++k) {
            TextureDesc d;
            d.width = d.height = 16 << k;
            auto t = memory.create(d);
            std::vector<uint8_t> b(size_t(d.width) * size_t(d.height) * 4);
            for (auto& x : b) x = uint8_t(rng());
            memory.upload(*t, 0, 0, b);
            textures[k] = t;
        }
        for (int i = 0; i < 14; ++i) {
            Draw d;
            d.points = i % 5 == 4;
            const int prims = 3 + int(rng() % 25);
            for (int v = 0; v < (d.points ? prims : 3 * prims); ++v) {
                std::array<float, 8> r;
                for (float& x : r) x = u(rng);
                const float w = 0.5f + r[0];
                d.vertices.push_back({glm::vec4((r[1] * 2.4f - 1.2f) * w, (r[2] * 2.4f - 1.2f) * w,
                                                (r[3] * 1.1f - 0.05f) * w, w),
                                      glm::vec4(r[4] * 2.0f, r[5], r[6], r[7])});
            }
            if (i % 3 == 1)  // indexed, some vertices used twice
                for (size_t v = 0; v < d.vertices.size(); ++v)
                    d.indices.push_back(uint32_t((v * 7) % d.vertices.size()));
            d.state.cull = CullMode(rng() % 3);
            d.state.depthTest = uint8_t(rng() & 1);
            d.state.depthWrite = uint8_t(rng() & 1);
            d.state.depthFunc = CompareFunc(rng() % 8);
            d.state.pointSize = 1.0f + float(rng() % 9);
            d.state.blend[0] = TargetBlend{uint8_t(rng() & 1), BlendFactor(rng() % 13), BlendFactor(rng() % 11),
                                           BlendOp(rng() % 5), uint8_t(rng() % 16)};
            d.texture = int(rng() % textures.size());
            d.viewport = rng() % 4 == 0;
            d.scissor = rng() % 4 == 0;
            d.tint = glm::vec4(u(rng), u(rng), u(rng), u(rng)) * 2.0f;
            d.offset = glm::vec4(u(rng) - 0.5f, u(rng) - 0.5f, 0.0f, 0.0f) * 0.3f;
            draws.push_back(std::move(d));
        }
    }

    // Every draw on a fresh device; `batched` issues them between beginBatch and endBatch,
    // changing the programs' uniforms in one reused object after each draw.
    std::pair<std::vector<uint8_t>, std::string> render(Path path, int threads, bool batched) {
        TextureDesc cd;
        cd.width = W;
        cd.height = H;
        auto color = memory.createRenderTarget(cd);
        cd.format = TexelFormat::Depth24;
        auto depth = memory.createRenderTarget(cd);
        ProgrammableDevice dev(g80(), DeviceOptions{path, threads});
        ColorTarget ct{color};
        dev.setRenderTargets({&ct, 1}, DepthTarget{depth});
        dev.clearColor(0, glm::vec4(0.2f, 0.4f, 0.6f, 0.8f));
        dev.clearDepth(0.6f);
        tex::SamplerState s;
        s.magFilter = tex::FilterMode::Nearest;
        BatchVP vp;
        BatchFP fp;
        if (batched) dev.beginBatch();
        for (const Draw& d : draws) {
            dev.setState(d.state);
            dev.setTexture(0, textures[size_t(d.texture)], s);
            if (d.viewport)
                dev.setViewport(Viewport{13, 7, W - 40, H - 30, 0.1f, 0.9f});
            else
                dev.setViewport(Viewport{0, 0, W, H, 0.0f, 1.0f});
            const Rect r{30, 20, 101, 77};
            dev.setScissor(d.scissor ? &r : nullptr);
            vp.offset = d.offset;
            fp.tint = d.tint;
            const std::span<const BatchVertex> v(d.vertices);
            if (d.points)
                dev.draw(vp, BatchPointFP{}, ProgramPrimitive::PointList, v, d.indices);
            else
                dev.draw(vp, fp, ProgramPrimitive::TriangleList, v, d.indices);
            vp.offset = glm::vec4(5.0f);  // what the draw must not see
            fp.tint = glm::vec4(-1.0f);
        }
        if (batched) {
            EXPECT_TRUE(dev.batching());
            dev.endBatch();
        }
        EXPECT_FALSE(dev.batching());
        std::vector<uint8_t> bytes(size_t(W) * H * 4 + size_t(W) * H * 4);
        std::memcpy(bytes.data(), color->renderData8(0, 0), size_t(W) * H * 4);
        std::memcpy(bytes.data() + size_t(W) * H * 4, depth->renderDataR(0, 0), size_t(W) * H * 4);
        return {bytes, dev.counters().toString()};
    }
};

TEST(ProgrammableBatch, GivesTheBytesAndCountersOfDrawingOneByOne) {
    for (uint32_t seed : {1u, 2u, 3u}) {
        Scene scene(seed);
        // The oracle: the draws one by one on the reference path (tests/programmable's
        // other tests hold that against analytic values and the fast path).
        const auto [expect, expectCounters] = scene.render(Path::Reference, 1, false);
        ASSERT_NE(expectCounters.find("fragments_written"), std::string::npos);
        for (const auto& [path, threads] : std::vector<std::pair<Path, int>>{
                 {Path::Reference, 1}, {Path::Fast, 1}, {Path::Fast, 2}, {Path::Fast, 3}, {Path::Fast, 8}}) {
            const auto [bytes, counters] = scene.render(path, threads, true);
            EXPECT_TRUE(bytes == expect) << "seed " << seed << ", batched, "
                                         << (path == Path::Reference ? "reference" : "fast") << " path, "
                                         << threads << " threads";
            EXPECT_EQ(counters, expectCounters) << "seed " << seed << ", " << threads << " threads";
        }
    }
}

TEST(ProgrammableBatch, WhatCannotBeDeferredIsRefusedAndTheBatchGoesOn) {
    Scene scene(7);
    TextureDesc cd;
    cd.width = cd.height = 64;
    auto color = scene.memory.createRenderTarget(cd);
    ProgrammableDevice dev(g80());
    ColorTarget ct{color};
    dev.setRenderTargets({&ct, 1});
    EXPECT_THROW(dev.endBatch(), InvalidState);
    dev.clearColor(0, glm::vec4(0.0f));
    dev.beginBatch();
    auto refused = [&](const char* what, auto&& call) {
        try {
            call();
            ADD_FAILURE() << what << " inside a batch was accepted";
        } catch (const InvalidState& e) {
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
            EXPECT_NE(std::string(e.what()).find("batch"), std::string::npos) << e.what();
        }
    };
    refused("clearColor", [&] { dev.clearColor(0, glm::vec4(1.0f)); });
    refused("clearDepth", [&] { dev.clearDepth(1.0f); });
    refused("setRenderTargets", [&] { dev.setRenderTargets({&ct, 1}); });
    refused("beginFrame", [&] { dev.beginFrame(); });
    refused("beginBatch", [&] { dev.beginBatch(); });
    refused("setPath", [&] { dev.setPath(Path::Reference); });
    refused("setThreads", [&] { dev.setThreads(1); });
    refused("setRecorder", [&] { dev.setRecorder(std::make_shared<TraceRecorder>()); });
    // The batch is still open and still runs.
    EXPECT_TRUE(dev.batching());
    const Scene::Draw& d = scene.draws[0];
    dev.setTexture(0, scene.textures[0]);
    dev.draw(BatchVP{}, BatchFP{}, ProgramPrimitive::TriangleList, std::span<const BatchVertex>(d.vertices));
    EXPECT_EQ(dev.counters().drawCalls, 0u);  // queued, not run
    dev.endBatch();
    EXPECT_EQ(dev.counters().drawCalls, 1u);
    EXPECT_GT(dev.counters().fragmentInvocations, 0u);
}

TEST(ProgrammableBatch, AVertexProgramErrorEndsTheBatchAndTheDeviceGoesOn) {
    Scene scene(8);
    TextureDesc cd;
    cd.width = cd.height = 64;
    auto color = scene.memory.createRenderTarget(cd);
    for (int threads : {1, 2}) {
        ProgrammableDevice dev(g80(), DeviceOptions{Path::Fast, threads});
        ColorTarget ct{color};
        dev.setRenderTargets({&ct, 1});
        dev.setTexture(0, scene.textures[0]);
        const std::span<const BatchVertex> v(scene.draws[0].vertices);
        dev.beginBatch();
        dev.draw(BatchVP{}, BatchFP{}, ProgramPrimitive::TriangleList, v);
        dev.draw(ThrowingVP{}, BatchFP{}, ProgramPrimitive::TriangleList, v);
        EXPECT_THROW(dev.endBatch(), std::runtime_error);
        EXPECT_FALSE(dev.batching());
        dev.beginBatch();  // a fresh batch: nothing of the failed one is left in it
        dev.draw(BatchVP{}, BatchFP{}, ProgramPrimitive::TriangleList, v);
        const uint64_t before = dev.counters().drawCalls;
        dev.endBatch();
        EXPECT_EQ(dev.counters().drawCalls, before + 1u) << threads << " threads";
    }
}

TEST(ProgrammableBatch, TheDestructorRunsABatchLeftOpen) {
    Scene scene(9);
    TextureDesc cd;
    cd.width = Scene::W;
    cd.height = Scene::H;
    auto color = scene.memory.createRenderTarget(cd);
    cd.format = TexelFormat::Depth24;
    auto depth = scene.memory.createRenderTarget(cd);
    {
        ProgrammableDevice dev(g80(), DeviceOptions{Path::Fast, 2});
        ColorTarget ct{color};
        dev.setRenderTargets({&ct, 1}, DepthTarget{depth});
        dev.clearColor(0, glm::vec4(0.2f, 0.4f, 0.6f, 0.8f));
        dev.clearDepth(0.6f);
        dev.beginBatch();
        const Scene::Draw& d = scene.draws[0];
        dev.setState(d.state);
        tex::SamplerState s;
        s.magFilter = tex::FilterMode::Nearest;
        dev.setTexture(0, scene.textures[size_t(d.texture)], s);
        BatchVP vp;
        vp.offset = d.offset;
        BatchFP fp;
        fp.tint = d.tint;
        dev.draw(vp, fp, ProgramPrimitive::TriangleList, std::span<const BatchVertex>(d.vertices), d.indices);
    }
    // The first draw alone, as the one-by-one device renders it.
    Scene first(9);
    first.draws.resize(1);
    const auto [one, oneCounters] = first.render(Path::Reference, 1, false);
    (void)oneCounters;
    EXPECT_EQ(std::memcmp(color->renderData8(0, 0), one.data(), size_t(Scene::W) * Scene::H * 4), 0);
}

}  // namespace
}  // namespace rg::raster
