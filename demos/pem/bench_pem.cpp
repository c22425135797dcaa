// `retroglass bench --filter pem`: the PEM viewer's frame at 640×480 (001 §6 table),
// on and off the manifold, at the paper's ~40,000 triangles and 256²×6 EMs. There is no
// software peer for this workload: the figure to compare with is the paper's own, 22 FPS
// on the manifold and 17.5 FPS off it on a 733 MHz PC with a GeForce, reported beside ours
// as the counter paper_fps.
#include <benchmark/benchmark.h>

#include <memory>
#include <random>

#include "harness.h"
#include "pem_precompute.h"
#include "pem_renderer.h"
#include "raycore/builtin_scenes.h"

namespace rg::pem {
namespace {

struct ViewerFixture {
    PemScene scene;
    std::unique_ptr<raster::Device> device;
    std::unique_ptr<PemRenderer> renderer;
    PemSample a, b;
    ray::ViewpointPath path;

    explicit ViewerFixture(int threads) {
        ray::BuiltinOptions bo;
        bo.teapotLevel = 25;  // 40,000 triangles
        scene = makePemScene(ray::makeBuiltinScene("teapot-in-room", bo), PemSceneOptions{});
        path = scene.scene.viewpointPaths.at(0);
        device = std::make_unique<raster::Device>(profileByName("geforce256"), 640, 480,
                                                  raster::DepthFormat::D24,
                                                  raster::DeviceOptions{Path::Fast, threads});
        renderer = std::make_unique<PemRenderer>(*device, scene);
        // Maps of the paper's size with arbitrary texels: the frame's cost does not depend
        // on the values, only on the sizes and the sampling.
        ViewSample s;
        std::mt19937 rng(1);
        for (size_t p = 0; p < scene.parts.size(); ++p) {
            PartMaps m;
            for (MapTexels* t : {&m.local, &m.distant}) {
                t->layout = TexelLayout{256, 6};
                t->texels.resize(size_t(t->layout.count()));
                for (auto& x : t->texels) x = {uint8_t(rng()), uint8_t(rng()), uint8_t(rng()), uint8_t(rng())};
            }
            s.parts.push_back(std::move(m));
        }
        a = uploadSample(*renderer, s, EmMode::Layered);
        b = uploadSample(*renderer, s, EmMode::Layered);
    }
};

// The eye alternates between two nearby viewpoints so that texture-coordinate generation
// is redone every frame, as in the interactive viewer.
void viewerFrame(benchmark::State& state, bool blended, int threads) {
    ViewerFixture f(threads);
    double texgen = 0;
    int frames = 0;
    for (auto _ : state) {
        ray::Camera cam = f.path.at(uint32_t(frames % 2));
        FrameTiming t = blended ? f.renderer->render(cam, EmMode::Layered, f.a, &f.b, 0.5f)
                                : f.renderer->render(cam, EmMode::Layered, f.a);
        texgen += t.texgenMs;
        ++frames;
        benchmark::DoNotOptimize(f.device->framebuffer().color().data());
    }
    state.SetItemsProcessed(state.iterations());
    state.counters["fps"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
    state.counters["paper_fps"] = blended ? 17.5 : 22.0;
    state.counters["texgen_ms"] = frames ? texgen / frames : 0.0;
    state.counters["passes"] = double(f.device->counters().passes);
}

const bool registered = [] {
    std::vector<int> threadCounts = {1};
    if (bench::allThreads() > 1) threadCounts.push_back(bench::allThreads());
    for (bool blended : {false, true})
        for (int t : threadCounts) {
            std::string name = std::string(blended ? "pem_viewer_off_manifold"
                                                   : "pem_viewer_on_manifold") +
                               "/retroglass/threads:" + std::to_string(t);
            benchmark::RegisterBenchmark(name.c_str(), [blended, t](benchmark::State& s) {
                viewerFrame(s, blended, t);
            })->Unit(benchmark::kMillisecond)->UseRealTime();
        }
    return true;
}();

}  // namespace
}  // namespace rg::pem
