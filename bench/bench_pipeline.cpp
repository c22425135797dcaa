// The fixed-function pipeline against Mesa llvmpipe (OpenGL 1.x through OSMesa), the same
// workloads on the same thread counts:
//   fill_flat            16 full-screen flat-coloured quads per 640×480 frame (fragments/s)
//   fill_gouraud_blend   16 full-screen Gouraud quads, SRCALPHA/INVSRCALPHA (fragments/s)
//   small_triangles      40,000 Gouraud triangles of 2 pixels, indexed mesh (triangles/s)
// Names follow bench/harness.h: <workload>/<retroglass|llvmpipe>/threads:N.
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

namespace rg::bench {
namespace {

using namespace rg::raster;

constexpr int kWidth = 640, kHeight = 480;
constexpr int kFillQuads = 16;
constexpr int kGridX = 200, kGridY = 100;  // cells of 2×2 pixels, two triangles each

enum class Workload { FillFlat, FillGouraudBlend, SmallTriangles };

// ---- the geometry, shared by both implementations --------------------------------------
struct Mesh {
    std::vector<float> xyz;       // window pixels, y down, z
    std::vector<Rgba8> color;
    std::vector<uint32_t> index;  // empty: non-indexed triangle list
    int64_t itemsPerFrame = 0;
};

Mesh makeMesh(Workload w) {
    Mesh m;
    auto vertex = [&](float x, float y, Rgba8 c) {
        m.xyz.insert(m.xyz.end(), {x, y, 0.5f});
        m.color.push_back(c);
    };
    if (w == Workload::SmallTriangles) {
        const float x0 = 120, y0 = 140;
        for (int j = 0; j <= kGridY; ++j)
            for (int i = 0; i <= kGridX; ++i)
                vertex(x0 + 2.0f * i, y0 + 2.0f * j,
                       Rgba8{uint8_t(i), uint8_t(j * 2), uint8_t(i ^ j), 255});
        for (int j = 0; j < kGridY; ++j)
            for (int i = 0; i < kGridX; ++i) {
                uint32_t a = uint32_t(j * (kGridX + 1) + i), b = a + 1, c = a + kGridX + 1,
                         d = c + 1;
                m.index.insert(m.index.end(), {a, b, d, a, d, c});
            }
        m.itemsPerFrame = int64_t(kGridX) * kGridY * 2;
        return m;
    }
    for (int q = 0; q < kFillQuads; ++q) {
        const bool gouraud = w == Workload::FillGouraudBlend;
        Rgba8 c[4];
        for (int k = 0; k < 4; ++k)
            c[k] = gouraud ? Rgba8{uint8_t(40 * k + q), uint8_t(200 - 30 * k), uint8_t(16 * q),
                                   uint8_t(96 + 20 * k)}
                           : Rgba8{uint8_t(16 * q), uint8_t(255 - 16 * q), 77, 255};
        const float W = kWidth, H = kHeight;
        vertex(0, 0, c[0]); vertex(W, 0, c[1]); vertex(W, H, c[2]);
        vertex(0, 0, c[0]); vertex(W, H, c[2]); vertex(0, H, c[3]);
    }
    m.itemsPerFrame = int64_t(kFillQuads) * kWidth * kHeight;
    return m;
}

// ---- retroglass ---------------------------------------------------------------------------
void runRetroglass(benchmark::State& state, Workload w, int threads) {
    const Mesh mesh = makeMesh(w);
    Device dev(profile(ProfileId::GeForce256), kWidth, kHeight, DepthFormat::None,
               {Path::Fast, threads});
    PipelineState s;
    s.cull = CullMode::None;
    s.depthTest = 0;
    s.depthWrite = 0;
    s.shade = w == Workload::FillFlat ? ShadeMode::Flat : ShadeMode::Gouraud;
    if (w == Workload::FillGouraudBlend) {
        s.blend = 1;
        s.srcBlend = BlendFactor::SrcAlpha;
        s.dstBlend = BlendFactor::InvSrcAlpha;
    }
    dev.setState(s);
    // The mesh goes through the full transform (orthographic, like glOrtho on the GL side).
    dev.setTransforms(glm::mat4(1.0f), glm::mat4(1.0f),
                      glm::orthoLH_ZO(0.0f, float(kWidth), float(kHeight), 0.0f, 0.0f, 1.0f));
    // The 16-byte D3DFVF_XYZ | D3DFVF_DIFFUSE vertices a Direct3D 7 program would put in
    // its vertex buffer: the same bytes per vertex as the float xyz and unsigned-byte
    // colour arrays the GL side hands over.
    std::vector<VertexXyzDiffuse> verts(mesh.color.size());
    for (size_t i = 0; i < verts.size(); ++i) {
        verts[i].position = {mesh.xyz[3 * i], mesh.xyz[3 * i + 1], mesh.xyz[3 * i + 2]};
        verts[i].diffuse = mesh.color[i];
    }
    // Wall-clock time per frame, as the llvmpipe side measures it (manual time on both
    // sides also gives both the same name suffix, which the harness pairs on).
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        dev.clear(true, Rgba8{0, 0, 0, 255}, false, 1.0f);
        dev.draw(Primitive::TriangleList, verts, mesh.index);
        benchmark::DoNotOptimize(dev.framebuffer().color().data());
        state.SetIterationTime(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    state.SetItemsProcessed(state.iterations() * mesh.itemsPerFrame);
}

// ---- llvmpipe ----------------------------------------------------------------------------
void runLlvmpipe(benchmark::State& state, Workload w, int threads) {
    auto mesh = std::make_shared<const Mesh>(makeMesh(w));
    auto setup = [mesh, w] {
        setupWindowOrtho(kWidth, kHeight);
        glShadeModel(w == Workload::FillFlat ? GL_FLAT : GL_SMOOTH);
        if (w == Workload::FillGouraudBlend) {
            glEnable(GL_BLEND);
            glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        }
        glClearColor(0, 0, 0, 1);
        glEnableClientState(GL_VERTEX_ARRAY);
        glEnableClientState(GL_COLOR_ARRAY);
        glVertexPointer(3, GL_FLOAT, 0, mesh->xyz.data());
        glColorPointer(4, GL_UNSIGNED_BYTE, 0, mesh->color.data());
    };
    auto frame = [mesh] {
        glClear(GL_COLOR_BUFFER_BIT);
        if (mesh->index.empty())
            glDrawArrays(GL_TRIANGLES, 0, GLsizei(mesh->color.size()));
        else
            glDrawElements(GL_TRIANGLES, GLsizei(mesh->index.size()), GL_UNSIGNED_INT,
                           mesh->index.data());
    };
    runMesaBenchmark(state, kWidth, kHeight, threads, setup, frame, mesh->itemsPerFrame);
}

// Registered once `retroglass bench` has read its thread counts (harness.h).
const bool registered = addWorkloads([](const std::vector<int>& threadCounts) {
    const struct {
        const char* name;
        Workload w;
    } workloads[] = {{"fill_flat", Workload::FillFlat},
                     {"fill_gouraud_blend", Workload::FillGouraudBlend},
                     {"small_triangles", Workload::SmallTriangles}};
    for (const auto& wl : workloads)
        for (int t : threadCounts) {
            const std::string suffix = "/threads:" + std::to_string(t);
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
});

}  // namespace
}  // namespace rg::bench
