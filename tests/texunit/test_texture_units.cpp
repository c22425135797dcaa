// The texture units as the rasterizer sees them: which sets are interpolated, validation
// against the profiles, the cascade on a quad (reference against fast under random
// states), and the instrumented tap query the PEM demo uses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/error.h"
#include "tex_test_util.h"
#include "texunit/cube_mapping.h"
#include "texunit/texture_units.h"

namespace rg::tex {
namespace {

using testing::makeRgba8;
using testing::Rng;

StageState op(TextureOp c, uint8_t a1 = arg::Texture, uint8_t a2 = arg::Current,
              TextureOp a = TextureOp::SelectArg1, uint8_t set = 0) {
    StageState s;
    s.colorOp = c;
    s.colorArg1 = a1;
    s.colorArg2 = a2;
    s.alphaOp = a;
    s.texCoordIndex = set;
    return s;
}

struct Fixture {
    const Profile& gf = profile(ProfileId::GeForce256);
    std::shared_ptr<TextureMemory> mem = std::make_shared<TextureMemory>(gf);
    std::shared_ptr<Texture> tex2d = makeRgba8(
        *mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 16, 16, 1, 1, 5},
        [](int l, int, int x, int y, int, int) {
            return Rgba8{uint8_t(x * 16), uint8_t(y * 16), uint8_t(l * 50), uint8_t(255 - x * y)};
        });
    std::shared_ptr<Texture> cube = makeRgba8(
        *mem, {TextureTarget::CubeMap, TexelFormat::RGBA8, 8, 8, 1, 1, 4},
        [](int l, int f, int x, int y, int, int) {
            return Rgba8{uint8_t(f * 40 + x), uint8_t(l * 60 + y), uint8_t(x * y * 3), uint8_t(200 + f)};
        });
    std::shared_ptr<Texture> fresnel = makeRgba8(
        *mem, {TextureTarget::Texture1D, TexelFormat::RGBA8, 32, 1, 1, 1, 6},
        [](int l, int, int x, int, int, int) {
            return Rgba8{uint8_t(x * 8), uint8_t(x * 8), uint8_t(x * 8 + l), uint8_t(x * 8)};
        });
};

TEST(TextureUnits, DefaultIsPassThrough) {
    TextureUnits tu;
    EXPECT_TRUE(tu.passThrough());
    EXPECT_EQ(tu.texCoordSetsUsed(), 0u);
    FragmentQuad q;
    q.diffuse = {Rgba8{1, 2, 3, 4}, Rgba8{5, 6, 7, 8}, Rgba8{9, 10, 11, 12}, Rgba8{13, 14, 15, 16}};
    std::array<Rgba8, 4> out;
    tu.shadeQuad(q, out, Path::Fast);
    EXPECT_EQ(out, q.diffuse);
    EXPECT_NO_THROW(tu.validate(profile(ProfileId::SgiO2)));
}

TEST(TextureUnits, UnboundTextureReadsWhite) {
    TextureUnits tu;
    tu.setStage(0, op(TextureOp::SelectArg1, arg::Texture, arg::Current, TextureOp::SelectArg1));
    FragmentQuad q;
    q.diffuse.fill(Rgba8{1, 2, 3, 4});
    std::array<Rgba8, 4> out;
    tu.shadeQuad(q, out, Path::Reference);
    EXPECT_EQ(out[0], (Rgba8{255, 255, 255, 255}));
    tu.setStage(0, op(TextureOp::Modulate, arg::Texture, arg::Diffuse, TextureOp::Modulate));
    tu.shadeQuad(q, out, Path::Fast);
    EXPECT_EQ(out[3], (Rgba8{1, 2, 3, 4}));
}

TEST(TextureUnits, CoordinateSetsUsedFollowTheStagesThatReadTextures) {
    Fixture fx;
    TextureUnits tu;
    tu.setStage(0, op(TextureOp::Modulate, arg::Texture, arg::Diffuse, TextureOp::SelectArg1, 3));
    EXPECT_EQ(tu.texCoordSetsUsed(), 0u);  // no texture bound: TEXTURE is white
    tu.setTexture(0, fx.tex2d);
    EXPECT_EQ(tu.texCoordSetsUsed(), 1u << 3);
    EXPECT_FALSE(tu.passThrough());
    tu.setStage(1, op(TextureOp::SelectArg1, arg::Diffuse, arg::Current, TextureOp::SelectArg1, 5));
    tu.setTexture(1, fx.cube);
    // Stage 1 names set 5 but neither its colour nor its alpha op reads TEXTURE.
    StageState s1 = tu.stage(1);
    s1.alphaArg1 = arg::Diffuse;
    tu.setStage(1, s1);
    EXPECT_EQ(tu.texCoordSetsUsed(), 1u << 3);
    s1.colorArg1 = arg::Texture | arg::Complement;
    tu.setStage(1, s1);
    EXPECT_EQ(tu.texCoordSetsUsed(), (1u << 3) | (1u << 5));
    // Stages after a disabled one are ignored.
    StageState off;
    tu.setStage(0, off);
    EXPECT_EQ(tu.texCoordSetsUsed(), 0u);
    EXPECT_TRUE(tu.passThrough());
}

TEST(TextureUnits, ValidateAgainstProfiles) {
    Fixture fx;
    TextureUnits tu;
    tu.setTexture(0, fx.tex2d);
    tu.setStage(0, op(TextureOp::Modulate));
    tu.setStage(1, op(TextureOp::Add, arg::Diffuse));
    EXPECT_NO_THROW(tu.validate(fx.gf));
    tu.setStage(2, op(TextureOp::Add, arg::Diffuse));
    EXPECT_THROW(tu.validate(fx.gf), UnsupportedFeature);  // 3 stages > 2 on a GeForce 256
    EXPECT_NO_THROW(tu.validate(profile(ProfileId::GeForce3)));
    tu.setStage(1, StageState{});
    // D3D-only ops on the SGI machines, and more than one unit there.
    tu.setStage(0, op(TextureOp::DotProduct3));
    EXPECT_THROW(tu.validate(profile(ProfileId::SgiOctaneMxe)), UnsupportedFeature);
    tu.setStage(0, op(TextureOp::Modulate));
    EXPECT_NO_THROW(tu.validate(profile(ProfileId::SgiOctaneMxe)));
    tu.setStage(1, op(TextureOp::Modulate));
    EXPECT_THROW(tu.validate(profile(ProfileId::SgiOctaneMxe)), UnsupportedFeature);
    tu.setStage(1, StageState{});
    // D3DTOP_LERP is Direct3D 8; colour-only ops refuse to be ALPHAOPs.
    tu.setStage(0, op(TextureOp::Lerp));
    EXPECT_THROW(tu.validate(fx.gf), UnsupportedFeature);
    // (refused as the stage is set, so that no state the device holds has one)
    EXPECT_THROW(tu.setStage(0, op(TextureOp::Modulate, arg::Texture, arg::Current, TextureOp::ModulateAlphaAddColor)),
                 InvalidState);
    // An incomplete texture cannot be drawn with.
    auto partial = fx.mem->create({TextureTarget::Texture2D, TexelFormat::RGBA8, 4, 4, 1, 1, 3});
    fx.mem->upload(*partial, 0, 0, std::vector<uint8_t>(64));
    tu.setStage(0, op(TextureOp::Modulate));
    tu.setTexture(0, partial);
    EXPECT_THROW(tu.validate(fx.gf), InvalidState);
    // glTexGen modes exist on the OpenGL machines only.
    tu.setTexture(0, fx.tex2d);
    TexGenState sphere;
    sphere.mode = TexGenMode::SphereMap;
    tu.setTexGen(0, sphere);
    EXPECT_THROW(tu.validate(fx.gf), UnsupportedFeature);
    EXPECT_NO_THROW(tu.validate(profile(ProfileId::SgiOctaneMxe)));
    sphere.mode = TexGenMode::CameraSpaceReflectionVector;
    tu.setTexGen(0, sphere);
    EXPECT_NO_THROW(tu.validate(fx.gf));
    // A stage index past the device's array is refused at once.
    EXPECT_THROW(tu.setStage(kMaxStages, StageState{}), InvalidState);
}

TEST(TextureUnits, TextureMatrixQDivideAndGeneratedCoordinates) {
    Fixture fx;
    TextureUnits tu;
    TexGenState g;
    g.mode = TexGenMode::CameraSpacePosition;
    g.matrixEnabled = true;
    g.matrix = glm::mat4(0.5f);  // (x, y, z, 1) → ½(x, y, z, 1)
    tu.setTexGen(2, g);
    TexGenState projected;
    projected.projected = true;
    tu.setTexGen(0, projected);
    VertexEye v{};
    v.eyePosition = {2, 4, 6, 1};
    EXPECT_EQ(tu.processVertexTexCoord(2, v, glm::vec4(9)), glm::vec4(1, 2, 3, 0.5f));
    EXPECT_EQ(tu.processVertexTexCoord(0, v, glm::vec4(9)), glm::vec4(9));
    // q divide at the pixel on a projected set: s/q = 0.53125 → texel 8 of 16.
    tu.setTexture(0, fx.tex2d);
    SamplerState s;
    s.magFilter = s.minFilter = FilterMode::Nearest;
    tu.setSampler(0, s);
    tu.setStage(0, op(TextureOp::SelectArg1));
    FragmentQuad q;
    for (auto& c : q.texCoord[0]) c = {0.265625f, 0.265625f, 0, 0.5f};
    std::array<Rgba8, 4> out;
    tu.shadeQuad(q, out, Path::Reference);
    EXPECT_EQ(out[0], (Rgba8{128, 128, 0, 255 - 64}));
    // Not projected (the Direct3D 7 default): q is ignored, even q = 0.
    tu.setTexGen(0, TexGenState{});
    for (auto& c : q.texCoord[0]) c = {0.53125f, 0.53125f, 0, 0};
    tu.shadeQuad(q, out, Path::Reference);
    EXPECT_EQ(out[0], (Rgba8{128, 128, 0, 255 - 64}));
}

TEST(TextureUnits, PreModulateMultipliesTheNextStagesTexture) {
    Fixture fx;
    TextureUnits tu;
    auto white = makeRgba8(*fx.mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 1, 1, 1, 1, 1},
                           [](int, int, int, int, int, int) { return Rgba8{128, 255, 64, 255}; });
    auto other = makeRgba8(*fx.mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 1, 1, 1, 1, 1},
                           [](int, int, int, int, int, int) { return Rgba8{255, 128, 128, 128}; });
    tu.setTexture(0, white);
    tu.setTexture(1, other);
    tu.setStage(0, op(TextureOp::PreModulate));
    tu.setStage(1, op(TextureOp::SelectArg1));
    FragmentQuad q;
    std::array<Rgba8, 4> out;
    tu.shadeQuad(q, out, Path::Reference);
    EXPECT_EQ(out[0], (Rgba8{128, 128, 32, 128}));
}

// A random stage state: every op, argument modifier and scale (validity per profile is
// not the point here, equal bytes are).
StageState randomStage(Rng& rng, int sets) {
    StageState s;
    auto anyArg = [&] {
        uint8_t a = uint8_t(rng.below(5));
        if (rng.below(4) == 0) a |= arg::Complement;
        if (rng.below(4) == 0) a |= arg::AlphaReplicate;
        return a;
    };
    // Every op (SelectArg1..Lerp) as COLOROP; as ALPHAOP every op but the colour-only ones.
    s.colorOp = TextureOp(1 + rng.below(uint32_t(TextureOp::Lerp)));
    do {
        s.alphaOp = TextureOp(1 + rng.below(uint32_t(TextureOp::Lerp)));
    } while (s.alphaOp >= TextureOp::ModulateAlphaAddColor && s.alphaOp <= TextureOp::ModulateInvColorAddAlpha);
    s.colorArg1 = anyArg();
    s.colorArg2 = anyArg();
    s.colorArg0 = anyArg();
    s.alphaArg1 = anyArg();
    s.alphaArg2 = anyArg();
    s.alphaArg0 = anyArg();
    s.colorScaleShift = uint8_t(rng.below(4) == 0 ? rng.below(3) : 0);
    s.alphaScaleShift = uint8_t(rng.below(4) == 0 ? rng.below(3) : 0);
    s.texCoordIndex = uint8_t(rng.below(uint32_t(sets)));
    return s;
}

TEST(TextureUnits, ShadeQuadFastMatchesReferenceUnderRandomStates) {
    Fixture fx;
    Rng rng(77);
    const std::shared_ptr<Texture> textures[] = {fx.tex2d, fx.cube, fx.fresnel, nullptr};
    int quads = 0;
    // Many states, few quads each: every op and argument modifier reaches the SSE2 cascade
    // (stage_arith.h, quad::) and its per-pixel fallback, up to three stages deep.
    for (int stateI = 0; stateI < 1500; ++stateI) {
        TextureUnits tu;
        const int n = 1 + int(rng.below(3));
        for (int i = 0; i < n; ++i) {
            StageState st = randomStage(rng, 3);
            if (rng.below(3) == 0) {
                // The (colour, alpha) op pairs with their own SSE2 instantiation
                // (quad::StageKernel), with random arguments and scales.
                static constexpr std::pair<TextureOp, TextureOp> kFixed[] = {
                    {TextureOp::SelectArg1, TextureOp::SelectArg1}, {TextureOp::Modulate, TextureOp::Modulate},
                    {TextureOp::Modulate, TextureOp::SelectArg1}, {TextureOp::Modulate, TextureOp::SelectArg2},
                    {TextureOp::SelectArg1, TextureOp::Modulate},
                    {TextureOp::BlendFactorAlpha, TextureOp::BlendFactorAlpha},
                    {TextureOp::BlendTextureAlpha, TextureOp::Disable}};
                std::tie(st.colorOp, st.alphaOp) = kFixed[rng.below(7)];
            }
            if (rng.below(4) == 0) {
                // Alpha the same op on the same arguments (GL MODULATE/REPLACE): the SSE2
                // cascade then keeps the colour result's alpha byte.
                st.alphaOp = st.colorOp == TextureOp::DotProduct3 ? st.alphaOp : st.colorOp;
                if (st.alphaOp >= TextureOp::ModulateAlphaAddColor && st.alphaOp <= TextureOp::ModulateInvColorAddAlpha)
                    st.alphaOp = TextureOp::Modulate;
                st.alphaArg1 = st.colorArg1;
                st.alphaArg2 = st.colorArg2;
                st.alphaArg0 = st.colorArg0;
                st.alphaScaleShift = rng.below(3) ? st.colorScaleShift : uint8_t(rng.below(3));
            }
            tu.setStage(i, st);
            tu.setTexture(i, textures[rng.below(4)]);
            SamplerState s;
            for (auto& a : s.address) a = AddressMode(rng.below(5));
            s.magFilter = FilterMode(rng.below(2));
            s.minFilter = FilterMode(rng.below(2));
            s.mipFilter = MipMode(rng.below(3));
            s.lodBias = rng.uniform(-1, 1);
            s.borderColor = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()),
                             uint8_t(rng.next())};
            tu.setSampler(i, s);
        }
        tu.setTextureFactor({uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()),
                             uint8_t(rng.next())});
        for (int k = 0; k < 20; ++k) {
            FragmentQuad q;
            const float scale = rng.uniform(0.001f, 0.3f);
            for (int set = 0; set < 3; ++set) {
                glm::vec4 base(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2), 1.0f);
                glm::vec4 dx(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), 0.0f);
                glm::vec4 dy(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), 0.0f);
                for (int p = 0; p < 4; ++p)
                    q.texCoord[size_t(set)][size_t(p)] =
                        base + scale * (float(p & 1) * dx + float(p >> 1) * dy);
            }
            for (int p = 0; p < 4; ++p) {
                q.diffuse[size_t(p)] = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()),
                                        uint8_t(rng.next())};
                q.specular[size_t(p)] = {uint8_t(rng.next()), uint8_t(rng.next()),
                                         uint8_t(rng.next()), uint8_t(rng.next())};
            }
            std::array<Rgba8, 4> ref, fast;
            tu.shadeQuad(q, ref, Path::Reference);
            tu.shadeQuad(q, fast, Path::Fast);
            ASSERT_EQ(ref, fast) << "state " << stateI << " quad " << k << " (seed 77)" << [&] {
                std::string d;
                for (int i = 0; i < n; ++i) {
                    const StageState& s = tu.stage(i);
                    d += " | " + std::string(textureOpName(s.colorOp)) + "(" + std::to_string(s.colorArg1) + "," +
                         std::to_string(s.colorArg2) + "," + std::to_string(s.colorArg0) + ")<<" +
                         std::to_string(s.colorScaleShift) + " a:" + std::string(textureOpName(s.alphaOp)) + "(" +
                         std::to_string(s.alphaArg1) + "," + std::to_string(s.alphaArg2) + "," +
                         std::to_string(s.alphaArg0) + ")<<" + std::to_string(s.alphaScaleShift);
                }
                return d;
            }();
            ++quads;
        }
    }
    EXPECT_EQ(quads, 30000);
}

// The compiled per-quad samplers (texunit/filter_quad.cpp) against the reference, state by
// state: every target they take (1D, 2D incl. non-square, cube), every filter and mip mode,
// CLAMP_TO_EDGE and power-of-two WRAP on each axis, projected and not, biases and LOD
// clamps that reach magnification, both blended levels and the last level; plus the states
// that must fall back to the generic path (MIRROR, BORDER, CLAMP, WRAP on a
// non-power-of-two extent, colour tables). Bytes and texel-fetch counts must agree.
void compiledSamplersAgainstReference() {
    const Profile& g8 = profile(ProfileId::GeForce8800);  // allows non-power-of-two sizes
    auto mem = std::make_shared<TextureMemory>(g8);
    auto texel = [](int l, int f, int x, int y, int, int) {
        const uint32_t h = testing::hash32(uint32_t(((l * 7 + f) * 131 + x) * 977 + y));
        return Rgba8{uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
    };
    const std::shared_ptr<Texture> textures[] = {
        makeRgba8(*mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 32, 8, 1, 1, 6}, texel),
        makeRgba8(*mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 16, 16, 1, 1, 1}, texel),
        makeRgba8(*mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 12, 20, 1, 1, 5}, texel),
        makeRgba8(*mem, {TextureTarget::Texture1D, TexelFormat::RGBA8, 64, 1, 1, 1, 7}, texel),
        makeRgba8(*mem, {TextureTarget::Texture1D, TexelFormat::RGBA8, 24, 1, 1, 1, 1}, texel),
        makeRgba8(*mem, {TextureTarget::CubeMap, TexelFormat::RGBA8, 16, 16, 1, 1, 5}, texel),
        makeRgba8(*mem, {TextureTarget::CubeMap, TexelFormat::RGBA8, 8, 8, 1, 1, 1}, texel),
    };
    auto table = std::make_shared<ColorTable>();
    table->format = BaseFormat::Rgba;
    for (int i = 0; i < 256; ++i) table->entries.push_back(texel(9, 9, i, 3, 0, 0));
    const AddressMode modes[] = {AddressMode::ClampToEdge, AddressMode::Wrap, AddressMode::ClampToEdge,
                                 AddressMode::Wrap, AddressMode::Mirror, AddressMode::Border,
                                 AddressMode::Clamp};
    Rng rng(2024);
    int kernelStates = 0, fallbackStates = 0;
    for (int stateI = 0; stateI < 1500; ++stateI) {
        TextureUnits tu;
        const auto& tex = textures[rng.below(7)];
        SamplerState s;
        for (auto& a : s.address) a = modes[rng.below(rng.below(3) ? 4 : 7)];
        s.magFilter = FilterMode(rng.below(2));
        s.minFilter = FilterMode(rng.below(2));
        s.mipFilter = MipMode(rng.below(3));
        s.lodBias = rng.below(3) ? 0.0f : rng.uniform(-3, 3);
        if (rng.below(4) == 0) s.minLod = rng.uniform(-1, 2);
        if (rng.below(4) == 0) s.maxLod = rng.uniform(0, 4);
        if (rng.below(4) == 0) s.baseLevel = int(rng.below(3));
        if (rng.below(4) == 0) s.maxLevel = int(rng.below(5));
        s.borderColor = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())};
        const bool withTable = rng.below(10) == 0;
        TexGenState g;
        g.projected = rng.below(2) == 0;
        tu.setTexGen(0, g);
        tu.setTexture(0, tex);
        tu.setSampler(0, s);
        if (withTable) tu.setColorTable(0, table);
        // SELECTARG1 texture: the sample itself reaches the output.
        tu.setStage(0, op(TextureOp::SelectArg1, arg::Texture, arg::Current, TextureOp::SelectArg1));
        const bool cube = tex->desc().target == TextureTarget::CubeMap;
        auto fits = [&](int d, int n) {
            return s.address[size_t(d)] == AddressMode::ClampToEdge ||
                   (s.address[size_t(d)] == AddressMode::Wrap && (n & (n - 1)) == 0);
        };
        const bool kernel = !withTable && (cube || (fits(0, tex->desc().width) &&
                                                    (tex->dims() == 1 || fits(1, tex->desc().height))));
        (kernel ? kernelStates : fallbackStates) += 1;
        uint64_t refFetches = 0, fastFetches = 0;
        for (int k = 0; k < 60; ++k) {
            FragmentQuad q;
            // Footprints from deep magnification to far minification (and a few zero).
            const float scale = rng.below(8) == 0 ? 0.0f : std::exp2(rng.uniform(-9, 3));
            glm::vec4 base(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(0.3f, 2));
            glm::vec4 dx(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.1f, 0.1f));
            glm::vec4 dy(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-0.1f, 0.1f));
            for (int p = 0; p < 4; ++p)
                q.texCoord[0][size_t(p)] = base + scale * (float(p & 1) * dx + float(p >> 1) * dy);
            std::array<Rgba8, 4> ref, fast;
            tu.resetCounters();
            tu.shadeQuad(q, ref, Path::Reference);
            refFetches += tu.counters().texelFetches;
            tu.resetCounters();
            tu.shadeQuad(q, fast, Path::Fast);
            fastFetches += tu.counters().texelFetches;
            ASSERT_EQ(ref, fast) << "state " << stateI << " quad " << k << " (seed 2024)";
        }
        ASSERT_EQ(refFetches, fastFetches) << "state " << stateI;
    }
    EXPECT_GT(kernelStates, 800);
    EXPECT_GT(fallbackStates, 150);
}

// Stages that read the same coordinate set through textures of the same shape with the
// same sampler share one footprint on the fast path (the PEM viewer's two cube maps under
// BLENDFACTORALPHA); near misses (another sampler, another shape, another set) must not.
void sharedFootprintsAgainstReference() {
    const Profile& g8 = profile(ProfileId::GeForce8800);
    auto mem = std::make_shared<TextureMemory>(g8);
    auto texels = [](uint32_t seed) {
        return [seed](int l, int f, int x, int y, int, int) {
            const uint32_t h = testing::hash32(seed + uint32_t(((l * 7 + f) * 131 + x) * 977 + y));
            return Rgba8{uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
        };
    };
    const TextureDesc shapes[] = {{TextureTarget::CubeMap, TexelFormat::RGBA8, 16, 16, 1, 1, 5},
                                  {TextureTarget::Texture2D, TexelFormat::RGBA8, 32, 16, 1, 1, 6},
                                  {TextureTarget::Texture1D, TexelFormat::RGBA8, 64, 1, 1, 1, 7},
                                  {TextureTarget::CubeMap, TexelFormat::RGBA8, 8, 8, 1, 1, 4}};
    std::vector<std::array<std::shared_ptr<Texture>, 2>> twins;
    for (uint32_t i = 0; i < 4; ++i)
        twins.push_back({makeRgba8(*mem, shapes[i], texels(i * 2)), makeRgba8(*mem, shapes[i], texels(i * 2 + 1))});
    Rng rng(31);
    for (int stateI = 0; stateI < 600; ++stateI) {
        TextureUnits tu;
        const uint32_t shape = rng.below(3);
        SamplerState s;
        for (auto& a : s.address) a = rng.below(2) ? AddressMode::ClampToEdge : AddressMode::Wrap;
        s.magFilter = FilterMode(rng.below(2));
        s.minFilter = FilterMode(rng.below(2));
        s.mipFilter = MipMode(rng.below(3));
        s.lodBias = rng.below(2) ? 0.0f : rng.uniform(-2, 2);
        const int n = 2 + int(rng.below(2));
        for (int i = 0; i < n; ++i) {
            SamplerState si = s;
            if (rng.below(6) == 0) si.lodBias += 0.5f;  // a near miss: no sharing
            const bool otherShape = rng.below(6) == 0;
            tu.setTexture(i, otherShape ? twins[3][0] : twins[shape][rng.below(2)]);
            tu.setSampler(i, si);
            StageState st = randomStage(rng, 1);
            st.texCoordIndex = uint8_t(rng.below(5) == 0 ? 1 : 0);
            tu.setStage(i, st);
        }
        tu.setTextureFactor({uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())});
        uint64_t refFetches = 0, fastFetches = 0;
        for (int k = 0; k < 30; ++k) {
            FragmentQuad q;
            const float scale = std::exp2(rng.uniform(-8, 2));
            for (int set = 0; set < 2; ++set) {
                glm::vec4 base(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2), 1.0f);
                glm::vec4 dx(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), 0.0f);
                glm::vec4 dy(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), 0.0f);
                for (int p = 0; p < 4; ++p)
                    q.texCoord[size_t(set)][size_t(p)] = base + scale * (float(p & 1) * dx + float(p >> 1) * dy);
            }
            for (int p = 0; p < 4; ++p)
                q.diffuse[size_t(p)] = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()),
                                        uint8_t(rng.next())};
            std::array<Rgba8, 4> ref, fast;
            tu.resetCounters();
            tu.shadeQuad(q, ref, Path::Reference);
            refFetches += tu.counters().texelFetches;
            tu.resetCounters();
            tu.shadeQuad(q, fast, Path::Fast);
            fastFetches += tu.counters().texelFetches;
            ASSERT_EQ(ref, fast) << "state " << stateI << " quad " << k << " (seed 31)";
        }
        ASSERT_EQ(refFetches, fastFetches) << "state " << stateI;
    }
}

// Both instruction sets of the compiled samplers: AVX2 (when the CPU has it) and SSE2.
TEST(TextureUnits, CompiledSamplersMatchReferenceOnEveryKernelAndTheFallback) {
    for (bool avx2 : {true, false}) {
        SCOPED_TRACE(avx2 ? "AVX2 kernels allowed" : "SSE2 kernels");
        allowAvx2Kernels(avx2);
        compiledSamplersAgainstReference();
        allowAvx2Kernels(true);
        if (HasFatalFailure()) return;
    }
}
TEST(TextureUnits, SharedFootprintsMatchReference) {
    for (bool avx2 : {true, false}) {
        SCOPED_TRACE(avx2 ? "AVX2 kernels allowed" : "SSE2 kernels");
        allowAvx2Kernels(avx2);
        sharedFootprintsAgainstReference();
        allowAvx2Kernels(true);
        if (HasFatalFailure()) return;
    }
}

// The whole-cascade functions of the fast path (filter_quad.cpp, compileCascade): one
// MODULATE stage over a 2D texture (WRAP or CLAMP_TO_EDGE) or a cube map, and a cube stage
// followed by a 1D stage (the PEM pass), with random arguments, modifiers, scales,
// filters, mipmap modes and coordinate sets; plus near misses that must take the general
// loop (another op, a third stage). Bytes and fetch counts against the reference, under
// both instruction sets.
void cascadesAgainstReference(int& pairs) {  // pairs: how many shadeQuadPair calls compared
    const Profile& g8 = profile(ProfileId::GeForce8800);
    auto mem = std::make_shared<TextureMemory>(g8);
    auto texel = [](int l, int f, int x, int y, int, int) {
        const uint32_t h = testing::hash32(uint32_t(((l * 5 + f) * 113 + x) * 733 + y));
        return Rgba8{uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
    };
    const std::shared_ptr<Texture> first[] = {
        makeRgba8(*mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 32, 16, 1, 1, 6}, texel),
        makeRgba8(*mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 16, 16, 1, 1, 1}, texel),
        makeRgba8(*mem, {TextureTarget::CubeMap, TexelFormat::RGBA8, 16, 16, 1, 1, 5}, texel),
        makeRgba8(*mem, {TextureTarget::CubeMap, TexelFormat::RGBA8, 8, 8, 1, 1, 1}, texel)};
    const std::shared_ptr<Texture> fresnel =
        makeRgba8(*mem, {TextureTarget::Texture1D, TexelFormat::RGBA8, 64, 1, 1, 1, 7}, texel);
    Rng rng(4242);
    auto sampler = [&](bool edge) {
        SamplerState s;
        const AddressMode m = edge ? AddressMode::ClampToEdge : AddressMode::Wrap;
        s.address = {m, m, m, m};
        s.magFilter = FilterMode(rng.below(2));
        s.minFilter = FilterMode(rng.below(2));
        s.mipFilter = MipMode(rng.below(3));
        s.lodBias = rng.below(3) ? 0.0f : rng.uniform(-2, 2);
        return s;
    };
    // glModulate: every stage GL's MODULATE, (TEXTURE, CURRENT) without modifiers or
    // scale (the cascades' kTexCur form).
    bool glModulate = false;
    auto modulate = [&](int sets) {
        StageState st = randomStage(rng, sets);
        st.colorOp = st.alphaOp = TextureOp::Modulate;
        if (glModulate) {
            st.colorArg1 = st.alphaArg1 = arg::Texture;
            st.colorArg2 = st.alphaArg2 = arg::Current;
            st.colorScaleShift = st.alphaScaleShift = 0;
        }
        // A near miss (with glModulate on a lone cube stage, the hybrid layer pass's
        // alpha SELECTARG1(TEXTURE), which has its own cascade).
        if (rng.below(8) == 0) st.alphaOp = TextureOp::SelectArg1;
        return st;
    };
    for (int stateI = 0; stateI < 400; ++stateI) {
        TextureUnits tu;
        glModulate = rng.below(2) == 0;
        const uint32_t kind = rng.below(4);
        const bool cube = first[kind]->desc().target == TextureTarget::CubeMap;
        tu.setTexture(0, first[kind]);
        tu.setSampler(0, sampler(cube || rng.below(2) == 0));
        tu.setStage(0, modulate(2));
        const uint32_t stages = cube ? 1 + rng.below(2) + (rng.below(8) == 0 ? 1 : 0) : 1;
        for (uint32_t i = 1; i < stages; ++i) {
            tu.setTexture(int(i), fresnel);
            tu.setSampler(int(i), sampler(rng.below(8) != 0));
            tu.setStage(int(i), modulate(2));
        }
        tu.setTextureFactor({uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())});
        uint64_t refFetches = 0, fastFetches = 0;
        // shadeQuadPair (the AVX2 rasterizer's entry, when a cascade is compiled): each two
        // consecutive quads as one pair, a random one of them without coverage now and then.
        FragmentQuadPair pair;
        std::array<Rgba8, 4> pairRef[2];
        uint64_t pairRefFetches[2] = {0, 0};
        // The previous quad's planes: the second quad of a pair is half the time the quad
        // two pixels to the right on the same planes (as the rasterizer's pairs are).
        float scale = 0.0f;
        glm::vec4 base[2], dx[2], dy[2];
        for (int k = 0; k < 40; ++k) {
            FragmentQuad q;
            const bool neighbour = (k & 1) && rng.below(2) == 0;
            if (!neighbour) scale = rng.below(10) == 0 ? 0.0f : std::exp2(rng.uniform(-9, 2));
            for (int set = 0; set < 2; ++set) {
                if (neighbour) {
                    base[set] += 2.0f * scale * dx[set];
                } else {
                    base[set] = {rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3), 1.0f};
                    dx[set] = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), 0.0f};
                    dy[set] = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1), 0.0f};
                    if (rng.below(6) == 0) {
                        // A cube direction on a face diagonal at pixel 0 (every pixel when
                        // the scale is 0): the face-selection ties, X before Y before Z.
                        glm::vec4& b = base[set];
                        const float sign = rng.below(2) ? 1.0f : -1.0f;
                        switch (rng.below(4)) {
                            case 0: b.y = sign * b.x; break;
                            case 1: b.z = sign * b.x; break;
                            case 2: b.z = sign * b.y; break;
                            default: b.y = b.z = sign * b.x; break;
                        }
                    }
                }
                for (int p = 0; p < 4; ++p)
                    q.texCoord[size_t(set)][size_t(p)] =
                        base[set] + scale * (float(p & 1) * dx[set] + float(p >> 1) * dy[set]);
            }
            for (int p = 0; p < 4; ++p) {
                q.diffuse[size_t(p)] = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()),
                                        uint8_t(rng.next())};
                q.specular[size_t(p)] = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()),
                                         uint8_t(rng.next())};
            }
            std::array<Rgba8, 4> ref, fast;
            tu.resetCounters();
            tu.shadeQuad(q, ref, Path::Reference);
            refFetches += tu.counters().texelFetches;
            tu.resetCounters();
            tu.shadeQuad(q, fast, Path::Fast);
            fastFetches += tu.counters().texelFetches;
            ASSERT_EQ(ref, fast) << "state " << stateI << " quad " << k << " (seed 4242)";
            if (!tu.shadesPairs()) continue;
            const int h = k & 1;
            pairRef[h] = ref;
            pairRefFetches[h] = tu.counters().texelFetches;
            for (int set = 0; set < 2; ++set)
                for (int p = 0; p < 4; ++p)
                    for (int c = 0; c < 4; ++c)
                        pair.texCoord[set][c][4 * h + p] = q.texCoord[size_t(set)][size_t(p)][c];
            for (int p = 0; p < 4; ++p) {
                pair.diffuse[size_t(4 * h + p)] = q.diffuse[size_t(p)];
                pair.specular[size_t(4 * h + p)] = q.specular[size_t(p)];
            }
            if (h == 0) continue;
            const uint32_t empty = rng.below(6);  // 0 or 1: that quad has no coverage
            pair.coverage = {uint8_t(empty == 0 ? 0 : 1 + rng.below(15)),
                             uint8_t(empty == 1 ? 0 : 1 + rng.below(15))};
            std::array<Rgba8, 8> both;
            const uint64_t n = tu.shadeQuadPair(pair, both);
            uint64_t expected = 0;
            for (int g = 0; g < 2; ++g) {
                if (!pair.coverage[size_t(g)]) continue;
                expected += pairRefFetches[g];
                const std::array<Rgba8, 4> got{both[size_t(4 * g)], both[size_t(4 * g + 1)],
                                               both[size_t(4 * g + 2)], both[size_t(4 * g + 3)]};
                ASSERT_EQ(pairRef[g], got) << "state " << stateI << " pair quad " << k - 1 + g;
            }
            ASSERT_EQ(expected, n) << "state " << stateI << " pair at quad " << k - 1;
            ++pairs;
        }
        ASSERT_EQ(refFetches, fastFetches) << "state " << stateI;
    }
}
// GL MODULATE of a texture without alpha (OpenGL 1.2 table 3.18, base RGB or LUMINANCE:
// C = Cf·Ct, A = Af) takes the whole-quad cascades (compileCascade runs it as MODULATE of
// both, the texels' alpha being 255): lightfield's Gortler polygons. Against the reference
// and against the table itself (the alpha is the fragment's, byte for byte), for RGB8, L8
// and RGB565 textures, both address modes, with and without mipmaps, quad by quad and in
// pairs; the cascade must be compiled where the AVX2 kernels run.
TEST(TextureUnits, ModulateOfATextureWithoutAlphaTakesTheCascades) {
    const Profile& g8 = profile(ProfileId::GeForce8800);
    auto mem = std::make_shared<TextureMemory>(g8);
    const bool avx2 = __builtin_cpu_supports("avx2") && !std::getenv("RETROGLASS_NO_AVX2");
    Rng rng(777);
    int pairs = 0;
    for (TexelFormat f : {TexelFormat::RGB8, TexelFormat::L8, TexelFormat::RGB565}) {
        const int bpt = f == TexelFormat::RGB8 ? 3 : f == TexelFormat::L8 ? 1 : 2;
        for (int levels : {1, 5}) {
            auto t = mem->create({TextureTarget::Texture2D, f, 16, 16, 1, 1, levels});
            for (int l = 0; l < levels; ++l) {
                std::vector<uint8_t> bytes(size_t(16 >> l) * size_t(16 >> l) * size_t(bpt));
                for (uint8_t& b : bytes) b = uint8_t(rng.next());
                mem->upload(*t, l, 0, bytes);
            }
            for (bool edge : {true, false}) {
                SCOPED_TRACE(std::string(formatInfo(f).name) + ", " + std::to_string(levels) +
                             " levels, " + (edge ? "CLAMP_TO_EDGE" : "REPEAT"));
                TextureUnits tu;
                tu.setTexture(0, t);
                SamplerState s;
                const AddressMode m = edge ? AddressMode::ClampToEdge : AddressMode::Wrap;
                s.address = {m, m, m, m};
                s.magFilter = s.minFilter = FilterMode::Linear;
                s.mipFilter = levels > 1 ? MipMode::Linear : MipMode::None;
                tu.setSampler(0, s);
                tu.setStage(0, texEnvStage(TexEnvMode::Modulate,
                                           f == TexelFormat::L8 ? BaseFormat::Luminance : BaseFormat::Rgb));
                if (avx2) {
                    EXPECT_TRUE(tu.shadesPairs()) << "no cascade compiled";
                }
                FragmentQuadPair pair;
                std::array<Rgba8, 4> ref[2];
                for (int k = 0; k < 64; ++k) {
                    FragmentQuad q;
                    const glm::vec4 base{rng.uniform(-2, 2), rng.uniform(-2, 2), 0.0f, 1.0f};
                    const float scale = std::exp2(rng.uniform(-7, 1));
                    for (int p = 0; p < 4; ++p) {
                        q.texCoord[0][size_t(p)] = base + scale * glm::vec4(float(p & 1), float(p >> 1), 0, 0);
                        q.diffuse[size_t(p)] = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()),
                                                uint8_t(rng.next())};
                    }
                    std::array<Rgba8, 4> fast;
                    const int h = k & 1;
                    tu.shadeQuad(q, ref[h], Path::Reference);
                    tu.shadeQuad(q, fast, Path::Fast);
                    ASSERT_EQ(ref[h], fast) << "quad " << k;
                    for (int p = 0; p < 4; ++p) ASSERT_EQ(fast[size_t(p)].a, q.diffuse[size_t(p)].a) << "quad " << k;
                    if (!tu.shadesPairs()) continue;
                    for (int p = 0; p < 4; ++p) {
                        for (int c = 0; c < 4; ++c) pair.texCoord[0][c][4 * h + p] = q.texCoord[0][size_t(p)][c];
                        pair.diffuse[size_t(4 * h + p)] = q.diffuse[size_t(p)];
                    }
                    if (h == 0) continue;
                    pair.coverage = {0xF, 0xF};
                    std::array<Rgba8, 8> both;
                    tu.shadeQuadPair(pair, both);
                    for (int g = 0; g < 2; ++g)
                        for (int p = 0; p < 4; ++p) ASSERT_EQ(ref[g][size_t(p)], both[size_t(4 * g + p)]) << "pair " << k;
                    ++pairs;
                }
            }
        }
    }
    if (avx2) {
        EXPECT_GT(pairs, 300);
    }
}

// The hybrid layer passes (demos/hybrid/hybrid_renderer.cpp) take the whole-quad cascades
// (compileCascade: cascadeOne's kAlpha0 = SelectArg1 and kTail): stage 0 colour
// MODULATE(TEXTURE, DIFFUSE), alpha SELECTARG1(TEXTURE) over an RGBA8 cube map, alone or
// followed by a stage that samples nothing, colour MODULATE(CURRENT, TFACTOR), alpha
// SELECTARG1(CURRENT) (the "b" weighted passes). Against the reference, quad by quad and
// in pairs (neighbouring quads and unrelated ones, now and then one without coverage),
// with and without mipmaps (trilinear and bilinear), random TFACTOR and DIFFUSE; and
// every pixel against the stage formulas of docs/hardware.md with the reference's texel
// t: C = m(m(Ct, Cd), Cf) (m(Ct, Cd) alone without the weight), A = At. The cascade must
// be compiled where the AVX2 kernels run.
TEST(TextureUnits, HybridLayerStatesTakeTheCascades) {
    const Profile& g8 = profile(ProfileId::GeForce8800);
    auto mem = std::make_shared<TextureMemory>(g8);
    const bool avx2 =
        __builtin_cpu_supports("avx2") && !std::getenv("RETROGLASS_NO_AVX2");
    auto texel = [](int l, int f, int x, int y, int, int) {
        const uint32_t h =
            testing::hash32(uint32_t(((l * 7 + f) * 131 + x) * 521 + y) + 99u);
        return Rgba8{uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
    };
    // m(a, b) = mulDiv255 as docs/hardware.md defines it:
    // t = a·b + 128, (t + (t >> 8)) >> 8.
    auto m = [](uint32_t a, uint32_t b) {
        const uint32_t t = a * b + 128u;
        return uint8_t((t + (t >> 8)) >> 8);
    };
    Rng rng(2008);
    int pairs = 0;
    for (int levels : {1, 5}) {
        const auto cube = makeRgba8(
            *mem, {TextureTarget::CubeMap, TexelFormat::RGBA8, 16, 16, 1, 1, levels},
            texel);
        // HybridRenderer::layerSampler, without mipmaps where there are none.
        SamplerState s;
        s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge,
                     AddressMode::ClampToEdge, AddressMode::ClampToEdge};
        s.magFilter = s.minFilter = FilterMode::Linear;
        s.mipFilter = levels > 1 ? MipMode::Linear : MipMode::None;
        // The texel alone (SELECTARG1 of TEXTURE for both), through the reference.
        TextureUnits probe;
        probe.setTexture(0, cube);
        probe.setSampler(0, s);
        probe.setStage(0, op(TextureOp::SelectArg1));
        for (bool weighted : {false, true}) {
            for (int stateI = 0; stateI < 8; ++stateI) {
                SCOPED_TRACE(std::to_string(levels) + " levels, " +
                             (weighted ? "× TFACTOR" : "one stage") + ", state " +
                             std::to_string(stateI) + " (seed 2008)");
                TextureUnits tu;
                tu.setTexture(0, cube);
                tu.setSampler(0, s);
                // DIFFUSE as hybrid writes it; now and then CURRENT, the same at stage 0.
                tu.setStage(0, op(TextureOp::Modulate, arg::Texture,
                                  stateI % 4 == 3 ? arg::Current : arg::Diffuse));
                if (weighted) {
                    StageState s1 =
                        stateI & 1 ? op(TextureOp::Modulate, arg::Current, arg::TFactor)
                                   : op(TextureOp::Modulate, arg::TFactor, arg::Current);
                    s1.alphaArg1 = arg::Current;
                    tu.setStage(1, s1);
                    if (stateI & 2) {
                        // A texture left bound on the stage (as after hybrid's lerp
                        // passes), which its arguments do not read.
                        tu.setTexture(1, cube);
                        tu.setSampler(1, s);
                    }
                }
                const Rgba8 tf{uint8_t(rng.next()), uint8_t(rng.next()),
                               uint8_t(rng.next()), uint8_t(rng.next())};
                tu.setTextureFactor(tf);
                if (avx2) {
                    EXPECT_TRUE(tu.shadesPairs()) << "no cascade compiled";
                }
                FragmentQuadPair pair;
                std::array<Rgba8, 4> ref[2];
                uint64_t refFetches[2] = {0, 0};
                float scale = 0.0f;
                glm::vec4 base{}, dx{}, dy{};
                for (int k = 0; k < 48; ++k) {
                    // The second quad of a pair half the time two pixels to the right on
                    // the same plane (the rasterizer's pairs: one 8-lane footprint).
                    FragmentQuad q;
                    const int h = k & 1;
                    if (h && rng.below(2) == 0) {
                        base += 2.0f * scale * dx;
                    } else {
                        scale = std::exp2(rng.uniform(-9, 1));
                        base = {rng.uniform(-3, 3), rng.uniform(-3, 3),
                                rng.uniform(-3, 3), 1.0f};
                        dx = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1),
                              0.0f};
                        dy = {rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1),
                              0.0f};
                    }
                    for (int p = 0; p < 4; ++p) {
                        q.texCoord[0][size_t(p)] =
                            base + scale * (float(p & 1) * dx + float(p >> 1) * dy);
                        q.diffuse[size_t(p)] = {uint8_t(rng.next()), uint8_t(rng.next()),
                                                uint8_t(rng.next()), uint8_t(rng.next())};
                    }
                    std::array<Rgba8, 4> fast, t;
                    tu.resetCounters();
                    tu.shadeQuad(q, ref[h], Path::Reference);
                    refFetches[h] = tu.counters().texelFetches;
                    tu.resetCounters();
                    tu.shadeQuad(q, fast, Path::Fast);
                    ASSERT_EQ(ref[h], fast) << "quad " << k;
                    ASSERT_EQ(refFetches[h], tu.counters().texelFetches) << "quad " << k;
                    probe.shadeQuad(q, t, Path::Reference);
                    for (int p = 0; p < 4; ++p) {
                        const Rgba8 d = q.diffuse[size_t(p)], tp = t[size_t(p)];
                        Rgba8 want{m(tp.r, d.r), m(tp.g, d.g), m(tp.b, d.b), tp.a};
                        if (weighted)
                            want = {m(want.r, tf.r), m(want.g, tf.g), m(want.b, tf.b),
                                    tp.a};
                        ASSERT_EQ(want, fast[size_t(p)])
                            << "quad " << k << " pixel " << p;
                    }
                    if (!tu.shadesPairs()) continue;
                    for (int p = 0; p < 4; ++p) {
                        for (int c = 0; c < 4; ++c)
                            pair.texCoord[0][c][4 * h + p] = q.texCoord[0][size_t(p)][c];
                        pair.diffuse[size_t(4 * h + p)] = q.diffuse[size_t(p)];
                    }
                    if (h == 0) continue;
                    const uint32_t empty =
                        rng.below(8);  // 0 or 1: that quad has no coverage
                    pair.coverage = {uint8_t(empty == 0 ? 0 : 0xF),
                                     uint8_t(empty == 1 ? 0 : 0xF)};
                    std::array<Rgba8, 8> both;
                    const uint64_t n = tu.shadeQuadPair(pair, both);
                    uint64_t expected = 0;
                    for (int g = 0; g < 2; ++g) {
                        if (!pair.coverage[size_t(g)]) continue;
                        expected += refFetches[g];
                        for (int p = 0; p < 4; ++p)
                            ASSERT_EQ(ref[g][size_t(p)], both[size_t(4 * g + p)])
                                << "pair at quad " << k - 1 << ", quad " << g << " pixel "
                                << p;
                    }
                    ASSERT_EQ(expected, n) << "pair at quad " << k - 1;
                    ++pairs;
                }
            }
        }
    }
    if (avx2) {
        EXPECT_GT(pairs, 700);  // 2 × 2 × 8 states × 24 pairs = 768
    }
}

TEST(TextureUnits, CascadesMatchReference) {
    for (bool avx2 : {true, false}) {
        SCOPED_TRACE(avx2 ? "AVX2 kernels allowed" : "SSE2 kernels");
        allowAvx2Kernels(avx2);
        int pairs = 0;
        cascadesAgainstReference(pairs);
        // The pair cascades exist with the AVX2 kernels only.
        if (avx2 && __builtin_cpu_supports("avx2") && !std::getenv("RETROGLASS_NO_AVX2")) {
            EXPECT_GT(pairs, 1000);
        }
        if (!avx2) {
            EXPECT_EQ(pairs, 0);
        }
        allowAvx2Kernels(true);
        if (HasFatalFailure()) return;
    }
}

// The pair path's 4×3 texel block (filter_quad.cpp, bilinearBlockPair) at its edges: a
// magnified 2D texture under GL MODULATE (cascadePairBlock2D) and the same with mipmaps
// (the general pair path), pairs of neighbouring quads on planes whose texel steps per
// pixel run through ±1.1 in both axes and both signs — offsets from the block's origin of
// 0 to 3 columns and 0 to 2 rows, so blocks that just fit and ones that just do not, the
// top-left pixel the smallest or not — near wraps and clamped edges. Bytes and fetches of
// both quads against the reference.
TEST(TextureUnits, PairBlockPathMatchesReferenceAtItsEdges) {
    const Profile& g8 = profile(ProfileId::GeForce8800);
    auto mem = std::make_shared<TextureMemory>(g8);
    auto texel = [](int l, int f, int x, int y, int, int) {
        const uint32_t h = testing::hash32(uint32_t(((l * 5 + f) * 113 + x) * 733 + y));
        return Rgba8{uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
    };
    const std::shared_ptr<Texture> textures[] = {
        makeRgba8(*mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 16, 8, 1, 1, 1}, texel),
        makeRgba8(*mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 16, 16, 1, 1, 5}, texel)};
    Rng rng(99);
    int pairs = 0;
    for (int stateI = 0; stateI < 200; ++stateI) {
        TextureUnits tu;
        const bool mips = rng.below(2) == 1;
        tu.setTexture(0, textures[mips ? 1 : 0]);
        SamplerState smp;
        const AddressMode m = rng.below(2) ? AddressMode::ClampToEdge : AddressMode::Wrap;
        smp.address = {m, m, m, m};
        if (mips) smp.mipFilter = MipMode::Nearest;
        tu.setSampler(0, smp);
        StageState st;
        st.colorOp = st.alphaOp = TextureOp::Modulate;
        st.colorArg1 = st.alphaArg1 = arg::Texture;
        st.colorArg2 = st.alphaArg2 = arg::Current;
        tu.setStage(0, st);
        if (!tu.shadesPairs()) continue;  // without AVX2
        for (int k = 0; k < 30; ++k) {
            // Texel steps per pixel in [−1.1, 1.1] on both axes, mostly axis-aligned.
            const float w = 16.0f, h = float(tu.texture(0)->desc().height);
            const float dudx = rng.uniform(-1.1f, 1.1f), dvdy = rng.uniform(-1.1f, 1.1f);
            const float dudy = rng.below(2) ? 0.0f : rng.uniform(-0.3f, 0.3f);
            const float dvdx = rng.below(2) ? 0.0f : rng.uniform(-0.3f, 0.3f);
            const float u0 = rng.uniform(-20.0f, 20.0f), v0 = rng.uniform(-20.0f, 20.0f);
            FragmentQuadPair pair;
            std::array<Rgba8, 4> ref[2];
            uint64_t refFetches = 0;
            for (int hq = 0; hq < 2; ++hq) {
                FragmentQuad q;
                for (int p = 0; p < 4; ++p) {
                    const float x = float(2 * hq + (p & 1)), y = float(p >> 1);
                    q.texCoord[0][size_t(p)] = {(u0 + dudx * x + dudy * y) / w,
                                                (v0 + dvdx * x + dvdy * y) / h, 0.0f, 1.0f};
                    q.diffuse[size_t(p)] = {uint8_t(rng.next()), uint8_t(rng.next()),
                                            uint8_t(rng.next()), uint8_t(rng.next())};
                    for (int c = 0; c < 4; ++c)
                        pair.texCoord[0][c][4 * hq + p] = q.texCoord[0][size_t(p)][c];
                    pair.diffuse[size_t(4 * hq + p)] = q.diffuse[size_t(p)];
                }
                tu.resetCounters();
                tu.shadeQuad(q, ref[hq], Path::Reference);
                refFetches += tu.counters().texelFetches;
            }
            pair.coverage = {15, 15};
            std::array<Rgba8, 8> both;
            const uint64_t n = tu.shadeQuadPair(pair, both);
            for (int hq = 0; hq < 2; ++hq) {
                const std::array<Rgba8, 4> got{both[size_t(4 * hq)], both[size_t(4 * hq + 1)],
                                               both[size_t(4 * hq + 2)], both[size_t(4 * hq + 3)]};
                ASSERT_EQ(ref[hq], got) << "state " << stateI << " pair " << k << " quad " << hq;
            }
            ASSERT_EQ(refFetches, n) << "state " << stateI << " pair " << k;
            ++pairs;
        }
    }
    if (__builtin_cpu_supports("avx2") && !std::getenv("RETROGLASS_NO_AVX2")) {
        EXPECT_GT(pairs, 5000);
    }
}

TEST(TextureUnits, TapQueryReproducesTheSampleAndItsWeightsSumToOne) {
    // The PEM set-up: stage 0 cube map MODULATE diffuse, stage 1 MODULATE by a 1D
    // Fresnel texture, trilinear, unnormalized cube coordinates per vertex.
    Fixture fx;
    TextureUnits tu;
    SamplerState tri;
    tri.mipFilter = MipMode::Linear;
    tu.setTexture(0, fx.cube);
    tu.setSampler(0, tri);
    tu.setStage(0, op(TextureOp::Modulate, arg::Texture, arg::Diffuse, TextureOp::SelectArg1, 0));
    tu.setTexture(1, fx.fresnel);
    tu.setSampler(1, tri);
    tu.setStage(1, op(TextureOp::Modulate, arg::Texture, arg::Current, TextureOp::Modulate, 1));
    EXPECT_NO_THROW(tu.validate(profile(ProfileId::GeForce256)));
    EXPECT_EQ(tu.texCoordSetsUsed(), 3u);
    Rng rng(8);
    for (int k = 0; k < 2000; ++k) {
        FragmentQuad q;
        glm::vec3 d(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3));
        glm::vec3 dx(rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f), rng.uniform(-0.5f, 0.5f));
        for (int p = 0; p < 4; ++p) {
            q.texCoord[0][size_t(p)] = glm::vec4(d + float(p & 1) * dx + float(p >> 1) * 0.5f * glm::vec3(dx.z, dx.x, dx.y), 1);
            q.texCoord[1][size_t(p)] = glm::vec4(rng.uniform(0, 1), 0, 0, 1);
        }
        const auto texels = tu.sampleStage(0, q, Path::Reference);
        for (int p = 0; p < 4; ++p) {
            TapList taps = tu.queryTaps(0, q, p);
            ASSERT_GT(taps.count, 0);
            double sum = 0;
            for (int i = 0; i < taps.count; ++i) sum += taps.weightOf(i);
            ASSERT_DOUBLE_EQ(sum, 1.0);
            // Every tap lies on the face the pixel's own direction selects.
            ASSERT_EQ(taps.taps[0].face, uint8_t(selectCubeFace(glm::vec3(q.texCoord[0][size_t(p)])).face));
            ASSERT_EQ(resolveTaps(*fx.cube, tri, taps), texels[size_t(p)]);
        }
    }
    EXPECT_EQ(tu.queryTaps(5, FragmentQuad{}, 0).count, 0);  // no texture: no taps
}

TEST(TextureUnits, NonFiniteCoordinatesAreSafeAndPathsStillAgree) {
    Fixture fx;
    const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                         -std::numeric_limits<float>::infinity(), 1e30f, -1e30f, 0.0f, -0.0f};
    Rng rng(13);
    for (const auto& t : {fx.tex2d, fx.cube, fx.fresnel}) {
        TextureUnits tu;
        tu.setTexture(0, t);
        SamplerState s;
        s.mipFilter = MipMode::Linear;
        tu.setSampler(0, s);
        tu.setStage(0, op(TextureOp::Modulate));
        TexGenState g;
        g.projected = true;
        tu.setTexGen(0, g);
        for (int k = 0; k < 2000; ++k) {
            FragmentQuad q;
            for (auto& c : q.texCoord[0])
                for (int i = 0; i < 4; ++i) c[i] = rng.below(3) ? rng.uniform(-2, 2) : bad[rng.below(7)];
            std::array<Rgba8, 4> ref, fast;
            tu.shadeQuad(q, ref, Path::Reference);
            tu.shadeQuad(q, fast, Path::Fast);
            ASSERT_EQ(ref, fast) << k;
        }
    }
}

TEST(TextureUnits, SettersRefuseOutOfRangeState) {
    TextureUnits tu;
    StageState s;
    s.colorOp = TextureOp::Modulate;
    s.texCoordIndex = kMaxTexCoordSets;
    EXPECT_THROW(tu.setStage(0, s), InvalidState);
    s.texCoordIndex = 0;
    s.colorArg1 = 7;
    EXPECT_THROW(tu.setStage(0, s), InvalidState);
    s.colorArg1 = arg::Texture | 0x40;
    EXPECT_THROW(tu.setStage(0, s), InvalidState);
    s.colorArg1 = arg::Texture;
    s.colorScaleShift = 3;
    EXPECT_THROW(tu.setStage(0, s), InvalidState);
    EXPECT_THROW(tu.setPixelTexture({true, PixelTexGenMode::Rgba, uint8_t(kMaxStages)}), InvalidState);
    EXPECT_THROW(tu.setTexGen(kMaxTexCoordSets, TexGenState{}), InvalidState);
    Fixture fx;
    auto l8 = fx.mem->create({TextureTarget::Texture2D, TexelFormat::L8, 2, 2, 1, 1, 1});
    EXPECT_THROW(fx.mem->upload(*l8, 0, 0, std::vector<Rgba8>(4)), InvalidState);
}

TEST(TextureUnits, CountersCountFetchesAndUploads) {
    Fixture fx;
    TextureUnits tu;
    tu.setTextureMemory(fx.mem);
    EXPECT_GT(tu.counters().uploadBytes, 0u);
    tu.resetCounters();
    EXPECT_EQ(tu.counters().uploadBytes, 0u);
    tu.setTexture(0, fx.tex2d);
    tu.setStage(0, op(TextureOp::SelectArg1));
    FragmentQuad q;
    std::array<Rgba8, 4> out;
    tu.shadeQuad(q, out, Path::Reference);  // bilinear magnification: 4 taps per pixel
    EXPECT_EQ(tu.counters().texelFetches, 16u);
    tu.shadeQuad(q, out, Path::Fast);
    EXPECT_EQ(tu.counters().texelFetches, 32u);
}

}  // namespace
}  // namespace rg::tex
