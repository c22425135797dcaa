// The Mesa peer of programmable traces (conformance/mesa_program_player.cpp): the test frame
// of tests/trace/program_frame.h (two targets, float and depth targets, blending, culling,
// viewport, scissor, points, a target sampled by a later pass, uniforms) played through
// GLSL twins on llvmpipe against ours, and the "ours only" reason of a program without a
// twin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdlib>
#include <cstring>

#include "conformance/mesa_player.h"
#include "program_frame.h"

namespace rg::raster {
namespace {

using namespace test;

// Measured with llvmpipe (LLVM 15, Mesa 22.3): 822 of the 1024 pixels equal, 189 differ by 1
// (float to unorm8 rounding, the 8-bit blend), 12 by 2 to 18 (pixels on triangle edges and
// point borders, and bilinear weights from llvmpipe's own coordinates on random texels,
// sampled once more by the second pass).
constexpr int kSmallDiff = 2;
constexpr double kMaxLargeShare = 0.03;

// TransformVP: three vec4 uniforms; the fragment programs one vec4 each.
const char* const kVertexShader = R"(#version 130
uniform vec4 scale;
uniform vec4 offset;
uniform vec4 tint;
in vec4 position;
in vec4 uv;
in vec4 colour;
out vec4 v0;
out vec4 v1;
void main() {
    v0 = uv;
    v1 = colour * tint;
    gl_Position = position * scale + offset;
}
)";

void setUniforms(std::span<const uint8_t> vp, std::span<const uint8_t> fp, GlslUniforms& u, const char* fragmentVec4) {
    float v[12];
    std::memcpy(v, vp.data(), sizeof v);
    u.setFloat("scale", 4, {v, 4});
    u.setFloat("offset", 4, {v + 4, 4});
    u.setFloat("tint", 4, {v + 8, 4});
    float f[4];
    std::memcpy(f, fp.data(), sizeof f);
    u.setFloat(fragmentVec4, 4, f);
}

GlslTwin twin(const char* fragmentShader, std::vector<std::string> samplers, std::vector<std::string> outputs,
              const char* fragmentVec4) {
    static_assert(sizeof(TransformVP) == 48 && sizeof(TexturedMrtFP) == 16 && sizeof(CompositeFP) == 16);
    GlslTwin t;
    t.vertexShader = kVertexShader;
    t.fragmentShader = fragmentShader;
    t.attributes = {{"position", 4, offsetof(TestVertex, position)},
                    {"uv", 4, offsetof(TestVertex, uv)},
                    {"colour", 4, offsetof(TestVertex, colour)}};
    t.samplers = std::move(samplers);
    t.outputs = std::move(outputs);
    t.uniforms = [fragmentVec4](std::span<const uint8_t> vp, std::span<const uint8_t> fp, GlslUniforms& u) {
        setUniforms(vp, fp, u, fragmentVec4);
    };
    return t;
}

void registerTwins() {
    registerTestPrograms();
    registerGlslTwin("test/textured_mrt", twin(R"(#version 130
uniform sampler2D unit0;
uniform vec4 bias;
in vec4 v0;
in vec4 v1;
out vec4 target0;
out vec4 target1;
void main() {
    vec4 t = texture(unit0, v0.xy);
    target0 = t * v1 + bias;
    target1 = vec4(v0.x, v0.y, t.z, 0.25);
}
)",
                                                   {"unit0"}, {"target0", "target1"}, "bias"));
    registerGlslTwin("test/composite", twin(R"(#version 130
uniform sampler2D unit0;
uniform sampler2D unit1;
uniform sampler2D unit2;
uniform vec4 weight;
in vec4 v0;
in vec4 v1;
out vec4 target0;
void main() {
    vec4 a = texture(unit0, v0.xy);
    vec4 b = textureLod(unit1, v0.xy, 0.0);
    vec4 c = textureLod(unit2, (v0 * 0.5).xy, 0.0);
    target0 = a * weight + b * (vec4(1.0) - weight) + vec4(c.x, 0.0, 0.0, 0.0);
}
)",
                                                {"unit0", "unit1", "unit2"}, {"target0"}, "weight"));
}

TEST(MesaProgramTrace, TheFrameThroughItsGlslTwinsIsOursWithinRounding) {
    registerTwins();
    const Trace t = readTrace(recordFrame().trace);
    ASSERT_EQ(conformance::oursOnlyReason(t), "");
    const conformance::MesaReplay mesa = conformance::replayOnMesa(t);
    ASSERT_TRUE(mesa.unsupported.empty());
    const ReplayResult ours = replayTrace(t, {Path::Reference, 1, -1});
    ASSERT_EQ(mesa.framebuffer.width(), 32);
    ASSERT_EQ(ours.framebuffer.width(), 32);
    const auto a = ours.framebuffer.color(), b = mesa.framebuffer.color();
    int maxDiff = 0;
    size_t large = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        const int d = std::max({std::abs(a[i].r - b[i].r), std::abs(a[i].g - b[i].g), std::abs(a[i].b - b[i].b),
                                std::abs(a[i].a - b[i].a)});
        maxDiff = std::max(maxDiff, d);
        large += d > kSmallDiff;
    }
    // What differs and why: docs/hardware.md, "Conformance against Mesa" (bilinear weights
    // from llvmpipe's own coordinates on random texels, pixels on edges and point borders
    // covered by one rasterizer and not the other, sampled again by the second pass). A
    // mapping mistake (a flipped row order, a culled strip, a lost scissor, viewport,
    // blend, write mask or uniform) changes whole regions, far past this share.
    EXPECT_LE(double(large) / double(a.size()), kMaxLargeShare)
        << large << " of " << a.size() << " pixels differ by more than " << kSmallDiff << " (largest " << maxDiff
        << "); reproduce: record the frame of tests/trace/program_frame.h and replay it with --backend mesa";
    // Both drew the frame: not the cleared target.
    EXPECT_GT(std::count_if(a.begin(), a.end(), [&](Rgba8 c) { return !(c == a[0]); }), 100);
}

TEST(MesaProgramTrace, AProgramWithoutAGlslTwinIsOursOnlyAndSaysWhy) {
    registerTestPrograms();
    tex::TextureMemory mem(g80());
    ProgrammableDevice dev(g80(), {Path::Fast, 1});
    tex::TextureDesc d;
    d.width = d.height = 8;
    const ColorTarget c[] = {{mem.createRenderTarget(d)}, {mem.createRenderTarget(d)}};
    dev.setRenderTargets(c);
    dev.setTexture(0, patternTexture(mem, 3));
    auto rec = std::make_shared<TraceRecorder>();
    dev.setRecorder(rec);
    const std::vector<ClipVertex> tri = {{{-1, 1, 0.5f, 1}}, {{1, 1, 0.5f, 1}}, {{-1, -1, 0.5f, 1}}};
    dev.draw(ClipVP{}, TexturedMrtFP{}, ProgramPrimitive::TriangleList, std::span<const ClipVertex>(tri));
    dev.setRecorder(nullptr);
    rec->finish();
    const Trace t = readTrace(rec->bytes());
    EXPECT_EQ(conformance::oursOnlyReason(t), "no GLSL twin registered for program 'test/clip_only'");
    EXPECT_FALSE(conformance::replayOnMesa(t).unsupported.empty());
}

}  // namespace
}  // namespace rg::raster
