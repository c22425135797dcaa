// End to end through rg::raster::Device: textured triangles with random stage states
// must give identical bytes on Path::Reference and Path::Fast; a 1:1 textured quad must
// reproduce its texels; a pixel-texture drawPixels through an identity texture must
// leave the image unchanged.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "rasterizer/device.h"
#include "tex_test_util.h"
#include "texunit/texture_units.h"

namespace rg::tex {
namespace {

using raster::Device;
using raster::DepthFormat;
using raster::PipelineState;
using raster::Primitive;
using raster::Vertex;
using raster::VertexSpace;
using testing::makeRgba8;
using testing::Rng;

PipelineState plain() {
    PipelineState s;
    s.cull = raster::CullMode::None;
    s.depthTest = 0;
    s.depthWrite = 0;
    return s;
}

Vertex tv(float x, float y, glm::vec4 t0, Rgba8 d = {255, 255, 255, 255}) {
    Vertex v;
    v.position = {x, y, 0.5f, 1.0f};
    v.diffuse = d;
    v.tex[0] = t0;
    return v;
}

TEST(DeviceTextured, OneToOneQuadReproducesTexels) {
    const Profile& p = profile(ProfileId::GeForce256);
    TextureMemory mem(p);
    auto tex = makeRgba8(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 8, 8, 1, 1, 1},
                         [](int, int, int x, int y, int, int) {
                             return Rgba8{uint8_t(x * 30), uint8_t(y * 30), uint8_t(x ^ y), 255};
                         });
    for (Path path : {Path::Reference, Path::Fast}) {
        Device dev(p, 8, 8, DepthFormat::None, {path, 2});
        dev.setState(plain());
        auto& tu = dev.textureUnits();
        tu.setTexture(0, tex);
        SamplerState s;
        s.magFilter = s.minFilter = FilterMode::Nearest;
        tu.setSampler(0, s);
        StageState st;
        st.colorOp = TextureOp::SelectArg1;
        st.alphaOp = TextureOp::SelectArg1;
        tu.setStage(0, st);
        dev.clear(true, {0, 0, 0, 0}, false, 1.0f);
        std::vector<Vertex> quad = {tv(0, 0, {0, 0, 0, 1}), tv(8, 0, {1, 0, 0, 1}),
                                    tv(8, 8, {1, 1, 0, 1}), tv(0, 8, {0, 1, 0, 1})};
        dev.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, quad);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
                ASSERT_EQ(dev.framebuffer().pixel(x, y), tex->texel8(0, 0, x, y, 0, 0))
                    << pathName(path) << " pixel " << x << "," << y;
    }
}

// Coordinate generation of pre-transformed vertices, which have no eye space (pinned in
// docs/hardware.md, "Coordinate generation"): the object and eye position are the submitted
// (x, y, z, RHW) — window pixels, window depth and RHW — and the normal the submitted one as
// it is (not normalized). Seen in the interpolated coordinates of a quad (the fragment
// observer), with the same RHW at every vertex so that the interpolation is affine.
TEST(DeviceTextured, PretransformedTexGenSeesTheSubmittedWindowPosition) {
    struct Case {
        ProfileId profile;
        TexGenMode mode;
        glm::vec4 expect;  // at the centre of pixel (2, 3)
    };
    const Case cases[] = {
        {ProfileId::GeForce256, TexGenMode::CameraSpacePosition, {2.5f, 3.5f, 0.25f, 1.0f}},
        {ProfileId::GeForce256, TexGenMode::CameraSpaceNormal, {0.0f, 0.0f, 2.0f, 1.0f}},
        // OBJECT_LINEAR's planes over (x, y, z, w) with w the submitted RHW (0.5 here).
        {ProfileId::SgiOctaneMxe, TexGenMode::ObjectLinear, {2.5f, 3.5f, 0.25f, 0.5f}},
        {ProfileId::SgiOctaneMxe, TexGenMode::EyeLinear, {2.5f, 3.5f, 0.25f, 0.5f}},
    };
    for (const Case& c : cases) {
        const Profile& p = profile(c.profile);
        TextureMemory mem(p);
        auto tex = makeRgba8(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 2, 2, 1, 1, 1},
                             [](int, int, int, int, int, int) { return Rgba8{255, 255, 255, 255}; });
        Device dev(p, 8, 8, DepthFormat::None, {Path::Reference, 1});
        dev.setState(plain());
        auto& tu = dev.textureUnits();
        tu.setTexture(0, tex);
        StageState st;
        st.colorOp = TextureOp::Modulate;
        st.alphaOp = TextureOp::Modulate;
        tu.setStage(0, st);
        TexGenState g;
        g.mode = c.mode;  // default planes: s = x, t = y, r = z, q = w
        tu.setTexGen(0, g);
        glm::vec4 seen(-1.0f);
        dev.setFragmentObserver([&](const FragmentQuad& q, uint8_t) {
            if (q.x == 2 && q.y == 2) seen = q.texCoord[0][2];  // pixel 2 of the quad: (2, 3)
        });
        std::vector<Vertex> tri = {tv(0, 0, {}), tv(8, 0, {}), tv(0, 8, {})};
        for (Vertex& v : tri) {
            v.position.z = 0.25f;
            v.position.w = 0.5f;  // RHW
            v.normal = {0.0f, 0.0f, 2.0f};
        }
        dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(seen[k], c.expect[k], 1e-5f) << int(c.mode) << " component " << k;
    }
}

TEST(DeviceTextured, PixelTextureDrawPixelsThroughIdentityLeavesImage) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    TextureMemory mem(p);
    auto id = makeRgba8(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 256, 256, 1, 1, 1},
                        [](int, int, int x, int y, int, int) { return Rgba8{uint8_t(x), uint8_t(y), 0, 255}; });
    for (Path path : {Path::Reference, Path::Fast}) {
        Device dev(p, 64, 32, DepthFormat::None, {path, 2});
        dev.setState(plain());
        auto& tu = dev.textureUnits();
        tu.setTexture(0, id);
        SamplerState s;
        s.magFilter = s.minFilter = FilterMode::Nearest;
        s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge,
                     AddressMode::ClampToEdge};
        tu.setSampler(0, s);
        tu.setPixelTexture({true, PixelTexGenMode::Rgba, 0});
        std::vector<Rgba8> image(64 * 32);
        for (size_t i = 0; i < image.size(); ++i)
            image[i] = {uint8_t(testing::hash32(uint32_t(i))), uint8_t(i), 0, 255};
        dev.drawPixels(0, 0, 64, 32, image);
        EXPECT_EQ(dev.readPixels(0, 0, 64, 32), image) << pathName(path);
    }
}

// Renders a small perspective scene of textured triangles with random two-stage states;
// returns the framebuffer bytes.
std::vector<Rgba8> renderRandom(Path path, uint32_t seed, TextureMemory& mem,
                                const std::vector<std::shared_ptr<Texture>>& textures) {
    const Profile& p = mem.profile();
    Device dev(p, 96, 80, DepthFormat::D24, {path, 2});
    Rng rng(seed);
    PipelineState ps;
    ps.cull = raster::CullMode::None;
    ps.blend = uint8_t(rng.below(2));
    ps.srcBlend = raster::BlendFactor::SrcAlpha;
    ps.dstBlend = raster::BlendFactor::InvSrcAlpha;
    ps.specularEnable = uint8_t(rng.below(2));
    dev.setState(ps);
    dev.setTransforms(glm::mat4(1.0f), glm::lookAt(glm::vec3(0, 0, 3), glm::vec3(0), glm::vec3(0, 1, 0)),
                      glm::perspective(0.9f, 96.0f / 80.0f, 0.5f, 10.0f));
    auto& tu = dev.textureUnits();
    const int n = 1 + int(rng.below(2));
    for (int i = 0; i < n; ++i) {
        StageState st;
        st.colorOp = TextureOp(1 + rng.below(uint32_t(TextureOp::DotProduct3)));
        st.alphaOp = TextureOp(1 + rng.below(uint32_t(TextureOp::BlendCurrentAlpha)));
        auto anyArg = [&] {
            uint8_t a = uint8_t(rng.below(5));
            if (rng.below(4) == 0) a |= arg::Complement;
            if (rng.below(4) == 0) a |= arg::AlphaReplicate;
            return a;
        };
        st.colorArg1 = rng.below(2) ? arg::Texture : anyArg();
        st.colorArg2 = anyArg();
        st.alphaArg1 = anyArg();
        st.alphaArg2 = anyArg();
        st.texCoordIndex = uint8_t(rng.below(2));
        tu.setStage(i, st);
        tu.setTexture(i, textures[rng.below(uint32_t(textures.size()))]);
        SamplerState s;
        for (auto& a : s.address) a = AddressMode(rng.below(5));
        s.magFilter = FilterMode(rng.below(2));
        s.minFilter = FilterMode(rng.below(2));
        s.mipFilter = MipMode(rng.below(3));
        tu.setSampler(i, s);
    }
    TexGenState g;
    g.mode = rng.below(2) ? TexGenMode::CameraSpaceReflectionVector : TexGenMode::PassThru;
    tu.setTexGen(1, g);
    tu.setTextureFactor({uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())});
    dev.clear(true, {20, 30, 40, 255}, true, 1.0f);
    std::vector<Vertex> verts;
    for (int k = 0; k < 24; ++k) {
        Vertex v;
        v.position = {rng.uniform(-1.5f, 1.5f), rng.uniform(-1.2f, 1.2f), rng.uniform(-1.5f, 1.0f), 1};
        v.normal = glm::normalize(glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), 1.0f));
        v.diffuse = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())};
        v.specular = {uint8_t(rng.next() & 63), uint8_t(rng.next() & 63), uint8_t(rng.next() & 63), 0};
        v.tex[0] = {rng.uniform(-1, 2), rng.uniform(-1, 2), rng.uniform(-1, 1), 1};
        v.tex[1] = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), 1};
        verts.push_back(v);
    }
    dev.draw(Primitive::TriangleList, VertexSpace::Untransformed, verts);
    return dev.readPixels(0, 0, 96, 80);
}

TEST(DeviceTextured, ReferenceAndFastGiveIdenticalBytesUnderRandomStageStates) {
    const Profile& p = profile(ProfileId::GeForce256);
    TextureMemory mem(p);
    std::vector<std::shared_ptr<Texture>> textures = {
        makeRgba8(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 32, 16, 1, 1, 6},
                  [](int l, int, int x, int y, int, int) {
                      uint32_t h = testing::hash32(uint32_t(l * 1000 + y * 40 + x));
                      return Rgba8{uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
                  }),
        makeRgba8(mem, {TextureTarget::CubeMap, TexelFormat::RGBA8, 16, 16, 1, 1, 5},
                  [](int l, int f, int x, int y, int, int) {
                      return Rgba8{uint8_t(f * 40 + x * 3), uint8_t(l * 50 + y * 3), uint8_t(x * y), 180};
                  }),
        makeRgba8(mem, {TextureTarget::Texture1D, TexelFormat::RGBA8, 64, 1, 1, 1, 7},
                  [](int l, int, int x, int, int, int) {
                      return Rgba8{uint8_t(x * 4), uint8_t(255 - x * 4), uint8_t(l * 30), uint8_t(x * 4)};
                  }),
        nullptr};
    int drawn = 0;
    for (uint32_t seed = 1; seed <= 24; ++seed) {
        auto ref = renderRandom(Path::Reference, seed, mem, textures);
        auto fast = renderRandom(Path::Fast, seed, mem, textures);
        ASSERT_EQ(ref, fast) << "seed " << seed;
        drawn += ref != std::vector<Rgba8>(ref.size(), Rgba8{20, 30, 40, 255});
    }
    EXPECT_GT(drawn, 20);  // the scenes really drew something
}

}  // namespace
}  // namespace rg::tex
