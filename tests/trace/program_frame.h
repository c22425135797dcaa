// The programmable frame the version-2 trace tests record (tests/trace/test_trace_program.cpp)
// and play through Mesa (tests/trace/test_trace_mesa.cpp): every version-2 record kind on
// 32×32 targets, with test programs registered as "test/...".
#pragma once

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bench_programs.h"
#include "core/profile.h"
#include "rasterizer/program_registry.h"
#include "rasterizer/programmable_device.h"
#include "rasterizer/trace.h"

namespace rg::raster::test {

// ---- test programs ---------------------------------------------------------------------

struct TestVertex {
    glm::vec4 position;
    glm::vec4 uv;
    glm::vec4 colour;
};

// Uniforms: a per-component scale and offset of the position, a tint of the colour.
struct TransformVP {
    static constexpr int kVaryings = 2;
    glm::vec4 scale{1.0f}, offset{0.0f}, tint{1.0f};
    glm::vec4 operator()(const TestVertex& v, Varyings& out) const {
        out[0] = v.uv;
        out[1] = v.colour * tint;
        return v.position * scale + offset;
    }
};

// Two targets: the texture of unit 0 modulated by the colour (plus a bias uniform), and
// the coordinates.
struct TexturedMrtFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 0b11;
    static constexpr uint32_t kUnits = 0b1;
    static constexpr bool kWritesDepth = false;
    glm::vec4 bias{0.0f};
    void operator()(FragmentContext& f) const {
        const glm::vec4 t = f.sample(0, 0);
        f.output(0, t * f.varying(1) + bias);
        f.output(1, glm::vec4(f.varying(0).x, f.varying(0).y, t.z, 0.25f));
    }
};

// The second pass: the first pass's target (unit 0), a float texture (unit 1) and a
// target drawn before the capture began (unit 2), mixed by a uniform weight.
struct CompositeFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b111;
    static constexpr bool kWritesDepth = false;
    glm::vec4 weight{0.5f};
    void operator()(FragmentContext& f) const {
        const glm::vec4 a = f.sample(0, 0);
        const glm::vec4 b = f.sampleLevel(1, f.varying(0), 0.0f);
        const glm::vec4 c = f.sampleLevel(2, f.varying(0) * 0.5f, 0.0f);
        f.output(0, a * weight + b * (glm::vec4(1.0f) - weight) + glm::vec4(c.x, 0.0f, 0.0f, 0.0f));
    }
};

// Same VP and FP sizes as the frame's, another vertex size: for the stride check.
struct ClipVertex {
    glm::vec4 clip;
};
struct ClipVP {
    static constexpr int kVaryings = 2;
    glm::vec4 scale{1.0f}, offset{0.0f}, tint{1.0f};
    glm::vec4 operator()(const ClipVertex& v, Varyings& out) const {
        out[0] = v.clip;
        out[1] = tint;
        return v.clip * scale + offset;
    }
};

// Never registered.
struct UnregisteredFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const { f.output(0, glm::vec4(1.0f)); }
};

inline void registerTestPrograms() {
    bench::registerPrograms();
    registerProgram<TransformVP, TexturedMrtFP, TestVertex>("test/textured_mrt");
    registerProgram<TransformVP, CompositeFP, TestVertex>("test/composite");
    registerProgram<ClipVP, TexturedMrtFP, ClipVertex>("test/clip_only");
}

// ---- the frame ---------------------------------------------------------------------------

inline const Profile& g80() { return profile(ProfileId::GeForce8800); }

inline TestVertex vtx(float x, float y, float z, float u, float v, glm::vec4 c) {
    return {{x, y, z, 1.0f}, {u, v, 0.0f, 1.0f}, c};
}

inline std::shared_ptr<tex::Texture> patternTexture(tex::TextureMemory& mem, uint32_t seed) {
    tex::TextureDesc d;
    d.width = d.height = 16;
    d.levels = 2;
    auto t = mem.create(d);
    for (int l = 0; l < 2; ++l) {
        const int n = 16 >> l;
        std::vector<Rgba8> texels;
        for (int i = 0; i < n * n; ++i) {
            const uint32_t h = (uint32_t(i) * 2654435761u) ^ (seed * 40503u + uint32_t(l) * 977u);
            texels.push_back({uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(200 + (h >> 29))});
        }
        mem.upload(*t, l, 0, texels);
    }
    return t;
}

struct Frame {
    std::vector<uint8_t> trace;
    std::vector<std::vector<uint8_t>> targets;  // renderTargetValues() of each, at the end
    std::string imageHash;                      // SHA-256 of the final target's values
};

// The frame, recorded: every version-2 record kind, on a 32×32 target.
inline Frame recordFrame(Path path = Path::Fast, int threads = 2) {
    registerTestPrograms();
    tex::TextureMemory mem(g80());
    ProgrammableDevice dev(g80(), {path, threads});
    auto rt = [&](tex::TexelFormat f) {
        tex::TextureDesc d;
        d.format = f;
        d.width = d.height = 32;
        return mem.createRenderTarget(d);
    };
    auto a = rt(tex::TexelFormat::RGBA8), b = rt(tex::TexelFormat::RGBA16F), depth = rt(tex::TexelFormat::Depth24);
    auto image = rt(tex::TexelFormat::RGBA8), before = rt(tex::TexelFormat::R32F);
    auto t0 = patternTexture(mem, 1);
    tex::TextureDesc fd;
    fd.format = tex::TexelFormat::RGBA16F;
    fd.width = fd.height = 8;
    auto t1 = mem.create(fd);
    {
        std::vector<uint8_t> halves(8 * 8 * 8);
        for (size_t i = 0; i < halves.size(); i += 2) {
            const uint16_t h = uint16_t(0x3000 + (i * 37) % 0x0c00);  // 0.125 … 0.87
            halves[i] = uint8_t(h);
            halves[i + 1] = uint8_t(h >> 8);
        }
        mem.upload(*t1, 0, 0, halves);
    }
    tex::SamplerState linear;  // bilinear, WRAP
    tex::SamplerState point;
    point.magFilter = point.minFilter = tex::FilterMode::Nearest;
    point.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::Mirror, tex::AddressMode::Wrap,
                     tex::AddressMode::Wrap};
    const std::vector<TestVertex> quad = {vtx(-1, 1, 0.5f, 0, 0, {1, 1, 1, 1}), vtx(1, 1, 0.5f, 1, 0, {1, 1, 1, 1}),
                                          vtx(-1, -1, 0.5f, 0, 1, {1, 1, 1, 1}), vtx(1, -1, 0.5f, 1, 1, {1, 1, 1, 1})};
    const std::vector<uint32_t> quadIndices = {0, 1, 2, 1, 3, 2};

    // Before the capture: `before` gets contents a trace must carry.
    {
        const ColorTarget c[] = {{before}, {rt(tex::TexelFormat::RGBA8)}};
        dev.setRenderTargets(c);
        dev.clearColor(0, {0.75f, 0, 0, 1});
        dev.setTexture(0, t0, linear);
        ProgramState s;
        dev.setState(s);
        dev.draw(TransformVP{{0.5f, 0.5f, 1, 1}, {}, {1, 1, 1, 1}}, TexturedMrtFP{}, ProgramPrimitive::TriangleList,
                 std::span<const TestVertex>(quad), quadIndices);
    }

    auto recorder = std::make_shared<TraceRecorder>();
    dev.setRecorder(recorder);
    dev.beginFrame();
    // Pass 1: two colour targets and depth.
    const ColorTarget pass1[] = {{a}, {b}};
    dev.setRenderTargets(pass1, DepthTarget{depth});
    dev.clearColor(0, {0.1f, 0.2f, 0.3f, 1.0f});
    dev.clearColor(1, {0.0f, 0.5f, -2.0f, 1.0f});
    dev.clearDepth(1.0f);
    ProgramState s;
    s.depthTest = 1;
    s.depthWrite = 1;
    s.depthFunc = CompareFunc::LessEqual;
    s.cull = CullMode::CW;
    s.blend[1] = {1, BlendFactor::One, BlendFactor::One, BlendOp::Add, kWriteRGBA};
    s.blend[0].writeMask = kWriteR | kWriteG | kWriteB;
    dev.setState(s);
    dev.setTexture(0, t0, linear);
    const std::vector<TestVertex> tris = {vtx(-0.9f, 0.9f, 0.3f, 0, 0, {1, 0.5f, 0.25f, 1}),
                                          vtx(0.8f, 0.7f, 0.6f, 2, 0, {0.5f, 1, 0.5f, 1}),
                                          vtx(-0.7f, -0.8f, 0.4f, 0, 2, {0.25f, 0.5f, 1, 1}),
                                          vtx(0.9f, -0.9f, 0.2f, 2, 2, {1, 1, 1, 1})};
    dev.draw(TransformVP{{1, 1, 1, 1}, {0.05f, 0, 0, 0}, {1, 0.9f, 0.8f, 1}}, TexturedMrtFP{{0.01f, 0, 0, 0}},
             ProgramPrimitive::TriangleStrip, std::span<const TestVertex>(tris));
    dev.setViewport({4, 2, 24, 26, 0.25f, 0.75f});
    const Rect scissor{3, 5, 20, 19};
    dev.setScissor(&scissor);
    dev.draw(TransformVP{{1, 1, 1, 1}, {0, 0, -0.1f, 0}, {0.5f, 0.5f, 0.5f, 1}}, TexturedMrtFP{},
             ProgramPrimitive::TriangleList, std::span<const TestVertex>(tris), std::vector<uint32_t>{3, 1, 2, 0, 2, 1});
    // A re-upload in place: new contents under the same texture object.
    {
        auto fresh = patternTexture(mem, 7);
        for (int l = 0; l < 2; ++l) mem.upload(*t0, l, 0, std::span<const Rgba8>(fresh->data8(l, 0), size_t(256 >> (2 * l))));
    }
    s.pointSize = 3.0f;
    s.cull = CullMode::None;
    dev.setState(s);
    dev.setTexture(0, t0, point);
    dev.draw(TransformVP{}, TexturedMrtFP{}, ProgramPrimitive::PointList, std::span<const TestVertex>(tris));
    s.pointSize = 6.0f;  // a state change in the point size alone
    dev.setState(s);
    dev.draw(TransformVP{{1, 1, 1, 1}, {0.1f, -0.1f, -0.05f, 0}, {1, 1, 1, 1}}, TexturedMrtFP{},
             ProgramPrimitive::PointList, std::span<const TestVertex>(tris));
    // Pass 2: one target; the first pass's target, a float texture and `before` sampled.
    const ColorTarget pass2[] = {{image}};
    dev.setRenderTargets(pass2);  // resets the viewport and scissor ...
    dev.setViewport({4, 2, 24, 26, 0.25f, 0.75f});  // ... which are set again as they were
    dev.setScissor(&scissor);
    dev.clearColor(0, {0, 0, 0, 1});
    dev.setScissor(nullptr);
    dev.setState(ProgramState{});
    dev.setTexture(0, a, linear);
    dev.setTexture(1, t1, point);
    dev.setTexture(2, before, point);
    const std::vector<TestVertex> fan = {vtx(0, 0, 0.5f, 0.5f, 0.5f, {1, 1, 1, 1}), vtx(-1, 1, 0.5f, 0, 0, {1, 1, 1, 1}),
                                         vtx(1, 1, 0.5f, 1, 0, {1, 1, 1, 1}), vtx(1, -1, 0.5f, 1, 1, {1, 1, 1, 1}),
                                         vtx(-1, -1, 0.5f, 0, 1, {1, 1, 1, 1}), vtx(-1, 1, 0.5f, 0, 0, {1, 1, 1, 1})};
    dev.draw(TransformVP{}, CompositeFP{{0.75f, 0.5f, 0.25f, 1.0f}}, ProgramPrimitive::TriangleFan,
             std::span<const TestVertex>(fan));
    dev.setRecorder(nullptr);
    recorder->finish();

    Frame f;
    f.trace = recorder->bytes();
    for (const auto& t : {a, b, depth, image, before}) f.targets.push_back(renderTargetValues(*t));
    const std::vector<uint8_t>& img = f.targets[3];
    f.imageHash = sha256Hex(img.data(), img.size());
    return f;
}

}  // namespace rg::raster::test
