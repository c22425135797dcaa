// Texturing workloads against Mesa llvmpipe (OpenGL 1.3 fixed function through OSMesa),
// 640×480, the same geometry, textures and filters on both sides:
//   tex_bilinear_2d      4 full-screen quads, 256² RGBA8 texture, LINEAR, MODULATE
//   tex_cube_trilinear   4 full-screen quads, 128² RGBA8 cube map with mips, unnormalized
//                        per-vertex directions, LINEAR_MIPMAP_LINEAR, MODULATE
//   tex_two_stage_blend  4 full-screen quads, the PEM pass: cube map MODULATE diffuse,
//                        then MODULATE by a 1D Fresnel texture, SRCALPHA/INVSRCALPHA blend
//   tex_upload_rgb8      64 uploads of a 128² RGB8 image into one texture (lightfield's
//                        swapped slices, 1024 of them a frame at paper quality); items are
//                        texels; glTexSubImage2D into a GL_RGB8 texture on llvmpipe
// and ours alone (llvmpipe has neither):
//   pixel_texture_4d     a 640×480 drawPixels through a 16⁴ RGBA8 4D texture,
//                        quadrilinear (sgi-octane-mxe)
//   color_table_lookup   4 full-screen quads of an I8 index texture through a 256-entry
//                        RGBA colour table, NEAREST (sgi-octane-mxe)
// Items are fragments (pixels for pixel_texture_4d). Names follow bench/harness.h.
#include <GL/gl.h>
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "core/profile.h"
#include "harness.h"
#include "mesa_peer.h"
#include "rasterizer/device.h"
#include "texunit/texture_units.h"

namespace rg::bench {
namespace {

using namespace rg::raster;
using namespace rg::tex;

constexpr int kWidth = 640, kHeight = 480;
constexpr int kQuads = 4;

enum class Workload { Bilinear2D, CubeTrilinear, TwoStageBlend };

uint32_t mix(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    return x ^ (x >> 16);
}

// ---- shared data -----------------------------------------------------------------------
struct Scene {
    std::vector<float> xyz;            // window pixels, z
    std::vector<Rgba8> color;
    std::vector<float> tc0, tc1;       // set 0: (s, t) or a cube direction (3); set 1: s
    int tc0Size = 2;
    // Texture images: [level] (2D, 1D) or [face][level] flattened (cube).
    std::vector<std::vector<uint8_t>> tex2d, cube, fresnel;
    int tex2dSize = 256, cubeSize = 128, fresnelSize = 64;
};

std::vector<uint8_t> image(int w, int h, uint32_t seed) {
    std::vector<uint8_t> px(size_t(w) * size_t(h) * 4);
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(mix(uint32_t(i) * 2654435761u + seed) >> 7);
    return px;
}

Scene makeScene(Workload w) {
    Scene s;
    const float W = kWidth, H = kHeight;
    for (int q = 0; q < kQuads; ++q) {
        const float corner[4][2] = {{0, 0}, {W, 0}, {W, H}, {0, H}};
        const int order[6] = {0, 1, 2, 0, 2, 3};
        for (int k : order) {
            s.xyz.insert(s.xyz.end(), {corner[k][0], corner[k][1], 0.5f});
            s.color.push_back(Rgba8{uint8_t(200 - 10 * q), uint8_t(180 + 20 * (k & 1)), 230,
                                    uint8_t(w == Workload::TwoStageBlend ? 140 + 20 * k : 255)});
            if (w == Workload::Bilinear2D) {
                // 256² texels over 640×480: magnified about 2.5×, repeated once.
                s.tc0.insert(s.tc0.end(), {corner[k][0] / W * 1.3f + 0.01f * q, corner[k][1] / H});
            } else {
                // Unnormalized directions sweeping the +Z face and its neighbours; about
                // one and a half texels per pixel, so trilinear blends two levels.
                const float x = (corner[k][0] / W - 0.5f) * 6.0f, y = (corner[k][1] / H - 0.5f) * 4.5f;
                s.tc0.insert(s.tc0.end(), {x + 0.1f * q, -y, 2.0f});
                s.tc1.push_back(corner[k][0] / W * 0.8f + 0.1f);
            }
        }
    }
    s.tc0Size = w == Workload::Bilinear2D ? 2 : 3;
    for (int l = 0, n = s.tex2dSize; n >= 1; ++l, n /= 2) s.tex2d.push_back(image(n, n, 7u + uint32_t(l)));
    for (int f = 0; f < 6; ++f)
        for (int l = 0, n = s.cubeSize; n >= 1; ++l, n /= 2)
            s.cube.push_back(image(n, n, 100u * uint32_t(f + 1) + uint32_t(l)));
    for (int l = 0, n = s.fresnelSize; n >= 1; ++l, n /= 2) s.fresnel.push_back(image(n, 1, 999u + uint32_t(l)));
    return s;
}

int levelsOf(int n) {
    int l = 0;
    for (; n >= 1; n /= 2) ++l;
    return l;
}

// ---- retroglass ------------------------------------------------------------------------
void runRetroglass(benchmark::State& state, Workload w, int threads) {
    const Scene sc = makeScene(w);
    const Profile& p = profile(ProfileId::GeForce256);
    Device dev(p, kWidth, kHeight, DepthFormat::None, {Path::Fast, threads});
    PipelineState ps;
    ps.cull = CullMode::None;
    ps.depthTest = 0;
    ps.depthWrite = 0;
    if (w == Workload::TwoStageBlend) {
        ps.blend = 1;
        ps.srcBlend = BlendFactor::SrcAlpha;
        ps.dstBlend = BlendFactor::InvSrcAlpha;
    }
    dev.setState(ps);
    dev.setTransforms(glm::mat4(1.0f), glm::mat4(1.0f),
                      glm::orthoLH_ZO(0.0f, float(kWidth), float(kHeight), 0.0f, 0.0f, 1.0f));
    auto mem = std::make_shared<TextureMemory>(p);
    TextureUnits& tu = dev.textureUnits();
    tu.setTextureMemory(mem);
    StageState modulate;
    modulate.colorOp = TextureOp::Modulate;
    modulate.alphaOp = TextureOp::Modulate;
    modulate.colorArg1 = modulate.alphaArg1 = arg::Texture;
    modulate.colorArg2 = modulate.alphaArg2 = arg::Current;
    SamplerState linear;
    if (w == Workload::Bilinear2D) {
        auto t = mem->create({TextureTarget::Texture2D, TexelFormat::RGBA8, sc.tex2dSize, sc.tex2dSize, 1, 1, 1});
        mem->upload(*t, 0, 0, sc.tex2d[0]);
        tu.setTexture(0, t);
        tu.setSampler(0, linear);
        tu.setStage(0, modulate);
    } else {
        const int cl = levelsOf(sc.cubeSize);
        auto cube = mem->create({TextureTarget::CubeMap, TexelFormat::RGBA8, sc.cubeSize, sc.cubeSize, 1, 1, cl});
        for (int f = 0; f < 6; ++f)
            for (int l = 0; l < cl; ++l) mem->upload(*cube, l, f, sc.cube[size_t(f * cl + l)]);
        SamplerState tri;
        tri.mipFilter = MipMode::Linear;
        tu.setTexture(0, cube);
        tu.setSampler(0, tri);
        tu.setStage(0, modulate);
        if (w == Workload::TwoStageBlend) {
            const int fl = levelsOf(sc.fresnelSize);
            auto fres = mem->create({TextureTarget::Texture1D, TexelFormat::RGBA8, sc.fresnelSize, 1, 1, 1, fl});
            for (int l = 0; l < fl; ++l) mem->upload(*fres, l, 0, sc.fresnel[size_t(l)]);
            SamplerState s1 = tri;
            s1.address[0] = AddressMode::ClampToEdge;
            StageState st1 = modulate;
            st1.texCoordIndex = 1;
            tu.setTexture(1, fres);
            tu.setSampler(1, s1);
            tu.setStage(1, st1);
        }
    }
    std::vector<Vertex> verts(sc.color.size());
    for (size_t i = 0; i < verts.size(); ++i) {
        verts[i].position = {sc.xyz[3 * i], sc.xyz[3 * i + 1], sc.xyz[3 * i + 2], 1.0f};
        verts[i].diffuse = sc.color[i];
        if (sc.tc0Size == 2)
            verts[i].tex[0] = {sc.tc0[2 * i], sc.tc0[2 * i + 1], 0.0f, 1.0f};
        else
            verts[i].tex[0] = {sc.tc0[3 * i], sc.tc0[3 * i + 1], sc.tc0[3 * i + 2], 1.0f};
        if (!sc.tc1.empty()) verts[i].tex[1] = {sc.tc1[i], 0.0f, 0.0f, 1.0f};
    }
    // Wall-clock time per frame, as the llvmpipe side measures it; manual time on both
    // sides also gives both the same name suffix, which the harness pairs on.
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        dev.clear(true, Rgba8{0, 0, 0, 255}, false, 1.0f);
        dev.draw(Primitive::TriangleList, VertexSpace::Untransformed, verts);
        benchmark::DoNotOptimize(dev.framebuffer().color().data());
        state.SetIterationTime(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    state.SetItemsProcessed(state.iterations() * int64_t(kQuads) * kWidth * kHeight);
}

// ---- llvmpipe --------------------------------------------------------------------------
void runLlvmpipe(benchmark::State& state, Workload w, int threads) {
    auto sc = std::make_shared<const Scene>(makeScene(w));
    auto setup = [sc, w] {
        setupWindowOrtho(kWidth, kHeight);
        glShadeModel(GL_SMOOTH);
        if (w == Workload::TwoStageBlend) {
            glEnable(GL_BLEND);
            glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        }
        glClearColor(0, 0, 0, 1);
        GLuint names[2];
        glGenTextures(2, names);
        glActiveTexture(GL_TEXTURE0);
        if (w == Workload::Bilinear2D) {
            glBindTexture(GL_TEXTURE_2D, names[0]);
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, sc->tex2dSize, sc->tex2dSize, 0, GL_RGBA,
                         GL_UNSIGNED_BYTE, sc->tex2d[0].data());
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glEnable(GL_TEXTURE_2D);
        } else {
            const int cl = levelsOf(sc->cubeSize);
            glBindTexture(GL_TEXTURE_CUBE_MAP, names[0]);
            for (int f = 0; f < 6; ++f)
                for (int l = 0, n = sc->cubeSize; l < cl; ++l, n /= 2)
                    glTexImage2D(GLenum(GL_TEXTURE_CUBE_MAP_POSITIVE_X + f), l, GL_RGBA8, n, n, 0,
                                 GL_RGBA, GL_UNSIGNED_BYTE, sc->cube[size_t(f * cl + l)].data());
            glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
            glTexParameteri(GL_TEXTURE_CUBE_MAP, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glEnable(GL_TEXTURE_CUBE_MAP);
        }
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        if (w == Workload::TwoStageBlend) {
            glActiveTexture(GL_TEXTURE1);
            glBindTexture(GL_TEXTURE_1D, names[1]);
            for (int l = 0, n = sc->fresnelSize; n >= 1; ++l, n /= 2)
                glTexImage1D(GL_TEXTURE_1D, l, GL_RGBA8, n, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                             sc->fresnel[size_t(l)].data());
            glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
            glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
            glTexParameteri(GL_TEXTURE_1D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
            glEnable(GL_TEXTURE_1D);
            glClientActiveTexture(GL_TEXTURE1);
            glEnableClientState(GL_TEXTURE_COORD_ARRAY);
            glTexCoordPointer(1, GL_FLOAT, 0, sc->tc1.data());
        }
        glClientActiveTexture(GL_TEXTURE0);
        glEnableClientState(GL_TEXTURE_COORD_ARRAY);
        glTexCoordPointer(sc->tc0Size, GL_FLOAT, 0, sc->tc0.data());
        glEnableClientState(GL_VERTEX_ARRAY);
        glEnableClientState(GL_COLOR_ARRAY);
        glVertexPointer(3, GL_FLOAT, 0, sc->xyz.data());
        glColorPointer(4, GL_UNSIGNED_BYTE, 0, sc->color.data());
    };
    auto frame = [sc] {
        glClear(GL_COLOR_BUFFER_BIT);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(sc->color.size()));
    };
    runMesaBenchmark(state, kWidth, kHeight, threads, setup, frame, int64_t(kQuads) * kWidth * kHeight);
}

// ---- texture upload ------------------------------------------------------------------
constexpr int kUploadSize = 128, kUploads = 64;

std::shared_ptr<const std::vector<std::vector<uint8_t>>> uploadImages() {
    auto images = std::make_shared<std::vector<std::vector<uint8_t>>>(kUploads);
    for (int k = 0; k < kUploads; ++k) {
        auto& img = (*images)[size_t(k)];
        img.resize(size_t(kUploadSize) * kUploadSize * 3);
        for (size_t i = 0; i < img.size(); ++i) img[i] = uint8_t(mix(uint32_t(i) * 131u + uint32_t(k)));
    }
    return images;
}

void runUploadRetroglass(benchmark::State& state) {
    const auto images = uploadImages();
    TextureMemory mem(profile(ProfileId::SgiOctaneMxe));
    auto t = mem.create({TextureTarget::Texture2D, TexelFormat::RGB8, kUploadSize, kUploadSize, 1, 1, 1});
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        for (const auto& img : *images) mem.upload(*t, 0, 0, img);
        benchmark::DoNotOptimize(t->data8(0, 0));
        state.SetIterationTime(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    state.SetItemsProcessed(state.iterations() * int64_t(kUploads) * kUploadSize * kUploadSize);
}

void runUploadLlvmpipe(benchmark::State& state, int threads) {
    const auto images = uploadImages();
    auto setup = [] {
        GLuint name;
        glGenTextures(1, &name);
        glBindTexture(GL_TEXTURE_2D, name);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, kUploadSize, kUploadSize, 0, GL_RGB,
                     GL_UNSIGNED_BYTE, nullptr);
    };
    auto frame = [images] {
        for (const auto& img : *images)
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, kUploadSize, kUploadSize, GL_RGB,
                            GL_UNSIGNED_BYTE, img.data());
    };
    runMesaBenchmark(state, 64, 64, threads, setup, frame,
                     int64_t(kUploads) * kUploadSize * kUploadSize);
}

// ---- ours alone ------------------------------------------------------------------------
void runPixelTexture4D(benchmark::State& state, int threads) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    Device dev(p, kWidth, kHeight, DepthFormat::None, {Path::Fast, threads});
    TextureMemory mem(p);
    auto t = mem.create({TextureTarget::Texture4D, TexelFormat::RGBA8, 16, 16, 16, 16, 1});
    mem.upload(*t, 0, 0, image(16 * 16 * 16 * 16, 1, 5));
    TextureUnits& tu = dev.textureUnits();
    tu.setTexture(0, t);
    SamplerState s;
    s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge,
                 AddressMode::ClampToEdge};
    tu.setSampler(0, s);
    tu.setPixelTexture({true, PixelTexGenMode::Rgba, 0});
    std::vector<Rgba8> pixels(size_t(kWidth) * kHeight);
    for (size_t i = 0; i < pixels.size(); ++i) {
        uint32_t h = mix(uint32_t(i));
        pixels[i] = {uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
    }
    for (auto _ : state) {
        dev.drawPixels(0, 0, kWidth, kHeight, pixels);
        benchmark::DoNotOptimize(dev.framebuffer().color().data());
    }
    state.SetItemsProcessed(state.iterations() * int64_t(kWidth) * kHeight);
}

void runColorTable(benchmark::State& state, int threads) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    Device dev(p, kWidth, kHeight, DepthFormat::None, {Path::Fast, threads});
    PipelineState ps;
    ps.cull = CullMode::None;
    ps.depthTest = 0;
    ps.depthWrite = 0;
    dev.setState(ps);
    dev.setTransforms(glm::mat4(1.0f), glm::mat4(1.0f),
                      glm::orthoLH_ZO(0.0f, float(kWidth), float(kHeight), 0.0f, 0.0f, 1.0f));
    TextureMemory mem(p);
    auto t = mem.create({TextureTarget::Texture2D, TexelFormat::I8, 256, 256, 1, 1, 1});
    std::vector<uint8_t> idx(256 * 256);
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = uint8_t(mix(uint32_t(i)));
    mem.upload(*t, 0, 0, idx);
    auto table = std::make_shared<ColorTable>();
    table->format = BaseFormat::Rgba;
    for (int i = 0; i < 256; ++i)
        table->entries.push_back({uint8_t(i), uint8_t(255 - i), uint8_t(i * 7), 255});
    TextureUnits& tu = dev.textureUnits();
    tu.setTexture(0, t);
    SamplerState s;
    s.magFilter = s.minFilter = FilterMode::Nearest;
    tu.setSampler(0, s);
    tu.setColorTable(0, table);
    tu.setStage(0, texEnvStage(TexEnvMode::Replace, BaseFormat::Rgba));
    TexGenState g;
    g.projected = true;
    tu.setTexGen(0, g);
    const float W = kWidth, H = kHeight;
    std::vector<Vertex> verts;
    for (int q = 0; q < kQuads; ++q) {
        const float corner[4][2] = {{0, 0}, {W, 0}, {W, H}, {0, H}};
        for (int k : {0, 1, 2, 0, 2, 3}) {
            Vertex v;
            v.position = {corner[k][0], corner[k][1], 0.5f, 1.0f};
            v.tex[0] = {corner[k][0] / W * 2.0f, corner[k][1] / H * 2.0f, 0.0f, 1.0f};
            verts.push_back(v);
        }
    }
    for (auto _ : state) {
        dev.draw(Primitive::TriangleList, VertexSpace::Untransformed, verts);
        benchmark::DoNotOptimize(dev.framebuffer().color().data());
    }
    state.SetItemsProcessed(state.iterations() * int64_t(kQuads) * kWidth * kHeight);
}

// Registered once `retroglass bench` has read its thread counts (harness.h).
const bool registered = addWorkloads([](const std::vector<int>& threadCounts) {
    const struct {
        const char* name;
        Workload w;
    } workloads[] = {{"tex_bilinear_2d", Workload::Bilinear2D},
                     {"tex_cube_trilinear", Workload::CubeTrilinear},
                     {"tex_two_stage_blend", Workload::TwoStageBlend}};
    for (int t : threadCounts) {
        const std::string suffix = "/threads:" + std::to_string(t);
        for (const auto& wl : workloads) {
            const Workload w = wl.w;
            benchmark::RegisterBenchmark((std::string(wl.name) + "/retroglass" + suffix).c_str(),
                                         [w, t](benchmark::State& s) { runRetroglass(s, w, t); })
                ->UseManualTime()
                ->Unit(benchmark::kMillisecond);
            benchmark::RegisterBenchmark((std::string(wl.name) + "/llvmpipe" + suffix).c_str(),
                                         [w, t](benchmark::State& s) { runLlvmpipe(s, w, t); })
                ->UseManualTime()
                ->Unit(benchmark::kMillisecond);
        }
        // An upload is one thread on both sides; registered per thread count so that the
        // harness pairs it like the others.
        benchmark::RegisterBenchmark(("tex_upload_rgb8/retroglass" + suffix).c_str(),
                                     [](benchmark::State& s) { runUploadRetroglass(s); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("tex_upload_rgb8/llvmpipe" + suffix).c_str(),
                                     [t](benchmark::State& s) { runUploadLlvmpipe(s, t); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("pixel_texture_4d/retroglass" + suffix).c_str(),
                                     [t](benchmark::State& s) { runPixelTexture4D(s, t); })
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("color_table_lookup/retroglass" + suffix).c_str(),
                                     [t](benchmark::State& s) { runColorTable(s, t); })
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
    }
});

}  // namespace
}  // namespace rg::bench
