// Textured quads on both paths: random textures (2D of power-of-two and other sizes, cube
// maps, 1D, with and without mipmaps), random samplers and one or two random stages —
// often the MODULATE cascades the fast path compiles into one function — under random
// fragment states, drawn by the reference path and by the fast path (1–3 threads), which
// must give the same bytes, depth and counters (texel fetches included).
//
// Why a second random test: PathsAgree.TenThousandRandomDraws... draws its stages without
// a texture, so it never reaches the compiled samplers and cascades that the fast path's
// textured quad kernel (rasterizer/fragment_quad_textured.h) feeds. Here triangles cover
// the target's edges and odd sizes (quads half outside the target take the scalar
// template, the others the kernel), tiny and full-screen triangles, flat and Gouraud
// colour, perspective and pre-transformed vertices with varying 1/w, and now and then a
// NaN, infinite, huge or zero texture coordinate.
//
// Reproduce a failure: the message names the seed and draw; rerun
//   bin/test_rasterizer --gtest_filter='PathsAgree.TexturedQuads*'
// with RETROGLASS_TEXTURED_SEED=<seed> to replay that session alone. The suite is
// PathsAgree so that PathsAgree.WithoutAvx2 repeats it with the SSE2 kernels.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>

#include "raster_test_util.h"
#include "texunit/texture_units.h"

namespace rg::testing {
namespace {

using namespace rg::raster;

int levelsOf(int n) {
    int l = 0;
    for (; n >= 1; n /= 2) ++l;
    return l;
}

// A texture with random texels and `levels` mipmap levels (each face).
std::shared_ptr<tex::Texture> randomTexture(Rng& r, tex::TextureMemory& mem, tex::TextureTarget target,
                                            int w, int h, int levels) {
    auto t = mem.create({target, tex::TexelFormat::RGBA8, w, h, 1, 1, levels});
    const int faces = target == tex::TextureTarget::CubeMap ? 6 : 1;
    for (int f = 0; f < faces; ++f)
        for (int l = 0, lw = w, lh = h; l < levels; ++l, lw = std::max(1, lw / 2), lh = std::max(1, lh / 2)) {
            std::vector<uint8_t> bytes(size_t(lw) * size_t(lh) * 4);
            for (uint8_t& b : bytes) b = r.byte();
            mem.upload(*t, l, f, bytes);
        }
    return t;
}

tex::SamplerState randomSampler(Rng& r) {
    tex::SamplerState s;
    // Mostly the address modes the compiled samplers specialise (CLAMP_TO_EDGE, WRAP).
    for (auto& a : s.address)
        a = r.p(0.7) ? (r.p(0.5) ? tex::AddressMode::Wrap : tex::AddressMode::ClampToEdge)
                     : tex::AddressMode(r.i(0, 4));
    s.magFilter = tex::FilterMode(r.i(0, 1));
    s.minFilter = r.p(0.6) ? s.magFilter : tex::FilterMode(r.i(0, 1));
    s.mipFilter = tex::MipMode(r.i(0, 2));
    if (r.p(0.3)) s.lodBias = r.f(-2.0f, 2.0f);
    if (r.p(0.1)) s.minLod = r.f(-1.0f, 2.0f);
    if (r.p(0.1)) s.maxLod = r.f(0.0f, 4.0f);
    if (r.p(0.1)) s.baseLevel = r.i(0, 2);
    s.borderColor = Rgba8{r.byte(), r.byte(), r.byte(), r.byte()};
    return s;
}

tex::StageState randomStage(Rng& r, int sets) {
    tex::StageState st;
    st.texCoordIndex = uint8_t(r.i(0, sets - 1));
    if (r.p(0.6)) {  // the compiled cascades' MODULATE, TEXTURE × CURRENT
        st.colorOp = st.alphaOp = tex::TextureOp::Modulate;
        st.colorArg1 = st.alphaArg1 = tex::arg::Texture;
        st.colorArg2 = st.alphaArg2 = tex::arg::Current;
        return st;
    }
    const tex::TextureOp ops[] = {tex::TextureOp::Modulate, tex::TextureOp::Add,
                                  tex::TextureOp::SelectArg1, tex::TextureOp::Subtract,
                                  tex::TextureOp::BlendTextureAlpha, tex::TextureOp::Modulate2x};
    auto anyArg = [&] {
        uint8_t a = uint8_t(r.i(0, 4));
        if (r.p(0.2)) a |= tex::arg::Complement;
        if (r.p(0.2)) a |= tex::arg::AlphaReplicate;
        return a;
    };
    st.colorOp = ops[r.i(0, 5)];
    st.alphaOp = r.p(0.8) ? ops[r.i(0, 5)] : tex::TextureOp::Disable;
    st.colorArg1 = r.p(0.6) ? tex::arg::Texture : anyArg();
    st.colorArg2 = anyArg();
    st.alphaArg1 = r.p(0.6) ? tex::arg::Texture : anyArg();
    st.alphaArg2 = anyArg();
    return st;
}

// No culling, unlike randomState: every quad reaches the texture units.
PipelineState randomQuadState(Rng& r) {
    PipelineState s;
    s.cull = CullMode::None;
    s.shade = r.p(0.8) ? ShadeMode::Gouraud : ShadeMode::Flat;
    s.depthTest = uint8_t(r.p(0.4));
    s.depthWrite = uint8_t(r.p(0.7));
    s.depthFunc = CompareFunc(r.i(0, 7));
    s.alphaTest = uint8_t(r.p(0.2));
    s.alphaFunc = CompareFunc(r.i(0, 7));
    s.alphaRef = r.byte();
    s.blend = uint8_t(r.p(0.5));
    const int mode = r.i(0, 2);  // the fast path's constant blend modes, then any
    s.srcBlend = mode == 0 ? BlendFactor::SrcAlpha : mode == 1 ? BlendFactor::One : BlendFactor(r.i(0, 12));
    s.dstBlend = mode == 0 ? BlendFactor::InvSrcAlpha : mode == 1 ? BlendFactor::One : BlendFactor(r.i(0, 10));
    s.blendOp = mode < 2 ? BlendOp::Add : BlendOp(r.i(0, 4));
    s.colorWriteMask = r.p(0.8) ? uint8_t(kWriteRGBA) : uint8_t(r.i(0, 15));
    s.scissorTest = uint8_t(r.p(0.2));
    s.specularEnable = uint8_t(r.p(0.3));
    s.perspectiveColor = uint8_t(r.p(0.5));
    return s;
}

std::string firstDifference(const Framebuffer& a, const Framebuffer& b) {
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            const size_t i = size_t(y) * size_t(a.width()) + size_t(x);
            const Rgba8 p = a.color()[i], q = b.color()[i];
            if (!(p == q) || (!a.depth().empty() && a.depth()[i] != b.depth()[i])) {
                std::ostringstream s;
                s << "pixel (" << x << ", " << y << "): reference " << int(p.r) << "," << int(p.g)
                  << "," << int(p.b) << "," << int(p.a) << " fast " << int(q.r) << "," << int(q.g)
                  << "," << int(q.b) << "," << int(q.a);
                return s.str();
            }
        }
    return "none (counters)";
}

bool sameCounters(const Counters& a, const Counters& b) {
    return a.trianglesDrawn == b.trianglesDrawn && a.fragmentsGenerated == b.fragmentsGenerated &&
           a.fragmentsWritten == b.fragmentsWritten && a.blendOps == b.blendOps &&
           a.texture.texelFetches == b.texture.texelFetches;
}

// One session: a pair of devices receiving the same random textured draws. Returns the
// fragments written (to check that the draws reached the framebuffer).
uint64_t runSession(uint64_t seed, int draws) {
    Rng r(seed);
    const int sizes[][2] = {{97, 71}, {64, 64}, {130, 33}, {17, 9}, {160, 120}};
    const auto& sz = sizes[r.i(0, 4)];
    const int w = sz[0], h = sz[1];
    // geforce8800 for textures of other sizes than powers of two.
    const bool npot = r.p(0.3);
    const Profile& prof = profile(npot ? ProfileId::GeForce8800 : ProfileId::GeForce256);
    const DepthFormat fmt = DepthFormat(r.i(0, 2));
    Device ref(prof, w, h, fmt, {Path::Reference, 1});
    Device fast(prof, w, h, fmt, {Path::Fast, r.i(1, 3)});
    tex::TextureMemory mem(prof);
    // The session's textures: 2D power of two (WRAP specialised), 2D of any size, a
    // cube map and a 1D texture, with full mipmap chains or one level.
    std::vector<std::shared_ptr<tex::Texture>> textures;
    for (int k = 0; k < 4; ++k) {
        const bool mips = r.p(0.6);
        switch (k) {
            case 0: {
                const int tw = 1 << r.i(0, 7), th = 1 << r.i(0, 7);
                textures.push_back(randomTexture(r, mem, tex::TextureTarget::Texture2D, tw, th,
                                                 mips ? levelsOf(std::max(tw, th)) : 1));
                break;
            }
            case 1: {
                const int tw = npot ? r.i(1, 40) : 1 << r.i(0, 5), th = npot ? r.i(1, 40) : 1 << r.i(0, 5);
                textures.push_back(randomTexture(r, mem, tex::TextureTarget::Texture2D, tw, th,
                                                 mips ? levelsOf(std::max(tw, th)) : 1));
                break;
            }
            case 2: {
                const int n = 1 << r.i(0, 5);
                textures.push_back(randomTexture(r, mem, tex::TextureTarget::CubeMap, n, n,
                                                 mips ? levelsOf(n) : 1));
                break;
            }
            default: {
                const int n = 1 << r.i(0, 7);
                textures.push_back(randomTexture(r, mem, tex::TextureTarget::Texture1D, n, 1,
                                                 mips ? levelsOf(n) : 1));
                break;
            }
        }
    }
    const Rgba8 background{r.byte(), r.byte(), r.byte(), r.byte()};
    for (Device* d : {&ref, &fast}) d->clear(true, background, true, 1.0f);
    uint64_t written = 0;
    for (int k = 0; k < draws; ++k) {
        const std::string where = "seed " + std::to_string(seed) + " draw " + std::to_string(k) +
                                  " (" + std::to_string(w) + "x" + std::to_string(h) + ")";
        const PipelineState s = randomQuadState(r);
        const Rect scissor{r.i(-5, w), r.i(-5, h), r.i(0, w), r.i(0, h)};
        const int stages = r.p(0.6) ? 1 : 2;
        tex::StageState st[2];
        tex::SamplerState smp[2];
        std::shared_ptr<tex::Texture> tx[2];
        for (int i = 0; i < stages; ++i) {
            st[i] = randomStage(r, 2);
            smp[i] = randomSampler(r);
            tx[i] = r.p(0.95) ? textures[size_t(r.i(0, 3))] : nullptr;
        }
        if (stages == 2 && r.p(0.4)) {  // the PEM pass: cube then 1D, both MODULATE
            st[0] = randomStage(r, 1);
            st[0].colorOp = st[0].alphaOp = tex::TextureOp::Modulate;
            st[0].colorArg1 = st[0].alphaArg1 = tex::arg::Texture;
            st[0].colorArg2 = st[0].alphaArg2 = tex::arg::Current;
            st[1] = st[0];
            st[1].texCoordIndex = 1;
            tx[0] = textures[2];
            tx[1] = textures[3];
            smp[1].address[0] = tex::AddressMode::ClampToEdge;
        }
        const Rgba8 factor{r.byte(), r.byte(), r.byte(), r.byte()};

        // Geometry: pre-transformed (window pixels, 1/w per vertex) or through a
        // perspective camera; triangles from full-screen to a few pixels, many crossing
        // the target's edges.
        const VertexSpace space = r.p(0.6) ? VertexSpace::Pretransformed : VertexSpace::Untransformed;
        const int n = 3 * r.i(1, 4);
        const float scale = r.p(0.3) ? 3.0f : r.p(0.5) ? 40.0f : float(std::max(w, h)) * 1.5f;
        const bool flatW = r.p(0.4);
        // A shared 1/w: 1 (the rasterizer skips the ·1/w) or another value (one 1/w per
        // triangle instead of one per pixel).
        const float flatRhw = r.p(0.5) ? 1.0f : r.f(0.2f, 3.0f);
        const float texScale = r.p(0.5) ? r.f(0.1f, 1.5f) : r.f(1.5f, 12.0f);
        std::vector<Vertex> verts;
        const float cx = r.f(-10.0f, float(w) + 10.0f), cy = r.f(-10.0f, float(h) + 10.0f);
        for (int i = 0; i < n; ++i) {
            Vertex v;
            if (space == VertexSpace::Pretransformed) {
                v.position = {cx + r.f(-scale, scale), cy + r.f(-scale, scale), r.f(0.0f, 1.0f),
                              flatW ? flatRhw : r.f(0.2f, 3.0f)};
            } else {
                v.position = {r.f(-2.0f, 2.0f), r.f(-2.0f, 2.0f), r.f(-1.5f, 1.5f), 1.0f};
            }
            v.diffuse = Rgba8{r.byte(), r.byte(), r.byte(), r.byte()};
            v.specular = Rgba8{r.byte(), r.byte(), r.byte(), r.byte()};
            v.tex[0] = {r.f(-texScale, texScale), r.f(-texScale, texScale), r.f(-2.0f, 2.0f),
                        r.p(0.8) ? 1.0f : r.f(0.5f, 2.0f)};
            v.tex[1] = {r.f(-0.5f, 1.5f), r.f(-texScale, texScale), r.f(-2.0f, 2.0f), 1.0f};
            if (r.p(0.05)) v.tex[r.i(0, 1)][r.i(0, 3)] = weird(r);  // NaN, ±inf, huge, 0
            verts.push_back(v);
        }
        const glm::mat4 proj = glm::perspectiveLH_ZO(r.f(0.6f, 1.6f), float(w) / float(h), 0.5f, 20.0f);
        const glm::mat4 view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 3.0f));
        for (Device* d : {&ref, &fast}) {
            d->setState(s);
            d->setViewport(Viewport{0, 0, w, h, 0.0f, 1.0f});
            d->setScissor(scissor);
            d->setTransforms(glm::mat4(1.0f), view, proj);
            tex::TextureUnits& tu = d->textureUnits();
            for (int i = 0; i < 2; ++i) {
                tu.setStage(i, i < stages ? st[i] : tex::StageState{});
                tu.setTexture(i, i < stages ? tx[i] : nullptr);
                tu.setSampler(i, i < stages ? smp[i] : tex::SamplerState{});
            }
            tu.setTextureFactor(factor);
            d->beginFrame();
            d->draw(Primitive::TriangleList, space, verts);
        }
        const Framebuffer &a = ref.framebuffer(), &b = fast.framebuffer();
        const bool same = std::memcmp(a.color().data(), b.color().data(), a.color().size_bytes()) == 0 &&
                          std::equal(a.depth().begin(), a.depth().end(), b.depth().begin());
        if (!same || !sameCounters(ref.counters(), fast.counters())) {
            ADD_FAILURE() << "paths differ after " << where << ": " << firstDifference(a, b)
                          << "\nreference:\n" << ref.counters().toString() << "fast:\n"
                          << fast.counters().toString();
            return written;
        }
        written += ref.counters().fragmentsWritten;
    }
    return written;
}

TEST(PathsAgree, TexturedQuadsOnRandomStagesAndSamplers) {
    if (const char* one = std::getenv("RETROGLASS_TEXTURED_SEED")) {
        runSession(std::strtoull(one, nullptr, 10), 60);
        return;
    }
    uint64_t written = 0;
    for (uint64_t seed = 1; seed <= 50 && !HasFailure(); ++seed) written += runSession(seed, 60);
    EXPECT_GT(written, 500000u);  // the draws reached the framebuffer
}

}  // namespace
}  // namespace rg::testing
