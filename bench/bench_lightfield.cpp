// Heidrich et al. 1999 §3 against Mesa llvmpipe: the Gortler reconstruction of a 16·16·64·64
// RGB light field at 400² (the frame of `retroglass reproduce lightfield`'s §4 route, with
// synthetic texels: the arithmetic does not depend on them). llvmpipe draws the same
// triangles (per eye point its hexagon on the (s, t) plane), the same 256 RGB8 slices
// (LINEAR, CLAMP_TO_EDGE), the same vertex colours and GL MODULATE, ONE/ONE blending.
// Pixel texture, texture colour tables and 4D textures have no llvmpipe peer (ours only:
// pixel_texture_4d and color_table_lookup in bench_texunit.cpp, the lightfield_* frames in
// bench_papers.cpp).
//
// lightfield_vq_assign (ours only): the VQ's nearest-codeword search (vq.cpp, what training
// and encoding spend their time in) for 8192 blocks of 48 bytes (2×2×2×2 RGB) against a
// K = 2^16 codebook: 1/128 of encoding the paper's 2^20 all-halved blocks.
#include <GL/gl.h>
#include <benchmark/benchmark.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "gortler_renderer.h"
#include "harness.h"
#include "lightfield_scene.h"
#include "mesa_peer.h"
#include "vq.h"

namespace rg::bench {
namespace {

constexpr int kSize = 400;
// The slices' texture names in the llvmpipe child (setup fills them, frame binds them).
std::vector<GLuint> gSliceNames;

struct GortlerWorkload {
    lightfield::LightField lf;
    ray::Camera camera;
    std::vector<float> xyz, st;
    std::vector<uint8_t> rgba;
    std::vector<int> first, count;
};

std::shared_ptr<const GortlerWorkload> workload() {
    auto w = std::make_shared<GortlerWorkload>();
    w->lf.slab = lightfield::geometrySlab(16, 64);
    w->lf.data.resize(w->lf.slab.samples() * 3);
    uint32_t h = 12345;
    for (uint8_t& b : w->lf.data) {
        h = h * 1664525u + 1013904223u;
        b = uint8_t(h >> 24);
    }
    w->camera = lightfield::evalCamera(1);
    const lightfield::LightSlab& s = w->lf.slab;
    for (int j = 0; j < s.T; ++j)
        for (int i = 0; i < s.S; ++i) {
            w->first.push_back(int(w->xyz.size() / 3));
            const auto tris = lightfield::eyePointTriangles(s, i, j, lightfield::Triangulation::FixedDiagonal);
            for (const auto& t : tris)
                for (const glm::ivec2& g : t.v) {
                    const glm::vec3 p = s.eyePoint(g.x, g.y);
                    const glm::vec2 uv = lightfield::windowCoords(s, w->camera.eye, p);
                    const uint8_t wt = g == glm::ivec2(i, j) ? 255 : 0;
                    w->xyz.insert(w->xyz.end(), {p.x, p.y, p.z});
                    w->st.insert(w->st.end(), {uv.x, uv.y});
                    w->rgba.insert(w->rgba.end(), {wt, wt, wt, wt});
                }
            w->count.push_back(int(tris.size() * 3));
        }
    return w;
}

void runRetroglass(benchmark::State& state, int threads) {
    auto w = workload();
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    auto mem = std::make_shared<tex::TextureMemory>(p);
    lightfield::SliceTextures slices(mem, w->lf);
    raster::Device dev(p, kSize, kSize, raster::DepthFormat::None, {Path::Fast, threads});
    for (auto _ : state) {
        // Manual time, as the peer's (the harness pairs the two names).
        const auto t0 = std::chrono::steady_clock::now();
        dev.beginFrame();
        lightfield::renderGortler(dev, slices, w->lf, w->camera);
        dev.endFrame();
        benchmark::DoNotOptimize(dev.framebuffer().color().data());
        state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    state.SetItemsProcessed(state.iterations());
}

void runLlvmpipe(benchmark::State& state, int threads) {
    auto w = workload();
    auto setup = [w] {
        setupWindowOrtho(kSize, kSize);
        // GL's clip volume −w ≤ z ≤ w: the same camera as ours with GL's depth mapping.
        glMatrixMode(GL_PROJECTION);
        const glm::mat4 proj = glm::perspectiveRH_NO(glm::radians(w->camera.fovYDegrees), 1.0f, 0.05f, 100.0f);
        glLoadMatrixf(glm::value_ptr(proj));
        glMatrixMode(GL_MODELVIEW);
        const glm::mat4 view = lightfield::viewMatrix(w->camera);
        glLoadMatrixf(glm::value_ptr(view));
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        std::vector<GLuint>& names = gSliceNames;
        names.assign(size_t(w->lf.slab.S * w->lf.slab.T), 0);
        glGenTextures(GLsizei(names.size()), names.data());
        for (int j = 0; j < w->lf.slab.T; ++j)
            for (int i = 0; i < w->lf.slab.S; ++i) {
                glBindTexture(GL_TEXTURE_2D, names[size_t(j * w->lf.slab.S + i)]);
                glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, w->lf.slab.U, w->lf.slab.V, 0, GL_RGB, GL_UNSIGNED_BYTE, w->lf.slice(i, j));
                glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
                glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
                glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
                glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            }
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_MODULATE);
        glEnable(GL_TEXTURE_2D);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        glShadeModel(GL_SMOOTH);
        glClearColor(0, 0, 0, 0);
        glEnableClientState(GL_VERTEX_ARRAY);
        glEnableClientState(GL_COLOR_ARRAY);
        glEnableClientState(GL_TEXTURE_COORD_ARRAY);
        glVertexPointer(3, GL_FLOAT, 0, w->xyz.data());
        glColorPointer(4, GL_UNSIGNED_BYTE, 0, w->rgba.data());
        glTexCoordPointer(2, GL_FLOAT, 0, w->st.data());
    };
    auto frame = [w] {
        glClear(GL_COLOR_BUFFER_BIT);
        // The same order as ours: eye points row by row, one texture bind and draw each.
        for (size_t e = 0; e < w->first.size(); ++e) {
            glBindTexture(GL_TEXTURE_2D, gSliceNames[e]);
            glDrawArrays(GL_TRIANGLES, w->first[e], w->count[e]);
        }
    };
    runMesaBenchmark(state, kSize, kSize, threads, setup, frame, 1);
}

void runVqAssign(benchmark::State& state, int threads) {
    constexpr int kBlocks = 8192, kCodewords = 65536, kDims = 48;
    // Byte values, as the encoding sees them (the light field's samples, the rounded codebook).
    std::vector<float> blocks(size_t(kBlocks) * kDims), codebook(size_t(kCodewords) * kDims);
    uint32_t h = 777;
    for (float& v : blocks) v = float((h = h * 1664525u + 1013904223u) >> 24);
    for (float& v : codebook) v = float((h = h * 1664525u + 1013904223u) >> 24);
    for (auto _ : state) {
        const std::vector<int> label = lightfield::nearestCodewords(blocks.data(), kBlocks, codebook.data(), kCodewords, kDims, threads);
        benchmark::DoNotOptimize(label.data());
    }
    state.SetItemsProcessed(state.iterations() * kBlocks);
}

// Registered once `retroglass bench` has read its thread counts (harness.h).
const bool registered = addWorkloads([](const std::vector<int>& threadCounts) {
    for (int t : threadCounts) {
        const std::string suffix = "/threads:" + std::to_string(t);
        benchmark::RegisterBenchmark(("lightfield_gortler_400/retroglass" + suffix).c_str(),
                                     [t](benchmark::State& s) { runRetroglass(s, t); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("lightfield_gortler_400/llvmpipe" + suffix).c_str(),
                                     [t](benchmark::State& s) { runLlvmpipe(s, t); })
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark(("lightfield_vq_assign/retroglass" + suffix).c_str(),
                                     [t](benchmark::State& s) { runVqAssign(s, t); })
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
    }
    noteOursOnly("lightfield_vq_assign", "a CPU k-means step (Eigen products), no GL peer");
});

}  // namespace
}  // namespace rg::bench
