// Golden trace builders: deterministic frames, each exercising one stage of the pipeline
// through the public Device API (docs/testing.md, "Golden traces"). Sizes are kept small
// (framebuffers of at most 32×32, textures of at most 16×16) so the files stay a few KB;
// the programmable frames are the benchmarks' and demos' own (programBuilders() below),
// at their own size (the binary-search trace is 1 MiB, its depth texture).
#include "golden_cases.h"

#include <cstring>
#include <functional>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "bench_programs.h"
#include "binary_search_retroglass.h"
#include "core/error.h"
#include "core/profile.h"
#include "rasterizer/device.h"
#include "rasterizer/trace.h"
#include "texunit/texture_units.h"
#ifndef RETROGLASS_GOLDEN_NO_DEMOS
#include "impostor_programs.h"
#include "impostor_renderer.h"
#include "tir_programs.h"
#include "tir_renderer.h"
#endif

namespace rg::golden {

namespace {

using namespace rg::raster;
using namespace rg::tex;

// ---- helpers ---------------------------------------------------------------------------
uint32_t mix(uint32_t x) {
    x ^= x >> 16; x *= 0x7feb352dU; x ^= x >> 15; x *= 0x846ca68bU; x ^= x >> 16;
    return x;
}

PipelineState plain() {
    PipelineState s;
    s.cull = CullMode::None;
    s.depthTest = 0;
    s.depthWrite = 0;
    return s;
}

Vertex pv(float x, float y, Rgba8 c, glm::vec4 t0 = {0, 0, 0, 1}, float z = 0.5f) {
    Vertex v;
    v.position = {x, y, z, 1.0f};
    v.diffuse = c;
    v.tex[0] = t0;
    return v;
}

// A pre-transformed rectangle with per-corner colours and texture coordinates (s, t)
// from (s0, t0) to (s1, t1).
void rect(Device& d, float x0, float y0, float x1, float y1, std::array<Rgba8, 4> c,
          glm::vec2 st0 = {0, 0}, glm::vec2 st1 = {1, 1}, float z0 = 0.5f, float z1 = 0.5f) {
    std::vector<Vertex> v = {pv(x0, y0, c[0], {st0.x, st0.y, 0, 1}, z0),
                             pv(x1, y0, c[1], {st1.x, st0.y, 0, 1}, z0),
                             pv(x1, y1, c[2], {st1.x, st1.y, 0, 1}, z1),
                             pv(x0, y1, c[3], {st0.x, st1.y, 0, 1}, z1)};
    d.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, v);
}

Rgba8 pattern(uint32_t seed, int x, int y, int z = 0, int w = 0) {
    uint32_t h = mix(seed * 7919u + uint32_t(x) * 31u + uint32_t(y) * 1031u + uint32_t(z) * 7u +
                     uint32_t(w) * 131u);
    return {uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
}

// RGBA8 texture with pseudo-random texels (seed, level, face).
std::shared_ptr<Texture> rgbaTexture(TextureMemory& mem, TextureDesc d, uint32_t seed) {
    d.format = TexelFormat::RGBA8;
    auto t = mem.create(d);
    for (int l = 0; l < t->levels(); ++l)
        for (int f = 0; f < t->faces(); ++f) {
            const auto& s = t->levelSize(l);
            std::vector<Rgba8> texels;
            for (int w = 0; w < s[3]; ++w)
                for (int z = 0; z < s[2]; ++z)
                    for (int y = 0; y < s[1]; ++y)
                        for (int x = 0; x < s[0]; ++x)
                            texels.push_back(pattern(seed + uint32_t(l) * 101u + uint32_t(f) * 13u, x, y, z, w));
            mem.upload(*t, l, f, texels);
        }
    return t;
}

// Any texel format from pseudo-random packed bytes.
std::shared_ptr<Texture> packedTexture(TextureMemory& mem, TextureDesc d, uint32_t seed) {
    auto t = mem.create(d);
    const int bpt = formatInfo(d.format).bytesPerTexel;
    for (int l = 0; l < t->levels(); ++l)
        for (int f = 0; f < t->faces(); ++f) {
            const auto& s = t->levelSize(l);
            const size_t count = size_t(s[0]) * size_t(s[1]) * size_t(s[2]) * size_t(s[3]);
            std::vector<uint8_t> bytes(count * size_t(bpt));
            for (size_t i = 0; i < bytes.size(); ++i)
                bytes[i] = uint8_t(mix(seed + uint32_t(i) * 977u + uint32_t(l) * 31u + uint32_t(f)));
            mem.upload(*t, l, f, std::span<const uint8_t>(bytes));
        }
    return t;
}

StageState stage(TextureOp colorOp, uint8_t c1, uint8_t c2, TextureOp alphaOp, uint8_t a1, uint8_t a2) {
    StageState s;
    s.colorOp = colorOp; s.colorArg1 = c1; s.colorArg2 = c2;
    s.alphaOp = alphaOp; s.alphaArg1 = a1; s.alphaArg2 = a2;
    return s;
}

SamplerState sampler(FilterMode f, AddressMode a = AddressMode::Wrap, MipMode mip = MipMode::None) {
    SamplerState s;
    s.magFilter = s.minFilter = f;
    s.mipFilter = mip;
    s.address = {a, a, a, a};
    return s;
}

// Matrices from literal cosines, sines and tangents: calling libm here would make the
// trace bytes depend on the build (GCC folds constant tan/cos with MPFR in Release and
// calls libm in Debug, an ulp apart), and tests/compilers.sh checks the generator too.
// glm::perspective's and glm::rotate's formulas with tan(fovy/2), cos and sin given.
glm::mat4 perspectiveTan(float tanHalfFovy, float aspect, float n, float f) {
    glm::mat4 m(0.0f);
    m[0][0] = 1.0f / (aspect * tanHalfFovy);
    m[1][1] = 1.0f / tanHalfFovy;
    m[2][2] = -(f + n) / (f - n);
    m[2][3] = -1.0f;
    m[3][2] = -(2.0f * f * n) / (f - n);
    return m;
}
glm::mat4 rotateCosSin(float c, float s, glm::vec3 axis) {
    const glm::vec3 a = glm::normalize(axis);
    const glm::vec3 t = (1.0f - c) * a;
    glm::mat4 m(1.0f);
    m[0][0] = c + t[0] * a[0];
    m[0][1] = t[0] * a[1] + s * a[2];
    m[0][2] = t[0] * a[2] - s * a[1];
    m[1][0] = t[1] * a[0] - s * a[2];
    m[1][1] = c + t[1] * a[1];
    m[1][2] = t[1] * a[2] + s * a[0];
    m[2][0] = t[2] * a[0] + s * a[1];
    m[2][1] = t[2] * a[1] - s * a[0];
    m[2][2] = c + t[2] * a[2];
    return m;
}
constexpr float kTan30 = 0.57735026918962576f, kTan25 = 0.46630765815499859f,
                kTan20 = 0.36397023426620236f;
constexpr float kCos04 = 0.92106099400288508f, kSin04 = 0.38941834230865049f;
constexpr float kCos05 = 0.87758256189037276f, kSin05 = 0.47942553860420301f;
constexpr float kCos07 = 0.76484218728448842f, kSin07 = 0.64421768723769105f;
// cos and sin of k·π/8, k = 0..16: the fan's and the sphere's angles.
constexpr float kCosPi8[17] = {1.0f, 0.92387953251128674f, 0.70710678118654757f, 0.38268343236508984f, 6.123233995736766e-17f, -0.38268343236508973f, -0.70710678118654746f, -0.92387953251128674f, -1.0f, -0.92387953251128685f, -0.70710678118654768f, -0.38268343236509034f, -1.8369701987210297e-16f, 0.38268343236509f, 0.70710678118654735f, 0.92387953251128652f, 1.0f};
constexpr float kSinPi8[17] = {0.0f, 0.38268343236508978f, 0.70710678118654746f, 0.92387953251128674f, 1.0f, 0.92387953251128674f, 0.70710678118654757f, 0.38268343236508989f, 1.2246467991473532e-16f, -0.38268343236508967f, -0.70710678118654746f, -0.92387953251128652f, -1.0f, -0.92387953251128663f, -0.70710678118654768f, -0.38268343236509039f, -2.4492935982947064e-16f};

const std::array<Rgba8, 4> kCorners = {Rgba8{255, 0, 0, 255}, Rgba8{0, 255, 0, 160},
                                       Rgba8{0, 0, 255, 64}, Rgba8{255, 255, 255, 0}};

// A background both blending and the depth test read: a colour and alpha gradient.
void background(Device& d, int w, int h) {
    rect(d, 0, 0, float(w), float(h),
         {Rgba8{10, 200, 90, 0}, Rgba8{250, 20, 120, 90}, Rgba8{40, 60, 230, 255},
          Rgba8{180, 180, 20, 170}});
}

struct Builder {
    GoldenCase info;
    ProfileId profile;
    int width, height;
    DepthFormat depth;
    std::function<void(Device&, TextureMemory&)> build;
};

// ---- the cases -------------------------------------------------------------------------
std::vector<Builder> builders() {
    std::vector<Builder> b;

    b.push_back({{"raster-fill-rule", "top-left rule and subpixel snapping: fans, strips, indexed lists with shared edges, additive so double hits or gaps show"},
                 ProfileId::GeForce256, 32, 32, DepthFormat::None, [](Device& d, TextureMemory&) {
        PipelineState s = plain();
        s.blend = 1; s.srcBlend = BlendFactor::One; s.dstBlend = BlendFactor::One;
        d.setState(s);
        d.clear(true, {0, 0, 0, 0}, false, 1.0f);
        // A fan of 16 triangles around a subpixel centre: every edge is shared once.
        std::vector<Vertex> fan{pv(15.37f, 14.81f, {60, 60, 60, 255})};
        for (int i = 0; i <= 16; ++i) {
            fan.push_back(pv(15.37f + 13.3f * kCosPi8[i], 14.81f + 12.7f * kSinPi8[i],
                             {uint8_t(40 + 10 * (i % 5)), uint8_t(30 * (i % 3)), 50, 255}));
        }
        d.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, fan);
        // A strip on exact pixel centres and edges (the tie cases of the rule).
        std::vector<Vertex> strip;
        for (int i = 0; i < 8; ++i)
            strip.push_back(pv(float(i * 4), i % 2 ? 28.0f : 24.5f, {0, 70, uint8_t(20 * i), 255}));
        d.draw(Primitive::TriangleStrip, VertexSpace::Pretransformed, strip);
        // Indexed list: a 3×3 grid of quads with irrational-looking corners.
        std::vector<Vertex> grid;
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x)
                grid.push_back(pv(1.1f + x * 2.6f + 0.13f * y, 1.3f + y * 2.45f, {50, 0, 60, 255}));
        std::vector<uint32_t> idx;
        for (uint32_t y = 0; y < 3; ++y)
            for (uint32_t x = 0; x < 3; ++x) {
                uint32_t i = y * 4 + x;
                idx.insert(idx.end(), {i, i + 1, i + 5, i, i + 5, i + 4});
            }
        d.draw(Primitive::TriangleList, VertexSpace::Pretransformed, grid, idx);
        // Degenerate and sliver triangles.
        std::vector<Vertex> sliver{pv(2, 30, {255, 0, 0, 255}), pv(30, 30.2f, {255, 0, 0, 255}),
                                   pv(2, 30.4f, {255, 0, 0, 255}), pv(5, 5, {9, 9, 9, 9}),
                                   pv(5, 5, {9, 9, 9, 9}), pv(9, 9, {9, 9, 9, 9})};
        d.draw(Primitive::TriangleList, VertexSpace::Pretransformed, sliver);
    }});

    for (bool affine : {false, true})
    b.push_back({{affine ? "raster-affine-colour" : "raster-transform-clip-cull",
                  affine ? "the same clipped, culled geometry with colours interpolated without perspective correction (perspectiveColor off)"
                         : "world/view/projection, near and far clipping, guard band, CW/CCW culling, flat and Gouraud shading, perspective-correct colour"},
                 ProfileId::GeForce256, 32, 32, DepthFormat::D24, [affine](Device& d, TextureMemory&) {
        d.clear(true, {20, 20, 20, 255}, true, 1.0f);
        glm::mat4 proj = perspectiveTan(kTan30, 1.0f, 0.5f, 20.0f);
        glm::mat4 view = glm::lookAt(glm::vec3(0.3f, 0.4f, 2.0f), glm::vec3(0, 0, 0), glm::vec3(0, 1, 0));
        d.setTransforms(rotateCosSin(kCos04, kSin04, glm::vec3(0, 1, 0)), view, proj);
        int k = 0;
        for (CullMode cull : {CullMode::None, CullMode::CW, CullMode::CCW})
            for (ShadeMode shade : {ShadeMode::Gouraud, ShadeMode::Flat}) {
                PipelineState s;
                s.cull = cull;
                s.shade = shade;
                s.perspectiveColor = affine ? 0 : 1;
                d.setState(s);
                float o = float(k) * 0.35f - 0.9f;
                auto v = [&](float x, float y, float z, Rgba8 c) {
                    Vertex r;
                    r.position = {x + o, y, z, 1};
                    r.diffuse = c;
                    return r;
                };
                // One triangle each way round, and one crossing the near plane.
                std::vector<Vertex> tri{v(-0.3f, -0.8f, 0, {255, 0, 0, 255}), v(0.3f, -0.8f, 0, {0, 255, 0, 255}),
                                        v(0, 0, 0.2f, {0, 0, 255, 255}),
                                        v(-0.3f, 0.1f, 0, {255, 255, 0, 255}), v(0, 0.8f, 0.1f, {0, 255, 255, 255}),
                                        v(0.3f, 0.1f, 0, {255, 0, 255, 255}),
                                        v(-0.2f, -0.2f, 2.5f, {200, 100, 0, 255}), v(0.2f, -0.1f, -1.0f, {0, 100, 200, 255}),
                                        v(0.0f, 0.4f, 1.9f, {100, 200, 100, 255})};
                d.draw(Primitive::TriangleList, VertexSpace::Untransformed, tri);
                ++k;
            }
        // Far clipping: a triangle reaching past the far plane.
        PipelineState last{CullMode::None};
        last.perspectiveColor = affine ? 0 : 1;
        d.setState(last);
        std::vector<Vertex> far(3);
        far[0].position = {-3, -1, -30, 1}; far[1].position = {3, -1, -30, 1}; far[2].position = {0, -1, 1, 1};
        far[0].diffuse = {255, 128, 0, 255}; far[1].diffuse = {0, 128, 255, 255}; far[2].diffuse = {128, 255, 128, 255};
        d.draw(Primitive::TriangleList, VertexSpace::Untransformed, far);
    }});

    for (DepthFormat df : {DepthFormat::D16, DepthFormat::D24}) {
        std::string name = df == DepthFormat::D16 ? "depth-compare-d16" : "depth-compare-d24";
        b.push_back({{name, "the eight depth compare functions, depth writes on and off, depth clear, viewport depth range"},
                     ProfileId::GeForce256, 32, 32, df, [](Device& d, TextureMemory&) {
            d.clear(true, {0, 0, 0, 255}, true, 0.5f);
            PipelineState s = plain();
            s.depthTest = 1;
            s.depthWrite = 1;
            s.depthFunc = CompareFunc::Always;
            d.setState(s);
            // A depth ramp along x: the reference surface.
            rect(d, 0, 16, 32, 32, {Rgba8{50, 50, 50, 255}, Rgba8{50, 50, 50, 255}, Rgba8{90, 90, 90, 255}, Rgba8{90, 90, 90, 255}},
                 {0, 0}, {1, 1}, 0.3f, 0.7f);
            for (int f = 0; f < 8; ++f) {
                s.depthFunc = CompareFunc(f);
                s.depthWrite = uint8_t(f % 2);
                d.setState(s);
                Rgba8 c{uint8_t(30 * f + 20), uint8_t(255 - 30 * f), uint8_t(f * 17), 255};
                // Ramps in y crossing the cleared 0.5 and the reference ramp; drawn twice so
                // the second draw sees the first one's depth writes.
                rect(d, float(4 * f), 0, float(4 * f + 4), 32, {c, c, c, c}, {0, 0}, {1, 1}, 0.2f, 0.8f);
                rect(d, float(4 * f) + 1, 0, float(4 * f + 3), 32, {Rgba8{255, 255, 255, 255}, c, c, c}, {0, 0}, {1, 1}, 0.6f, 0.4f);
            }
            d.setViewport({8, 8, 16, 16, 0.25f, 0.75f});
            s.depthFunc = CompareFunc::Less;
            d.setState(s);
            d.setTransforms(glm::mat4(1), glm::mat4(1), glm::mat4(1));
            std::vector<Vertex> tri(3);
            tri[0].position = {-1, -1, -1, 1}; tri[1].position = {1, -1, 1, 1}; tri[2].position = {0, 1, 0, 1};
            tri[0].diffuse = {255, 0, 0, 255}; tri[1].diffuse = {0, 255, 0, 255}; tri[2].diffuse = {0, 0, 255, 255};
            d.draw(Primitive::TriangleList, VertexSpace::Untransformed, tri);
        }});
    }

    b.push_back({{"alpha-test", "the eight alpha compare functions against three reference values, over an alpha gradient"},
                 ProfileId::GeForce256, 32, 24, DepthFormat::None, [](Device& d, TextureMemory&) {
        d.clear(true, {0, 0, 40, 255}, false, 1.0f);
        for (int ref = 0; ref < 3; ++ref)
            for (int f = 0; f < 8; ++f) {
                PipelineState s = plain();
                s.alphaTest = 1;
                s.alphaFunc = CompareFunc(f);
                s.alphaRef = uint8_t(ref == 0 ? 0 : ref == 1 ? 128 : 255);
                d.setState(s);
                rect(d, float(4 * f), float(8 * ref), float(4 * f + 4), float(8 * ref + 8),
                     {Rgba8{255, 0, 0, 0}, Rgba8{0, 255, 0, 0}, Rgba8{0, 0, 255, 255}, Rgba8{255, 255, 0, 255}});
            }
    }});

    b.push_back({{"blend-factors", "every source × destination blend factor pair (13 source × 11 destination: BOTH* are source-only) over a colour and alpha gradient"},
                 ProfileId::GeForce256, 22, 26, DepthFormat::None, [](Device& d, TextureMemory&) {
        d.setState(plain());
        background(d, 22, 26);
        for (int sf = 0; sf < 13; ++sf)
            for (int df = 0; df < 11; ++df) {
                PipelineState s = plain();
                s.blend = 1;
                s.srcBlend = BlendFactor(sf);
                s.dstBlend = BlendFactor(df);
                d.setState(s);
                rect(d, float(2 * df), float(2 * sf), float(2 * df + 2), float(2 * sf + 2),
                     {Rgba8{200, 30, 100, 40}, Rgba8{20, 220, 60, 130}, Rgba8{90, 90, 250, 255}, Rgba8{255, 128, 0, 200}});
            }
    }});

    b.push_back({{"blend-ops", "ADD, SUBTRACT, REVSUBTRACT, MIN, MAX with several factor pairs, colour write mask"},
                 ProfileId::GeForce256, 30, 24, DepthFormat::None, [](Device& d, TextureMemory&) {
        d.setState(plain());
        background(d, 30, 24);
        const std::pair<BlendFactor, BlendFactor> pairs[] = {
            {BlendFactor::One, BlendFactor::One}, {BlendFactor::SrcAlpha, BlendFactor::InvSrcAlpha},
            {BlendFactor::DestColor, BlendFactor::SrcColor}, {BlendFactor::SrcAlphaSat, BlendFactor::InvDestAlpha}};
        for (int op = 0; op < 5; ++op)
            for (int p = 0; p < 4; ++p) {
                PipelineState s = plain();
                s.blend = 1;
                s.blendOp = BlendOp(op);
                s.srcBlend = pairs[p].first;
                s.dstBlend = pairs[p].second;
                s.colorWriteMask = uint8_t(p == 3 ? (kWriteR | kWriteA) : kWriteRGBA);
                d.setState(s);
                rect(d, float(6 * op), float(6 * p), float(6 * op + 6), float(6 * p + 6), kCorners);
            }
    }});

    b.push_back({{"fragment-scissor-mask-specular", "scissor test (draws and clears), colour write masks, specular add, flat shading of the provoking vertex"},
                 ProfileId::GeForce256, 32, 32, DepthFormat::D16, [](Device& d, TextureMemory&) {
        d.clear(true, {30, 30, 30, 255}, true, 1.0f);
        PipelineState s = plain();
        s.scissorTest = 1;
        d.setState(s);
        d.setScissor({3, 5, 20, 17});
        d.clear(true, {90, 10, 10, 255}, false, 1.0f);
        rect(d, 0, 0, 32, 32, kCorners);
        s.scissorTest = 0;
        for (int m = 0; m < 16; ++m) {
            s.colorWriteMask = uint8_t(m);
            s.specularEnable = uint8_t(m & 1);
            s.shade = m & 2 ? ShadeMode::Flat : ShadeMode::Gouraud;
            d.setState(s);
            std::vector<Vertex> v = {pv(float(2 * m), 20, {255, 255, 255, 255}), pv(float(2 * m + 2), 20, {0, 0, 0, 0}),
                                     pv(float(2 * m + 2), 32, {128, 64, 32, 16}), pv(float(2 * m), 32, {16, 32, 64, 128})};
            for (size_t i = 0; i < v.size(); ++i) v[i].specular = {uint8_t(40 * i), 200, uint8_t(60 + 50 * i), 0};
            d.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, v);
        }
    }});

    // The stage ops in two groups: those ARB_texture_env_combine (+ dot3) can express, so
    // that `retroglass conform` compares them with Mesa, and the Direct3D-only ones.
    auto glExpressible = [](TextureOp o) {
        switch (o) {
            case TextureOp::AddSmooth: case TextureOp::BlendTextureAlphaPM: case TextureOp::PreModulate:
            case TextureOp::ModulateAlphaAddColor: case TextureOp::ModulateColorAddAlpha:
            case TextureOp::ModulateInvAlphaAddColor: case TextureOp::ModulateInvColorAddAlpha:
                return false;
            default: return true;
        }
    };
    for (int variant = 0; variant < 3; ++variant) {
        const bool alpha = variant == 1, d3dOnly = variant == 2;
        std::string name = d3dOnly ? "stage-ops-d3d-only" : alpha ? "stage-ops-alpha" : "stage-ops-color";
        std::string covers = d3dOnly ? "the Direct3D-only texture-stage operations (ADDSMOOTH, BLENDTEXTUREALPHAPM, "
                                       "PREMODULATE, MODULATE*ADD*) as colour and alpha operations, DOTPRODUCT3 as the alpha operation"
                                     : std::string("every texture-stage operation GL 1.3 combine can express as the ") +
                                           (alpha ? "alpha" : "colour") + " operation, arguments TEXTURE, DIFFUSE, TFACTOR";
        b.push_back({{name, covers},
                     ProfileId::GeForce3, 30, d3dOnly ? 25 : 20, DepthFormat::None, [alpha, d3dOnly, glExpressible](Device& d, TextureMemory& mem) {
            d.setState(plain());
            d.clear(true, {0, 0, 0, 0}, false, 1.0f);
            auto& tu = d.textureUnits();
            tu.setTexture(0, rgbaTexture(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 4, 4, 1, 1, 1}, 7));
            tu.setSampler(0, sampler(FilterMode::Nearest));
            tu.setTextureFactor({70, 140, 210, 100});
            // The D3D-only trace draws its colour-op cells in the first rows and its alpha-op
            // cells (with DOTPRODUCT3, whose alpha GL's DOT3_RGB does not define) below.
            for (int cell = 1; cell < 2 * int(TextureOp::Count); ++cell) {
                const int op = cell % int(TextureOp::Count);
                const bool alphaCell = d3dOnly ? cell >= int(TextureOp::Count) : alpha;
                if (op == 0 || (!d3dOnly && cell >= int(TextureOp::Count))) continue;
                TextureOp o = TextureOp(op);
                bool colorOnly = o == TextureOp::ModulateAlphaAddColor || o == TextureOp::ModulateColorAddAlpha ||
                                 o == TextureOp::ModulateInvAlphaAddColor || o == TextureOp::ModulateInvColorAddAlpha;
                if (alphaCell && colorOnly) continue;
                const bool glOk = glExpressible(o) && !(alphaCell && o == TextureOp::DotProduct3);
                if (glOk == d3dOnly) continue;
                StageState st = alphaCell ? stage(TextureOp::SelectArg1, arg::Texture, arg::Diffuse, o, arg::Texture, arg::Diffuse)
                                      : stage(o, arg::Texture, arg::Diffuse, TextureOp::SelectArg1, arg::Texture, arg::Diffuse);
                st.colorArg0 = st.alphaArg0 = arg::TFactor;
                tu.setStage(0, st);
                // Alpha results are made visible by writing them through the blend.
                PipelineState s = plain();
                if (alphaCell) { s.blend = 1; s.srcBlend = BlendFactor::SrcAlpha; s.dstBlend = BlendFactor::Zero; }
                d.setState(s);
                const int slot = d3dOnly ? (alphaCell ? 12 : 0) + (op % 12) : op - 1;
                int cx = slot % 6, cy = slot / 6;
                rect(d, float(5 * cx), float(5 * cy), float(5 * cx + 5), float(5 * cy + 5), kCorners, {0.03f, 0.07f}, {1.01f, 0.97f});  // no texel-edge ties: GL rounds those its own way
            }
        }});
    }

    b.push_back({{"stage-args-cascade", "argument modifiers (COMPLEMENT, ALPHAREPLICATE), CURRENT and SPECULAR arguments, RGB/ALPHA scale, a four-stage cascade with stages past the first disabled one ignored"},
                 ProfileId::GeForce3, 32, 16, DepthFormat::None, [](Device& d, TextureMemory& mem) {
        d.setState(plain());
        d.clear(true, {0, 0, 0, 0}, false, 1.0f);
        auto& tu = d.textureUnits();
        for (int i = 0; i < 4; ++i) {
            tu.setTexture(i, rgbaTexture(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 4, 4, 1, 1, 1}, 20 + uint32_t(i)));
            tu.setSampler(i, sampler(i % 2 ? FilterMode::Linear : FilterMode::Nearest));
        }
        tu.setTextureFactor({200, 100, 50, 25});
        const uint8_t mods[] = {0, arg::Complement, arg::AlphaReplicate, arg::Complement | arg::AlphaReplicate};
        for (int k = 0; k < 8; ++k) {
            StageState s0 = stage(TextureOp::Modulate, uint8_t(arg::Texture | mods[k % 4]), arg::Diffuse,
                                  TextureOp::Add, arg::Texture, uint8_t(arg::Diffuse | (k & 1 ? arg::Complement : 0)));
            s0.colorScaleShift = uint8_t(k % 3);
            s0.alphaScaleShift = uint8_t((k + 1) % 3);
            StageState s1 = stage(TextureOp::AddSigned, arg::Current, uint8_t(arg::Specular | mods[(k + 1) % 4]),
                                  TextureOp::Modulate, arg::Current, arg::Texture);
            StageState s2 = stage(k < 4 ? TextureOp::Lerp : TextureOp::Disable, arg::Texture, arg::Current,
                                  TextureOp::SelectArg2, arg::Texture, arg::Current);
            s2.colorArg0 = uint8_t(arg::TFactor | mods[k % 4]);
            StageState s3 = stage(TextureOp::Subtract, arg::Current, uint8_t(arg::Texture | arg::Complement),
                                  TextureOp::SelectArg1, arg::Current, arg::Texture);
            tu.setStage(0, s0); tu.setStage(1, s1); tu.setStage(2, s2); tu.setStage(3, s3);
            std::vector<Vertex> v = {pv(float(4 * k), 0, {255, 0, 0, 255}, {0, 0, 0, 1}),
                                     pv(float(4 * k + 4), 0, {0, 255, 0, 128}, {1, 0, 0, 1}),
                                     pv(float(4 * k + 4), 16, {0, 0, 255, 64}, {1, 1, 0, 1}),
                                     pv(float(4 * k), 16, {255, 255, 255, 0}, {0, 1, 0, 1})};
            for (size_t i = 0; i < 4; ++i) {
                v[i].specular = {uint8_t(60 * i), uint8_t(255 - 60 * i), 128, 0};
                v[i].tex[1] = {v[i].tex[0].y, v[i].tex[0].x, 0, 1};
            }
            d.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, v);
        }
    }});

    b.push_back({{"texture-address-filter", "WRAP, MIRROR, CLAMP, CLAMP_TO_EDGE, BORDER per axis with nearest and linear filtering, magnified"},
                 ProfileId::GeForce256, 30, 24, DepthFormat::None, [](Device& d, TextureMemory& mem) {
        d.setState(plain());
        auto& tu = d.textureUnits();
        tu.setTexture(0, rgbaTexture(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 4, 4, 1, 1, 1}, 3));
        tu.setStage(0, stage(TextureOp::SelectArg1, arg::Texture, arg::Diffuse, TextureOp::SelectArg1, arg::Texture, arg::Diffuse));
        for (int a = 0; a < 5; ++a)
            for (int f = 0; f < 2; ++f)
                for (int t = 0; t < 2; ++t) {
                    SamplerState s = sampler(FilterMode(f), AddressMode(a));
                    s.address[1] = t ? AddressMode((a + 2) % 5) : AddressMode(a);
                    s.borderColor = {255, 0, 255, 128};
                    tu.setSampler(0, s);
                    float x = float(6 * a), y = float(12 * f + 6 * t);
                    rect(d, x, y, x + 6, y + 6, kCorners, {-1.3f, -0.7f}, {2.1f, 1.9f});
                }
    }});

    b.push_back({{"texture-mipmap-lod", "mipmap selection: MIP NONE/POINT/LINEAR × min filter, LOD bias, MIN/MAX_LOD, BASE/MAX_LEVEL, minified and anisotropic quads"},
                 ProfileId::GeForce256, 32, 32, DepthFormat::None, [](Device& d, TextureMemory& mem) {
        d.setState(plain());
        auto& tu = d.textureUnits();
        auto t = rgbaTexture(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 16, 16, 1, 1, 5}, 11);
        tu.setTexture(0, t);
        tu.setStage(0, stage(TextureOp::SelectArg1, arg::Texture, arg::Diffuse, TextureOp::SelectArg1, arg::Texture, arg::Diffuse));
        int k = 0;
        for (int mip = 0; mip < 3; ++mip)
            for (int f = 0; f < 2; ++f)
                for (int v = 0; v < 2; ++v) {
                    SamplerState s = sampler(FilterMode(f), AddressMode::Wrap, MipMode(mip));
                    if (v) { s.lodBias = -0.75f; s.minLod = 0.5f; s.maxLod = 2.5f; s.baseLevel = 1; s.maxLevel = 3; }
                    tu.setSampler(0, s);
                    float x = float(8 * (k % 4)), y = float(8 * (k / 4));
                    // Repeats 5 and 3 times: anisotropic minification.
                    rect(d, x, y, x + 8, y + 8, kCorners, {0.1f, 0.2f}, {5.3f + 0.4f * float(k), 3.1f});
                    ++k;
                }
        // Texel-sized mixtures: an upload in place, seen by the next draw.
        std::vector<Rgba8> red(16 * 16, Rgba8{255, 0, 0, 255});
        mem.upload(*t, 0, 0, red);
        tu.setSampler(0, sampler(FilterMode::Linear, AddressMode::Wrap, MipMode::Linear));
        rect(d, 0, 24, 32, 32, kCorners, {0, 0}, {2, 0.5f});
    }});

    b.push_back({{"texture-formats", "every 8-bit texel format (L8, A8, L8A8, I8, RGB565, RGBA4444, RGB8, RGBA8) through MODULATE and their base-format expansion"},
                 ProfileId::GeForce256, 32, 8, DepthFormat::None, [](Device& d, TextureMemory& mem) {
        d.setState(plain());
        d.clear(true, {0, 0, 0, 0}, false, 1.0f);
        auto& tu = d.textureUnits();
        tu.setSampler(0, sampler(FilterMode::Linear));
        tu.setStage(0, stage(TextureOp::Modulate, arg::Texture, arg::Diffuse, TextureOp::Modulate, arg::Texture, arg::Diffuse));
        const TexelFormat fmts[] = {TexelFormat::L8, TexelFormat::A8, TexelFormat::L8A8, TexelFormat::I8,
                                    TexelFormat::RGB565, TexelFormat::RGBA4444, TexelFormat::RGB8, TexelFormat::RGBA8};
        for (int i = 0; i < 8; ++i) {
            tu.setTexture(0, packedTexture(mem, {TextureTarget::Texture2D, fmts[i], 4, 4, 1, 1, 1}, 40 + uint32_t(i)));
            PipelineState s = plain();
            s.blend = 1; s.srcBlend = BlendFactor::SrcAlpha; s.dstBlend = BlendFactor::InvSrcAlpha;
            d.setState(s);
            rect(d, float(4 * i), 0, float(4 * i + 4), 8, kCorners, {0.1f, 0.0f}, {1.2f, 2.0f});
        }
    }});

    b.push_back({{"texture-cube-reflection", "cube map (ARB_texture_cube_map) sampled by camera-space reflection and normal vectors (TCI), face selection and the texture matrix"},
                 ProfileId::GeForce256, 32, 32, DepthFormat::D24, [](Device& d, TextureMemory& mem) {
        d.clear(true, {0, 0, 0, 255}, true, 1.0f);
        PipelineState s;
        s.cull = CullMode::None;
        d.setState(s);
        auto& tu = d.textureUnits();
        tu.setTexture(0, rgbaTexture(mem, {TextureTarget::CubeMap, TexelFormat::RGBA8, 4, 4, 1, 1, 3}, 55));
        tu.setSampler(0, sampler(FilterMode::Linear, AddressMode::ClampToEdge, MipMode::Nearest));
        tu.setStage(0, stage(TextureOp::Modulate, arg::Texture, arg::Diffuse, TextureOp::SelectArg2, arg::Texture, arg::Diffuse));
        d.setTransforms(glm::mat4(1), glm::lookAt(glm::vec3(0, 0, 3), glm::vec3(0), glm::vec3(0, 1, 0)),
                        perspectiveTan(kTan25, 1.0f, 0.5f, 10.0f));
        // A tessellated sphere.
        std::vector<Vertex> v;
        std::vector<uint32_t> idx;
        const int n = 8;
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n; ++j) {
                // θ = iπ/8, φ = 2jπ/8
                glm::vec3 p(kSinPi8[i] * kCosPi8[2 * j], kCosPi8[i], kSinPi8[i] * kSinPi8[2 * j]);
                Vertex x;
                x.position = glm::vec4(p, 1);
                x.normal = p;
                x.diffuse = {255, uint8_t(200 + 6 * i), uint8_t(255 - 10 * j), 255};
                v.push_back(x);
            }
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                uint32_t a = uint32_t(i * (n + 1) + j);
                idx.insert(idx.end(), {a, a + 1, a + uint32_t(n) + 2, a, a + uint32_t(n) + 2, a + uint32_t(n) + 1});
            }
        TexGenState g;
        g.mode = TexGenMode::CameraSpaceReflectionVector;
        tu.setTexGen(0, g);
        d.setViewport({0, 0, 16, 32, 0, 1});
        d.draw(Primitive::TriangleList, VertexSpace::Untransformed, v, idx);
        g.mode = TexGenMode::CameraSpaceNormal;
        g.matrixEnabled = true;
        g.matrix = rotateCosSin(kCos07, kSin07, glm::vec3(1, 1, 0));
        tu.setTexGen(0, g);
        d.setViewport({16, 0, 16, 32, 0, 1});
        d.draw(Primitive::TriangleList, VertexSpace::Untransformed, v, idx);
    }});

    b.push_back({{"texgen-gl-modes", "OpenGL texgen on the SGI profile: OBJECT_LINEAR, EYE_LINEAR, SPHERE_MAP, REFLECTION/NORMAL_MAP, the texture matrix and the projective q divide"},
                 ProfileId::SgiOctaneMxe, 32, 16, DepthFormat::D16, [](Device& d, TextureMemory& mem) {
        d.clear(true, {0, 0, 0, 255}, true, 1.0f);
        PipelineState s;
        s.cull = CullMode::None;
        d.setState(s);
        auto& tu = d.textureUnits();
        tu.setTexture(0, rgbaTexture(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 8, 8, 1, 1, 1}, 77));
        tu.setSampler(0, sampler(FilterMode::Linear, AddressMode::Wrap));
        tu.setStage(0, texEnvStage(TexEnvMode::Modulate, BaseFormat::Rgba));
        d.setTransforms(rotateCosSin(kCos05, kSin05, glm::vec3(0.3f, 1, 0)),
                        glm::lookAt(glm::vec3(0, 0, 3), glm::vec3(0), glm::vec3(0, 1, 0)),
                        perspectiveTan(kTan20, 1.0f, 0.5f, 10.0f));
        const TexGenMode modes[] = {TexGenMode::PassThru, TexGenMode::ObjectLinear, TexGenMode::EyeLinear,
                                    TexGenMode::SphereMap, TexGenMode::ReflectionMap, TexGenMode::NormalMap,
                                    TexGenMode::CameraSpacePosition, TexGenMode::PassThru};
        for (int m = 0; m < 8; ++m) {
            TexGenState g;
            g.mode = modes[m];
            g.planes[0] = {1.5f, 0.3f, 0, 0.5f};
            g.planes[1] = {0, 1.2f, 0.4f, 0.5f};
            g.matrixEnabled = m >= 6;
            g.matrix = glm::scale(glm::translate(glm::mat4(1), glm::vec3(0.5f, 0.25f, 0)), glm::vec3(2, 1.5f, 1));
            g.projected = m == 7;
            tu.setTexGen(0, g);
            d.setViewport({4 * m, 0, 4, 16, 0, 1});
            std::vector<Vertex> v(4);
            const float xs[] = {-1, 1, 1, -1}, ys[] = {-1, -1, 1, 1};
            for (int i = 0; i < 4; ++i) {
                v[size_t(i)].position = {xs[i], ys[i], 0.3f * xs[i], 1};
                v[size_t(i)].normal = glm::normalize(glm::vec3(xs[i], ys[i], 1));
                v[size_t(i)].tex[0] = {xs[i] * 0.7f, ys[i] * 0.6f, 0, 1.0f + 0.5f * float(i)};
            }
            d.draw(Primitive::TriangleFan, VertexSpace::Untransformed, v);
        }
    }});

    b.push_back({{"texture-units-3d", "four texture units with their own coordinate sets and textures, a 3D texture, projected coordinates (geforce3)"},
                 ProfileId::GeForce3, 32, 32, DepthFormat::None, [](Device& d, TextureMemory& mem) {
        d.setState(plain());
        auto& tu = d.textureUnits();
        tu.setTexture(0, rgbaTexture(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 8, 8, 1, 1, 4}, 90));
        tu.setTexture(1, rgbaTexture(mem, {TextureTarget::Texture3D, TexelFormat::RGBA8, 4, 4, 4, 1, 1}, 91));
        tu.setTexture(2, packedTexture(mem, {TextureTarget::Texture1D, TexelFormat::RGB565, 16, 1, 1, 1, 1}, 92));
        tu.setTexture(3, packedTexture(mem, {TextureTarget::Texture2D, TexelFormat::L8A8, 4, 4, 1, 1, 1}, 93));
        for (int i = 0; i < 4; ++i) tu.setSampler(i, sampler(FilterMode::Linear, AddressMode(i), MipMode(i % 3)));
        StageState s0 = stage(TextureOp::SelectArg1, arg::Texture, arg::Diffuse, TextureOp::SelectArg1, arg::Texture, arg::Diffuse);
        StageState s1 = stage(TextureOp::Modulate2x, arg::Texture, arg::Current, TextureOp::Modulate, arg::Texture, arg::Current);
        s1.texCoordIndex = 1;
        StageState s2 = stage(TextureOp::Add, arg::Texture, arg::Current, TextureOp::SelectArg2, arg::Texture, arg::Current);
        s2.texCoordIndex = 2;
        StageState s3 = stage(TextureOp::BlendTextureAlpha, arg::Texture, arg::Current, TextureOp::Add, arg::Texture, arg::Current);
        s3.texCoordIndex = 3;
        tu.setStage(0, s0); tu.setStage(1, s1); tu.setStage(2, s2); tu.setStage(3, s3);
        TexGenState proj;
        proj.projected = true;
        tu.setTexGen(0, proj);
        std::vector<Vertex> v = {pv(0, 0, {255, 255, 255, 255}), pv(32, 0, {255, 128, 0, 255}),
                                 pv(32, 32, {0, 128, 255, 255}), pv(0, 32, {128, 255, 128, 255})};
        const float q[] = {1, 2, 0.5f, 1.5f};
        for (size_t i = 0; i < 4; ++i) {
            float s = (i == 1 || i == 2) ? 1.0f : 0.0f, t = i >= 2 ? 1.0f : 0.0f;
            v[i].tex[0] = {1.7f * s * q[i], 1.3f * t * q[i], 0, q[i]};
            v[i].tex[1] = {s, t, 0.2f + 0.6f * s * t, 1};
            v[i].tex[2] = {-0.5f + 2 * s + t, 0, 0, 1};
            v[i].tex[3] = {t * 3, s * 2, 0, 1};
            v[i].position.w = 1.0f / q[i];
        }
        d.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, v);
    }});

    b.push_back({{"color-table", "SGI_texture_color_table: every table base format on L8, I8 and RGBA8 textures, index rounding, sizes 2 to 256"},
                 ProfileId::SgiOctaneMxe, 32, 24, DepthFormat::None, [](Device& d, TextureMemory& mem) {
        d.setState(plain());
        auto& tu = d.textureUnits();
        tu.setSampler(0, sampler(FilterMode::Linear));
        const TexelFormat texFormats[] = {TexelFormat::L8, TexelFormat::I8, TexelFormat::RGBA8};
        const size_t sizes[] = {2, 17, 256, 64, 5, 128};
        for (int tf = 0; tf < 3; ++tf) {
            auto t = packedTexture(mem, {TextureTarget::Texture2D, texFormats[tf], 4, 4, 1, 1, 1}, 60 + uint32_t(tf));
            tu.setTexture(0, t);
            for (int f = 0; f < 6; ++f) {
                auto table = std::make_shared<ColorTable>();
                table->format = BaseFormat(f);
                for (size_t i = 0; i < sizes[f]; ++i) table->entries.push_back(pattern(300 + uint32_t(f), int(i), 0));
                tu.setColorTable(0, table);
                BaseFormat base = colorTableResultFormat(formatInfo(texFormats[tf]).base, BaseFormat(f));
                tu.setStage(0, texEnvStage(TexEnvMode::Replace, base));
                rect(d, float(5 * f), float(8 * tf), float(5 * f + 5), float(8 * tf + 8), kCorners, {0, 0}, {1.5f, 1});
            }
        }
        tu.setColorTable(0, nullptr);
    }});

    b.push_back({{"pixel-texture", "SGIX_pixel_texture: drawPixels and copyPixels through 2D and 3D textures in RGBA and RGB modes, with a colour table"},
                 ProfileId::SgiOctaneMxe, 32, 32, DepthFormat::None, [](Device& d, TextureMemory& mem) {
        d.setState(plain());
        std::vector<Rgba8> img(16 * 16);
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) img[size_t(y * 16 + x)] = {uint8_t(x * 17), uint8_t(y * 17), uint8_t((x ^ y) * 17), uint8_t(255 - x * 9)};
        d.drawPixels(0, 0, 16, 16, img);  // pixel texture off: a plain write
        auto& tu = d.textureUnits();
        tu.setTexture(0, rgbaTexture(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 8, 8, 1, 1, 1}, 123));
        tu.setSampler(0, sampler(FilterMode::Linear, AddressMode::ClampToEdge));
        tu.setPixelTexture({true, PixelTexGenMode::Rgba, 0});
        d.drawPixels(16, 0, 16, 16, img);
        tu.setTexture(0, rgbaTexture(mem, {TextureTarget::Texture3D, TexelFormat::RGBA8, 4, 4, 4, 1, 1}, 124));
        tu.setSampler(0, sampler(FilterMode::Nearest, AddressMode::Clamp));
        tu.setPixelTexture({true, PixelTexGenMode::Rgb, 0});
        d.drawPixels(-4, 16, 16, 16, img);  // clipped at the left edge
        auto table = std::make_shared<ColorTable>();
        table->format = BaseFormat::Rgb;
        for (int i = 0; i < 16; ++i) table->entries.push_back(pattern(9, i, 1));
        tu.setColorTable(0, table);
        d.copyPixels(0, 0, 16, 16, 16, 16);
        d.copyPixels(20, 20, 8, 8, 24, 12);  // overlapping source and destination
    }});

    b.push_back({{"texture-4d", "SGIS_texture4D: quadrilinear filtering with mipmaps through pixel texture, and 4D coordinates on triangles"},
                 ProfileId::SgiOctaneMxe, 32, 16, DepthFormat::None, [](Device& d, TextureMemory& mem) {
        d.setState(plain());
        auto& tu = d.textureUnits();
        tu.setTexture(0, rgbaTexture(mem, {TextureTarget::Texture4D, TexelFormat::RGBA8, 4, 4, 4, 4, 3}, 200));
        SamplerState s = sampler(FilterMode::Linear, AddressMode::Wrap, MipMode::Linear);
        s.address[3] = AddressMode::ClampToEdge;
        tu.setSampler(0, s);
        tu.setStage(0, texEnvStage(TexEnvMode::Replace, BaseFormat::Rgba));
        std::vector<Vertex> v = {pv(0, 0, {255, 255, 255, 255}), pv(16, 0, {255, 255, 255, 255}),
                                 pv(16, 16, {255, 255, 255, 255}), pv(0, 16, {255, 255, 255, 255})};
        const glm::vec4 t4[] = {{0, 0, 0.1f, 0.2f}, {2, 0, 0.6f, 0.4f}, {2, 2, 0.9f, 0.9f}, {0, 2, 0.3f, 0.7f}};
        for (size_t i = 0; i < 4; ++i) v[i].tex[0] = t4[i];
        d.draw(Primitive::TriangleFan, VertexSpace::Pretransformed, v);
        std::vector<Rgba8> img(16 * 16);
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) img[size_t(y * 16 + x)] = {uint8_t(x * 16 + 3), uint8_t(y * 16 + 5), uint8_t(x * 7 + y * 9), uint8_t(x * y)};
        tu.setPixelTexture({true, PixelTexGenMode::Rgba, 0});
        d.drawPixels(16, 0, 16, 16, img);
    }});

    b.push_back({{"passes-readback", "frames and passes: a textured base pass, a blended second pass, read-backs between them (the PEM pass structure in miniature)"},
                 ProfileId::GeForce256, 24, 24, DepthFormat::D24, [](Device& d, TextureMemory& mem) {
        d.beginFrame();
        d.beginPass("base");
        d.clear(true, {10, 20, 30, 255}, true, 1.0f);
        PipelineState s;
        s.cull = CullMode::None;
        d.setState(s);
        auto& tu = d.textureUnits();
        tu.setTexture(0, rgbaTexture(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 8, 8, 1, 1, 4}, 500));
        tu.setSampler(0, sampler(FilterMode::Linear, AddressMode::Mirror, MipMode::Linear));
        tu.setStage(0, stage(TextureOp::Modulate, arg::Texture, arg::Diffuse, TextureOp::SelectArg1, arg::Texture, arg::Diffuse));
        rect(d, 2, 2, 22, 22, kCorners, {0, 0}, {2, 2}, 0.2f, 0.6f);
        (void)d.readPixels(0, 0, 24, 24);
        d.beginPass("blend");
        s.blend = 1; s.srcBlend = BlendFactor::DestColor; s.dstBlend = BlendFactor::SrcAlpha;
        s.depthFunc = CompareFunc::Equal;
        s.depthWrite = 0;
        d.setState(s);
        tu.setStage(1, stage(TextureOp::AddSigned, arg::Texture, arg::Current, TextureOp::SelectArg2, arg::Texture, arg::Current));
        tu.setTexture(1, rgbaTexture(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 4, 4, 1, 1, 1}, 501));
        rect(d, 2, 2, 22, 22, kCorners, {0, 0}, {2, 2}, 0.2f, 0.6f);
        (void)d.readPixels(4, 4, 8, 8);
        d.beginPass("overlay");
        tu.setStage(0, StageState{});
        s = plain();
        s.blend = 1; s.srcBlend = BlendFactor::SrcAlpha; s.dstBlend = BlendFactor::InvSrcAlpha;
        d.setState(s);
        rect(d, 0, 10, 24, 14, {Rgba8{255, 255, 255, 100}, Rgba8{0, 0, 0, 200}, Rgba8{255, 0, 0, 50}, Rgba8{0, 255, 0, 255}});
        d.endFrame();
    }});

    return b;
}

const std::vector<Builder>& allBuilders() {
    static const std::vector<Builder> b = builders();
    return b;
}

// ---- the programmable device (trace version 2) -------------------------------------------
// A frame drawn on a ProgrammableDevice with `recorder` attached; returns its image as the
// replay shows it (colour target 0 as RGBA8). Its programs are registered by the module
// that owns them (bench/bench_programs.h), as `retroglass` registers them at startup.
struct ProgramBuilder {
    GoldenCase info;
    std::function<Framebuffer(const std::shared_ptr<TraceRecorder>& recorder)> build;
};

const std::vector<ProgramBuilder>& programBuilders() {
    static const std::vector<ProgramBuilder> b = {
        {{"programmable-binary-search",
          "geforce8800 (trace version 2): the binary_search benchmark frame (bench/binary_search_workload.h), "
          "a quad program registered by name searching a 512x512 R32F depth texture point-sampled 8 times per "
          "pixel into a 512x512 RGBA8 render target"},
         [](const std::shared_ptr<TraceRecorder>& recorder) {
             bench::registerPrograms();
             bench::binary_search::BinarySearchScene scene(1);
             scene.device.setRecorder(recorder);
             scene.device.beginFrame();
             scene.frame();  // exactly the frame `retroglass bench` times
             scene.device.setRecorder(nullptr);
             Framebuffer image(bench::binary_search::kWidth, bench::binary_search::kHeight, DepthFormat::None);
             std::memcpy(static_cast<void*>(image.color().data()), scene.target->renderData8(0, 0),
                         image.color().size_bytes());
             return image;
         }},
#ifndef RETROGLASS_GOLDEN_NO_DEMOS  // the sanitizer builds (tests/golden/CMakeLists.txt)
        {{"programmable-tir-frame",
          "geforce8800 (trace version 2): a frame of Davis & Wyman 2007 (demos/tir), the prism at 64x64 with "
          "front-and-back search and 3 bounces: back and front faces into RGBA16F normal/linear-depth maps, the "
          "nearby map with the world behind, the background copied, the refractor's front faces through the "
          "binary searches, total internal reflection and the exit into a float environment cube"},
         [](const std::shared_ptr<TraceRecorder>& recorder) {
             tir::registerTirPrograms();
             static const tir::TirScene scene = tir::makeTirScene("prism");
             tir::TirRenderer renderer(scene, 1, Path::Reference, 16);
             tir::TirSettings s;
             s.width = s.height = 64;
             s.envSize = 16;
             s.frontAndBack = true;
             renderer.render(scene.camera, s);  // the targets and the environment cube, made once
             renderer.device().setRecorder(recorder);
             renderer.render(scene.camera, s);  // the frame the trace holds
             renderer.device().setRecorder(nullptr);
             Framebuffer image(64, 64, DepthFormat::None);
             std::memcpy(static_cast<void*>(image.color().data()),
                         const_cast<tex::Texture&>(renderer.frameTexture()).renderData8(0, 0),
                         image.color().size_bytes());
             return image;
         }},
        {{"programmable-impostors-frame",
          "geforce8800 (trace version 2): a moving frame of Dancsik & Minarik (demos/impostors), separated mode at "
          "48x48: the mover's Depth32F shadow maps and its light map through sampleCompare (scissored), its "
          "environment impostor in six 90-degree faces of an RGBA16F cube through the static objects' impostors, "
          "the board and sky, the static glass objects through their refractor maps with the secant search and the "
          "search from outside in the mover's map (point-sampled cube fetches)"},
         [](const std::shared_ptr<TraceRecorder>& recorder) {
             impostors::registerImpostorPrograms();
             static const impostors::ImpostorScene scene = [] {
                 impostors::ChessOptions o;
                 o.segments = 12;
                 o.sphereSlices = 16;
                 o.keep = {"white_queen3"};
                 return impostors::makeChessScene(o);
             }();
             impostors::ImpostorRenderer renderer(scene, 1, Path::Reference);
             impostors::ImpostorSettings s;
             s.width = s.height = 48;
             s.envSize = s.refractorSize = 8;
             s.lightMapSize = 32;
             s.shadowMapSize = 64;
             s.mode = impostors::Mode::Separated;
             renderer.render(scene.closeUp, s);  // every map, made once
             s.moverU = 0.5f;
             renderer.device().setRecorder(recorder);
             renderer.render(scene.closeUp, s);  // the frame the trace holds: the mover moved
             renderer.device().setRecorder(nullptr);
             Framebuffer image(48, 48, DepthFormat::None);
             std::memcpy(static_cast<void*>(image.color().data()),
                         const_cast<tex::Texture&>(renderer.frameTexture()).renderData8(0, 0),
                         image.color().size_bytes());
             return image;
         }},
#endif
    };
    return b;
}

}  // namespace

const std::vector<GoldenCase>& goldenCases() {
    static const std::vector<GoldenCase> cases = [] {
        std::vector<GoldenCase> c;
        for (const Builder& b : allBuilders()) c.push_back(b.info);
        for (const ProgramBuilder& b : programBuilders()) c.push_back(b.info);
        return c;
    }();
    return cases;
}

void registerGoldenPrograms() {
    bench::registerPrograms();
#ifndef RETROGLASS_GOLDEN_NO_DEMOS
    tir::registerTirPrograms();
    impostors::registerImpostorPrograms();
#endif
}

std::vector<uint8_t> buildGoldenTrace(const std::string& name, Framebuffer* live) {
    for (const ProgramBuilder& b : programBuilders()) {
        if (b.info.name != name) continue;
        auto rec = std::make_shared<TraceRecorder>();
        Framebuffer image = b.build(rec);
        rec->finish();
        if (live) *live = std::move(image);
        return rec->bytes();
    }
    for (const Builder& b : allBuilders()) {
        if (b.info.name != name) continue;
        const Profile& p = profile(b.profile);
        // One thread on the reference path: capture does not depend on either, the
        // recorder only sees the commands.
        Device dev(p, b.width, b.height, b.depth, {Path::Reference, 1});
        TextureMemory mem(p);
        auto rec = std::make_shared<TraceRecorder>();
        dev.setRecorder(rec);
        b.build(dev, mem);
        dev.setRecorder(nullptr);
        rec->finish();
        if (live) *live = dev.framebuffer();
        return rec->bytes();
    }
    throw Error("unknown golden trace '" + name + "'");
}

}  // namespace rg::golden
