// `retroglass conform` tells right from wrong (issue 24, item 3): a golden trace passes
// when every pixel Mesa llvmpipe draws is ours within rounding or what a documented choice
// of docs/hardware.md made the other way gives (conformance/include/conformance/conform.h).
// Each test plants one bug in ours' copy of a golden trace — a wrong fill rule, a cube face
// flipped, an address mode swapped — keeps Mesa's image of the real trace, and expects the
// comparison to fail; the same comparison without the bug passes.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "conformance/conform.h"
#include "conformance/mesa_player.h"
#include "core/profile.h"
#include "rasterizer/device.h"

namespace rg::conformance {
namespace {

using raster::Trace;
using raster::TraceCommand;
using raster::TraceOp;

Trace golden(const std::string& name) {
    return raster::readTraceFile(RETROGLASS_SOURCE_DIR "/tests/golden/" + name + ".trace");
}

const Explanation& explanation(const std::string& name) {
    const Explanation* e = explanationFor(name);
    if (!e) throw Error("no explanation for " + name);
    return *e;
}

raster::Framebuffer mesaImage(const Trace& t, const Explanation& e) {
    MesaReplay m = replayOnMesa(peerTrace(t, e));
    if (!m.unsupported.empty()) throw Error("Mesa cannot play it: " + m.unsupported);
    return std::move(m.framebuffer);
}

std::string describe(const Comparison& c) {
    std::string s = std::to_string(c.beyond) + " beyond rounding, " + std::to_string(c.unexplained) + " unexplained";
    for (const auto& [name, n] : c.explainedBy) s += "; " + std::to_string(n) + " by " + name;
    return s;
}

TEST(ConformTellsRightFromWrong, EveryTraceWithAnExplanationPassesAsItIs) {
    for (const char* name : {"raster-fill-rule", "texture-cube-reflection", "texture-address-filter",
                             "raster-transform-clip-cull", "texgen-gl-modes"}) {
        const Trace t = golden(name);
        const Explanation& e = explanation(name);
        const Comparison c = compareWithPeer(oursAndAlternatives(t, e), mesaImage(t, e), e);
        EXPECT_TRUE(c.pass()) << name << ": " << describe(c);
    }
}

// A bottom-right fill rule is the top-left rule seen upside down: ours draws the trace
// turned by 180° (every pre-transformed vertex at (W − x, H − y)) and its image is turned
// back, so each tie on an edge through pixel centres goes to the other side. The frame's
// coordinates snap alike both ways round (none lies on half a subpixel step).
TEST(ConformTellsRightFromWrong, AWrongFillRuleFailsRasterFillRule) {
    const Trace real = golden("raster-fill-rule");
    const Explanation& e = explanation("raster-fill-rule");
    const raster::Framebuffer mesa = mesaImage(real, e);

    Trace turned = real;
    const float w = float(real.width), h = float(real.height);
    for (TraceCommand& c : turned.commands) {
        if (c.op == TraceOp::Draw) {
            ASSERT_EQ(c.space, raster::VertexSpace::Pretransformed);
            for (raster::Vertex& v : c.vertices) {
                v.position.x = w - v.position.x;
                v.position.y = h - v.position.y;
            }
        }
        if (c.op == TraceOp::Viewport) {  // the whole target either way round
            ASSERT_EQ(c.viewport.width, real.width);
            ASSERT_EQ(c.viewport.height, real.height);
        }
    }
    std::vector<OursImage> images = oursAndAlternatives(turned, e);
    for (OursImage& im : images) {
        const raster::Framebuffer f = im.image;
        for (int y = 0; y < real.height; ++y)
            for (int x = 0; x < real.width; ++x)
                im.image.pixel(x, y) = f.pixel(real.width - 1 - x, real.height - 1 - y);
    }
    const Comparison planted = compareWithPeer(images, mesa, e);
    EXPECT_FALSE(planted.pass()) << describe(planted);
    // The strip's top edges run through the centres of row 24: 24 pixels change sides.
    EXPECT_GE(planted.unexplained, 24u) << describe(planted);

    const Comparison right = compareWithPeer(oursAndAlternatives(real, e), mesa, e);
    EXPECT_TRUE(right.pass()) << describe(right);
}

// A cube face flipped: ours samples −X where +X is meant and the other way round (both
// faces' texels swapped in ours' copy of the texture, every level).
TEST(ConformTellsRightFromWrong, AFlippedCubeFaceFailsTextureCubeReflection) {
    const Trace real = golden("texture-cube-reflection");
    const Explanation& e = explanation("texture-cube-reflection");
    const raster::Framebuffer mesa = mesaImage(real, e);

    Trace flipped = real;
    int cubes = 0;
    for (auto& [id, t] : flipped.textures) {
        if (t.desc.target != tex::TextureTarget::CubeMap) continue;
        ++cubes;
        for (int l = 0; l < t.desc.levels; ++l) std::swap(t.levelFaces[size_t(6 * l)], t.levelFaces[size_t(6 * l + 1)]);
    }
    ASSERT_EQ(cubes, 1);
    const Comparison planted = compareWithPeer(oursAndAlternatives(flipped, e), mesa, e);
    EXPECT_FALSE(planted.pass()) << describe(planted);

    const Comparison right = compareWithPeer(oursAndAlternatives(real, e), mesa, e);
    EXPECT_TRUE(right.pass()) << describe(right);
}

// GL_CLAMP taken for CLAMP_TO_EDGE and the other way round (the address-mode confusion of
// a Direct3D mapping): the linear cells mix the border colour where they should not, and
// no texel-edge tie explains that.
TEST(ConformTellsRightFromWrong, ClampAndClampToEdgeSwappedFailTextureAddressFilter) {
    const Trace real = golden("texture-address-filter");
    const Explanation& e = explanation("texture-address-filter");
    const raster::Framebuffer mesa = mesaImage(real, e);

    Trace swapped = real;
    for (TraceCommand& c : swapped.commands)
        if (c.op == TraceOp::Sampler)
            for (tex::AddressMode& a : c.sampler.address)
                a = a == tex::AddressMode::Clamp         ? tex::AddressMode::ClampToEdge
                    : a == tex::AddressMode::ClampToEdge ? tex::AddressMode::Clamp
                                                         : a;
    const Comparison planted = compareWithPeer(oursAndAlternatives(swapped, e), mesa, e);
    EXPECT_FALSE(planted.pass()) << describe(planted);
}


// The fixed-function GL mapping (conformance/mesa_player.cpp) on what no golden trace Mesa
// plays has: initial colour and depth contents, a viewport and scissor off the target's
// centre and a scissored clear, pre-transformed triangles kept to the viewport, an
// untransformed triangle against the initial depth, drawPixels and copyPixels away from
// the diagonal. Every row of each is where ours puts it, within rounding; the same frame
// with its rows turned upside down is not.
TEST(ConformTellsRightFromWrong, TheGlMappingKeepsRowsRectanglesAndInitialContents) {
    using namespace raster;
    const Profile& p = profile(ProfileId::GeForce256);
    Device dev(p, 24, 20, DepthFormat::D24, {Path::Reference, 1});
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 24; ++x) {
            dev.framebuffer().pixel(x, y) = {uint8_t(10 * x), uint8_t(12 * y), 90, 200};
            dev.framebuffer().depth()[size_t(y * 24 + x)] = uint32_t(y) * 800000u;  // 0 … 0.9 down the rows
        }
    auto rec = std::make_shared<TraceRecorder>();
    dev.setRecorder(rec);
    PipelineState s;
    s.cull = CullMode::None;
    s.depthFunc = CompareFunc::Less;
    s.scissorTest = 1;
    dev.setState(s);
    dev.setViewport({2, 3, 16, 12, 0.0f, 1.0f});
    dev.setScissor({4, 1, 18, 9});
    dev.clear(true, {200, 40, 40, 255}, false, 1.0f);  // rows 3 … 9 of columns 4 … 17
    s.scissorTest = 0;
    dev.setState(s);
    // Pre-transformed, half in the viewport: rows 3 … 14 and columns 2 … 17 only.
    std::vector<Vertex> tri(3);
    tri[0].position = {0.25f, 0.25f, 0.1f, 1};
    tri[1].position = {23.25f, 6.25f, 0.1f, 1};
    tri[2].position = {9.25f, 19.75f, 0.1f, 1};
    tri[0].diffuse = {255, 255, 0, 255};
    tri[1].diffuse = {0, 255, 255, 255};
    tri[2].diffuse = {255, 0, 255, 255};
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
    // Untransformed at window depth 0.45: in front of the initial depth from row 10 down.
    dev.setViewport({0, 0, 24, 20, 0.0f, 1.0f});
    std::vector<Vertex> quad(4);
    const float xs[] = {-0.9f, 0.8f, 0.8f, -0.9f}, ys[] = {0.9f, 0.9f, -0.7f, -0.7f};
    for (int i = 0; i < 4; ++i) {
        quad[size_t(i)].position = {xs[i], ys[i], 0.45f, 1};
        quad[size_t(i)].diffuse = {uint8_t(60 * i), 30, 220, 255};
    }
    dev.draw(Primitive::TriangleFan, VertexSpace::Untransformed, quad);
    std::vector<Rgba8> block(5 * 3);
    for (size_t i = 0; i < block.size(); ++i) block[i] = {uint8_t(17 * i), 255, uint8_t(250 - 13 * i), 255};
    dev.drawPixels(1, 14, 5, 3, block);
    dev.copyPixels(0, 0, 7, 4, 16, 15);
    dev.setRecorder(nullptr);
    rec->finish();
    const Trace t = readTrace(rec->bytes());
    ASSERT_FALSE(t.initialColor.empty());
    ASSERT_FALSE(t.initialDepth.empty());

    Explanation e;
    e.smallDiff = 2;
    e.choices = {{Alternative{"subpixel-8", 8, nullptr, nullptr}}};
    const raster::Framebuffer mesa = mesaImage(t, e);
    const Comparison c = compareWithPeer(oursAndAlternatives(t, e), mesa, e);
    EXPECT_TRUE(c.pass()) << describe(c);
    EXPECT_EQ(c.beyond, 0u) << describe(c);

    // Upside down it is not the frame: the comparison sees rows.
    std::vector<OursImage> flipped = oursAndAlternatives(t, e);
    for (OursImage& im : flipped) {
        const raster::Framebuffer f = im.image;
        for (int y = 0; y < f.height(); ++y)
            for (int x = 0; x < f.width(); ++x) im.image.pixel(x, y) = f.pixel(x, f.height() - 1 - y);
    }
    EXPECT_FALSE(compareWithPeer(flipped, mesa, e).pass());
}

}  // namespace
}  // namespace rg::conformance
