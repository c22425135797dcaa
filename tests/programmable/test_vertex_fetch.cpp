// Vertex texture fetch on geforce8800 (docs/hardware.md, "Programmable profile: vertex
// texture fetch"): texelFetch and textureLod in vertex programs, the declared unit mask
// (kVertexUnits) checked at draw time, and both paths at any thread count.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/profile.h"
#include "rasterizer/programmable_device.h"

namespace rg::raster {
namespace {

using tex::TexelFormat;
using tex::TextureDesc;
using tex::TextureMemory;

const Profile& g80() { return profile(ProfileId::GeForce8800); }

struct TexelVertex {
    glm::ivec2 texel;  // which texel of unit 0 holds this point's (x, y, value)
};

constexpr int kW = 8, kH = 8;  // target size

// Each point's window position and value come from a texture: (x + ½, y + ½, value, 1)
// at its texel — the photon-splat pattern (positions written by an earlier pass).
struct FetchPositionVP {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kVertexUnits = 0b1;
    glm::vec4 operator()(const TexelVertex& v, Varyings& out, VertexContext& t) const {
        const glm::vec4 h = t.texelFetch(0, v.texel);
        out[0] = glm::vec4(h.z, 0.0f, 0.0f, 1.0f);
        return glm::vec4(2.0f * h.x / float(kW) - 1.0f, 1.0f - 2.0f * h.y / float(kH), 0.5f, 1.0f);
    }
};

// The same but reading unit 1, which it does not declare.
struct UndeclaredVP : FetchPositionVP {
    glm::vec4 operator()(const TexelVertex& v, Varyings& out, VertexContext& t) const {
        t.texelFetch(1, v.texel);
        return FetchPositionVP::operator()(v, out, t);
    }
};

// Declares unit 3 (bound or not, per test).
struct Unit3VP : FetchPositionVP {
    static constexpr uint32_t kVertexUnits = 0b1000;
    glm::vec4 operator()(const TexelVertex& v, Varyings& out, VertexContext& t) const {
        const glm::vec4 h = t.texelFetch(3, v.texel);
        out[0] = glm::vec4(h.z, 0.0f, 0.0f, 1.0f);
        return glm::vec4(2.0f * h.x / float(kW) - 1.0f, 1.0f - 2.0f * h.y / float(kH), 0.5f, 1.0f);
    }
};

// textureLod at a computed coordinate; the result becomes the varying, the point sits at
// pixel (0, 0).
struct LodVP {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kVertexUnits = 0b1;
    float s = 0.0f, lod = 0.0f;
    glm::vec4 operator()(const TexelVertex&, Varyings& out, VertexContext& t) const {
        out[0] = t.sampleLevel(0, glm::vec4(s, 0.5f, 0.0f, 0.0f), lod);
        return glm::vec4(2.0f * 0.5f / float(kW) - 1.0f, 1.0f - 2.0f * 0.5f / float(kH), 0.5f, 1.0f);
    }
};

struct VaryingFP {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const { f.output(0, f.varying(0)); }
};

struct Fixture {
    std::shared_ptr<TextureMemory> memory = std::make_shared<TextureMemory>(g80());
    std::shared_ptr<tex::Texture> floatTexture(int w, int h, const std::vector<float>& rgba) {
        TextureDesc d;
        d.format = TexelFormat::RGBA32F;
        d.width = w;
        d.height = h;
        auto t = memory->create(d);
        std::vector<uint8_t> b(rgba.size() * 4);
        std::memcpy(b.data(), rgba.data(), b.size());
        memory->upload(*t, 0, 0, b);
        return t;
    }
    std::shared_ptr<tex::Texture> target() {
        TextureDesc d;
        d.format = TexelFormat::R32F;
        d.width = kW;
        d.height = kH;
        return memory->createRenderTarget(d);
    }
};

// A 4×2 table of point positions and values: texel (i, j) sends its point to pixel
// (2i + j, 7 − i − 3j) with value 10·j + i + 1 (distinct pixels).
std::vector<float> positionTable() {
    std::vector<float> v;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i) {
            v.push_back(float(2 * i + j) + 0.5f);
            v.push_back(float(7 - i - 3 * j) + 0.5f);
            v.push_back(float(10 * j + i + 1));
            v.push_back(1.0f);
        }
    return v;
}

std::vector<TexelVertex> everyTexel() {
    std::vector<TexelVertex> v;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 4; ++i) v.push_back({{i, j}});
    return v;
}

TEST(VertexTextureFetch, TexelFetchPlacesEachPointWhereItsTexelSaysOnBothPathsAndAnyThreadCount) {
    Fixture fx;
    auto table = fx.floatTexture(4, 2, positionTable());
    const std::vector<TexelVertex> verts = everyTexel();
    std::vector<float> first;
    for (Path path : {Path::Reference, Path::Fast})
        for (int threads : {1, 2, 5}) {
            auto target = fx.target();
            ProgrammableDevice dev(g80(), DeviceOptions{path, threads});
            ColorTarget ct{target};
            dev.setRenderTargets({&ct, 1});
            dev.setTexture(0, table);
            dev.draw(FetchPositionVP{}, VaryingFP{}, ProgramPrimitive::PointList,
                     std::span<const TexelVertex>(verts));
            // The analytic answer: value 10·j + i + 1 at pixel (2i + j, 7 − i − 3j), 0 elsewhere.
            std::vector<float> expected(size_t(kW * kH), 0.0f);
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 4; ++i)
                    expected[size_t((7 - i - 3 * j) * kW + 2 * i + j)] = float(10 * j + i + 1);
            const float* got = target->renderDataR(0, 0);
            for (int p = 0; p < kW * kH; ++p)
                ASSERT_EQ(got[p], expected[size_t(p)]) << "pixel " << p << " path " << int(path) << " threads " << threads;
            EXPECT_EQ(dev.counters().vertexTextureFetches, verts.size());
            EXPECT_EQ(dev.counters().textureFetches, 0u);  // the fragment stage read nothing
            std::vector<float> bytes(got, got + kW * kH);
            if (first.empty()) first = bytes;
            EXPECT_EQ(bytes, first);
        }
}

// Reads out of range in x, in y, negative, a level and a face the texture lacks.
struct OutVP {
    static constexpr int kVaryings = 1;
    static constexpr uint32_t kVertexUnits = 0b1;
    glm::vec4 operator()(const TexelVertex& v, Varyings& out, VertexContext& t) const {
        const glm::vec4 a = t.texelFetch(0, v.texel);
        const glm::vec4 b = t.texelFetch(0, {0, 0}, 1);     // no level 1
        const glm::vec4 c = t.texelFetch(0, {0, 0}, 0, 1);  // no face 1
        out[0] = glm::vec4(a.x + a.y + a.z + a.w + b.x + b.w + c.x + c.w + 5.0f, 0, 0, 1);
        return glm::vec4(2.0f * 0.5f / float(kW) - 1.0f, 1.0f - 2.0f * 0.5f / float(kH), 0.5f, 1.0f);
    }
};

TEST(VertexTextureFetch, TexelFetchOutsideTheLevelReadsZeroAsD3D10Load) {
    Fixture fx;
    auto table = fx.floatTexture(4, 2, positionTable());
    // Out of range in x, in y, negative, a level and a face the texture lacks: all (0, 0, 0, 0),
    // so the point lands at window (0, 0) with value 0 — nothing but pixel (0, 0) is
    // touched, and its value is 0.
    const std::vector<TexelVertex> verts{{{4, 0}}, {{0, 2}}, {{-1, 0}}, {{0, -1}}};
    auto target = fx.target();
    ProgrammableDevice dev(g80());
    ColorTarget ct{target};
    dev.setRenderTargets({&ct, 1});
    dev.setTexture(0, table);
    dev.draw(OutVP{}, VaryingFP{}, ProgramPrimitive::PointList, std::span<const TexelVertex>(verts));
    EXPECT_EQ(target->renderDataR(0, 0)[0], 5.0f);  // every read was zero
    EXPECT_EQ(dev.counters().vertexTextureFetches, 3u * verts.size());
}

TEST(VertexTextureFetch, SampleLevelFiltersAtTheGivenLevel) {
    Fixture fx;
    // RGBA32F 2×1 (0, 1, 2, 3) and (4, 5, 6, 7): LINEAR at s = ½ weighs both texels ½ → their mean;
    // NEAREST at s = 0.3 → texel 0.
    auto t = fx.floatTexture(2, 1, {0, 1, 2, 3, 4, 5, 6, 7});
    TextureDesc d;
    d.format = TexelFormat::RGBA32F;
    d.width = kW;
    d.height = kH;
    auto rgba = fx.memory->createRenderTarget(d);
    ProgrammableDevice dev(g80());
    ColorTarget ct{rgba};
    dev.setRenderTargets({&ct, 1});
    const std::vector<TexelVertex> one{{{0, 0}}};
    tex::SamplerState linear;
    linear.magFilter = linear.minFilter = tex::FilterMode::Linear;
    linear.address.fill(tex::AddressMode::ClampToEdge);
    dev.setTexture(0, t, linear);
    dev.draw(LodVP{0.5f, 0.0f}, VaryingFP{}, ProgramPrimitive::PointList, std::span<const TexelVertex>(one));
    EXPECT_EQ(rgba->renderDataF(0, 0)[0], glm::vec4(2, 3, 4, 5));
    tex::SamplerState nearest = linear;
    nearest.magFilter = nearest.minFilter = tex::FilterMode::Nearest;
    dev.setTexture(0, t, nearest);
    dev.draw(LodVP{0.3f, 0.0f}, VaryingFP{}, ProgramPrimitive::PointList, std::span<const TexelVertex>(one));
    EXPECT_EQ(rgba->renderDataF(0, 0)[0], glm::vec4(0, 1, 2, 3));
    // LINEAR reads a 2×2 footprint (the one row clamped twice), NEAREST one texel.
    EXPECT_EQ(dev.counters().vertexTextureFetches, 4u + 1u);
}

TEST(VertexTextureFetch, UndeclaredUnboundAndTargetUnitsAreErrorsNamingTheUnit) {
    Fixture fx;
    auto table = fx.floatTexture(4, 2, positionTable());
    auto target = fx.target();
    ProgrammableDevice dev(g80());
    ColorTarget ct{target};
    dev.setRenderTargets({&ct, 1});
    const std::vector<TexelVertex> verts = everyTexel();
    auto message = [&](auto vp) {
        try {
            dev.draw(vp, VaryingFP{}, ProgramPrimitive::PointList, std::span<const TexelVertex>(verts));
        } catch (const InvalidState& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    // Unit 0 unbound.
    EXPECT_NE(message(FetchPositionVP{}).find("vertex program reads texture unit 0, which has no texture bound"),
              std::string::npos);
    dev.setTexture(0, table);
    // Unit 1 read but not declared.
    EXPECT_NE(message(UndeclaredVP{}).find("vertex program reads texture unit 1, which it does not declare in kVertexUnits"),
              std::string::npos);
    // Declared unit 3, unbound, although unit 0 is bound.
    EXPECT_NE(message(Unit3VP{}).find("vertex program reads texture unit 3, which has no texture bound"),
              std::string::npos);
    // A vertex unit that samples the draw's own target.
    dev.setTexture(3, target);
    EXPECT_NE(message(Unit3VP{}).find("vertex texture unit 3 samples render target 0 while the draw writes it"),
              std::string::npos);
    // Nothing was written by the refused draws; the unit-0 draw that was allowed is not run here.
    for (int p = 0; p < kW * kH; ++p) EXPECT_EQ(target->renderDataR(0, 0)[p], 0.0f) << p;
}

}  // namespace
}  // namespace rg::raster
