// PEM behind the shared interfaces (reproduction.h): the technique `retroglass compare`
// runs on any scene with a mirror object, the viewer demo, and the viewer frame that
// `retroglass bench` times.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <optional>
#include <random>
#include <set>

#include "core/error.h"
#include "core/profile.h"
#include "core/progress.h"
#include "figures.h"
#include "pem_demo.h"
#include "pem_precompute.h"
#include "pem_renderer.h"
#include "raycore/accel.h"
#include "raycore/builtin_scenes.h"
#include "reproduce_pem.h"

namespace rg::pem {

namespace {

using Clock = std::chrono::steady_clock;

const std::vector<std::pair<std::string, EmMode>>& variantModes() {
    static const std::vector<std::pair<std::string, EmMode>> v = {
        {"layered_pem", EmMode::Layered},
        {"single_infinite_pem", EmMode::SingleInfinite},
        {"ptm", EmMode::Ptm},
        {"static_em", EmMode::Static}};
    return v;
}

EmMode modeOfVariant(const std::string& variant) {
    for (const auto& [name, mode] : variantModes())
        if (name == variant) return mode;
    throw Error("pem: unknown variant '" + variant + "'");
}

ray::ViewpointPath pathOf(const ray::Scene& scene) {
    int i = scene.findViewpointPath("circle");
    if (i < 0 && !scene.viewpointPaths.empty()) i = 0;
    if (i < 0)
        throw Error("pem: scene '" + scene.name + "' has no viewpoint path (the 1D viewspace "
                    "the PEMs are sampled along, docs/scene-format.md)");
    return scene.viewpointPaths[size_t(i)];
}

// PEMs inferred at the viewpoint samples of the scene's path that bracket the views asked
// for (the paper's 1D viewspace, at the path's own spacing), every frame blended from the
// two samples nearest its angle as the paper's viewer does (001 §5).
class PemTechnique final : public demos::Technique {
  public:
    PemTechnique(const ray::Scene& scene, const std::vector<ray::Camera>& views,
                 const demos::PrepareOptions& options)
        : settings_(settingsFor(options.quality)),
          ps_(makePemScene(scene, reflectorOptionsFor(scene))),
          path_(pathOf(ps_.scene)),
          accel_(ps_.scene),
          device_(profileByName("geforce256"), options.width, options.height,
                  raster::DepthFormat::D24, {Path::Fast, options.threads}),
          renderer_(device_, ps_) {
        settings_.width = options.width;
        settings_.height = options.height;
        settings_.threads = options.threads;
        const auto t0 = Clock::now();
        std::set<int> needed;
        for (const ray::Camera& cam : views) {
            SampleBlend sb = blendForAngle(path_, angleOnPath(path_, cam), true);
            needed.insert(sb.a);
            needed.insert(sb.b);
        }
        Progress progress("pem precompute", uint64_t(needed.size()));
        for (int v : needed) {
            samples_.emplace(v, precomputeView(accel_, renderer_, v, path_.at(uint32_t(v)),
                                               settings_.emSize, settings_, true));
            progress.advance();
        }
        static_ = traceStaticEm(accel_, ps_, settings_.emSize, settings_);
        precomputeSeconds_ = std::chrono::duration<double>(Clock::now() - t0).count();
    }

    std::vector<std::string> variants() const override {
        std::vector<std::string> v;
        for (const auto& [name, mode] : variantModes()) v.push_back(name);
        return v;
    }
    std::string mainVariant() const override { return "layered_pem"; }
    std::string object() const override { return ps_.scene.objects.at(size_t(ps_.object)).name; }
    double precomputeSeconds() const override { return precomputeSeconds_; }
    uint64_t textureBytes(const std::string& variant) const override {
        auto it = bytes_.find(variant);
        return it == bytes_.end() ? 0 : it->second;
    }

    demos::RenderedView render(const std::string& variant, const ray::Camera& camera) override {
        const EmMode mode = modeOfVariant(variant);
        SampleBlend sb = blendForAngle(path_, angleOnPath(path_, camera), true);
        auto t0 = Clock::now();
        uint64_t bytes = 0;
        auto count = [&](const PemSample& s) {
            for (const auto* list : {&s.local, &s.distant, &s.ptm})
                for (const auto& t : *list) bytes += t->bytes();
        };
        if (mode == EmMode::Static) {
            PemSample s;
            s.distant.push_back(uploadMap(renderer_, static_));
            count(s);
            t0 = Clock::now();
            renderer_.render(camera, mode, s);
        } else {
            PemSample a = uploadSample(renderer_, samples_.at(sb.a), mode);
            count(a);
            if (sb.b != sb.a) {
                PemSample b = uploadSample(renderer_, samples_.at(sb.b), mode);
                count(b);
                t0 = Clock::now();
                renderer_.render(camera, mode, a, &b, sb.w);
            } else {
                t0 = Clock::now();
                renderer_.render(camera, mode, a);
            }
        }
        demos::RenderedView out;
        out.frameMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        out.image = demos::framebufferImage(device_.framebuffer(), &out.drawn);
        const raster::Counters& c = device_.counters();
        out.passes = int(c.passes);
        out.counters = {{"passes", c.passes},
                        {"triangles_drawn", c.trianglesDrawn},
                        {"fragments_generated", c.fragmentsGenerated},
                        {"texel_fetches", c.texture.texelFetches}};
        bytes_[variant] = bytes;
        return out;
    }

    demos::GroundTruth groundTruth(const ray::Camera& camera) override {
        demos::GroundTruth g;
        groundTruthOf(traceLayers(accel_, ps_, camera, settings_), g.image, g.coverage);
        g.tracer = "raycore two-term segmented tracer, " + std::to_string(settings_.spp) + "×" +
                   std::to_string(settings_.spp) + " samples";
        return g;
    }

  private:
    PemSettings settings_;
    PemScene ps_;
    ray::ViewpointPath path_;
    ray::Accel accel_;
    raster::Device device_;
    PemRenderer renderer_;
    std::map<int, ViewSample> samples_;
    MapTexels static_;
    double precomputeSeconds_ = 0;
    std::map<std::string, uint64_t> bytes_;
};

// The viewer's frame at the paper's setting (001 §6): 640×480, ~40,000 triangles, 256²×6
// EMs with arbitrary texels (the frame's cost depends on sizes and sampling, not values).
struct ViewerFixture {
    PemScene scene;
    std::unique_ptr<raster::Device> device;
    std::unique_ptr<PemRenderer> renderer;
    PemSample a, b;
    ray::ViewpointPath path;
    int frames = 0;

    explicit ViewerFixture(int threads) {
        ray::BuiltinOptions bo;
        bo.teapotLevel = 25;  // 40,000 triangles
        scene = makePemScene(ray::makeBuiltinScene("teapot-in-room", bo), PemSceneOptions{});
        path = scene.scene.viewpointPaths.at(0);
        device = std::make_unique<raster::Device>(profileByName("geforce256"), 640, 480,
                                                  raster::DepthFormat::D24,
                                                  raster::DeviceOptions{Path::Fast, threads});
        renderer = std::make_unique<PemRenderer>(*device, scene);
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

demos::BenchCase viewerCase(bool blended) {
    demos::BenchCase c;
    c.name = blended ? "pem_viewer_off_manifold" : "pem_viewer_on_manifold";
    c.paper = {{"paper_fps", blended ? 17.5 : 22.0}};
    c.setup = [blended](int threads) {
        auto f = std::make_shared<ViewerFixture>(threads);
        return std::function<std::map<std::string, double>()>([f, blended] {
            // The eye alternates between two nearby viewpoints so that texture-coordinate
            // generation is redone every frame, as in the interactive viewer.
            ray::Camera cam = f->path.at(uint32_t(f->frames++ % 2));
            FrameTiming t = blended ? f->renderer->render(cam, EmMode::Layered, f->a, &f->b, 0.5f)
                                    : f->renderer->render(cam, EmMode::Layered, f->a);
            return std::map<std::string, double>{{"texgen_ms", t.texgenMs},
                                                 {"passes", double(f->device->counters().passes)}};
        });
    };
    return c;
}

// One viewpoint sample's precompute at the paper's settings (issue 21: ≤ 20 s on 2 cores):
// segmented ray tracing, the rendering matrices and the inference of every map of the PEM
// (the baselines' maps are made for two views only and are left out), at the EM resolution
// the reproduction chooses. The counters split it as the report does.
struct PrecomputeFixture {
    PemSettings settings = settingsFor(demos::Quality::Paper);
    PemScene scene;
    std::unique_ptr<ray::Accel> accel;
    std::unique_ptr<raster::Device> device;
    std::unique_ptr<PemRenderer> renderer;
    ray::ViewpointPath path;
    int emSize = 0, view = 0;

    explicit PrecomputeFixture(int threads) {
        settings.threads = threads;
        ray::BuiltinOptions bo;
        bo.teapotLevel = settings.teapotLevel;
        scene = makePemScene(ray::makeBuiltinScene("teapot-in-room", bo), PemSceneOptions{});
        path = scene.scene.viewpointPaths.at(0);
        path.count = uint32_t(settings.views);
        path.stepDegrees = settings.stepDegrees;
        accel = std::make_unique<ray::Accel>(scene.scene);
        device = std::make_unique<raster::Device>(
            profileByName("geforce256"), settings.width, settings.height, raster::DepthFormat::D24,
            raster::DeviceOptions{Path::Fast, threads});
        renderer = std::make_unique<PemRenderer>(*device, scene);
        emSize = emResolutionFor(*renderer, path.at(uint32_t(settings.views / 2 - 1)), settings);
    }
};

demos::BenchCase precomputeCase() {
    demos::BenchCase c;
    c.name = "pem_precompute_view_paper";
    c.unit = "views";
    c.paper = {{"paper_s_per_view", 15 * 60 + 5.5 * 60}};  // 001 §6: 15 min tracing, 5.5 inference
    c.setup = [](int threads) {
        auto f = std::make_shared<PrecomputeFixture>(threads);
        return std::function<std::map<std::string, double>()>([f] {
            const int v = f->view++ % f->settings.views;
            ViewSample s = precomputeView(*f->accel, *f->renderer, v, f->path.at(uint32_t(v)),
                                          f->emSize, f->settings, false);
            return std::map<std::string, double>{{"raytrace_s", s.raytraceSeconds},
                                                 {"inference_s", s.inferenceSeconds},
                                                 {"inference_cpu_s", s.inferenceCpuSeconds},
                                                 {"em_size", double(f->emSize)}};
        });
    };
    return c;
}

}  // namespace

std::string PemReproduction::appliesTo(const ray::Scene& scene) const {
    for (const auto& o : scene.objects)
        if (scene.materials.at(o.material).type == ray::MaterialType::Mirror) return o.name;
    return {};
}

std::unique_ptr<demos::Technique> PemReproduction::prepare(
    const ray::Scene& scene, const std::vector<ray::Camera>& views,
    const demos::PrepareOptions& options) const {
    return std::make_unique<PemTechnique>(scene, views, options);
}

std::unique_ptr<viewer::Demo> PemReproduction::makeDemo(const viewer::DemoOptions& options) const {
    return std::make_unique<PemDemo>(options);
}

std::vector<demos::BenchCase> PemReproduction::benchCases() const {
    return {viewerCase(false), viewerCase(true), precomputeCase()};
}

}  // namespace rg::pem
