// impostors behind the shared interfaces (reproduction.h): the technique `retroglass compare`
// runs on any scene with glass or mirror objects, and the frames `retroglass bench` times.
#include <chrono>

#include "core/error.h"
#include "raycore/accel.h"
#include "raycore/render.h"
#include "raycore/tracer_whitted.h"

#include "reproduce_impostors.h"

namespace rg::impostors {

namespace {

// Every glass and mirror object of the scene gets impostors; nothing moves (the static
// mode: the maps are the precompute, built at the first view).
class ImpostorTechnique final : public demos::Technique {
  public:
    ImpostorTechnique(const ray::Scene& scene, const demos::PrepareOptions& options) : options_(options) {
        scene_.scene = scene;
        indexGlass(scene_);
        if (scene_.glass.empty()) throw Error("impostors: scene '" + scene.name + "' has no glass or mirror object");
        renderer_ = std::make_unique<ImpostorRenderer>(scene_, options.threads);
        settings_.width = options.width;
        settings_.height = options.height;
        if (options.quality == demos::Quality::Quick) settings_.envSize = settings_.refractorSize = 128;
        settings_.mode = Mode::Static;
    }
    std::vector<std::string> variants() const override { return {"impostors_depth2", "impostors_depth1"}; }
    std::string mainVariant() const override { return "impostors_depth2"; }
    std::string object() const override { return scene_.scene.objects.at(scene_.glass.front()).name; }
    double precomputeSeconds() const override { return precomputeSeconds_; }
    uint64_t textureBytes(const std::string&) const override { return renderer_->textureBytes(); }

    demos::RenderedView render(const std::string& variant, const ray::Camera& camera) override {
        ImpostorSettings s = settings_;
        s.depth = variant == "impostors_depth1" ? 1 : 2;
        const auto t0 = std::chrono::steady_clock::now();
        ImpostorFrame f = renderer_->render(camera, s);
        if (f.impostorsRebuilt > 0) {
            // The maps are the precompute: time a second frame.
            precomputeSeconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            f = renderer_->render(camera, s);
        }
        demos::RenderedView v;
        v.image = renderer_->frame();
        v.drawn = ray::Image(s.width, s.height, 1, 1.0f);
        v.frameMs = f.totalMs;
        v.passes = int(f.passes.size());
        v.counters = {{"glass_fragments", f.glassFragments}, {"fetches_per_glass_fragment", f.fetchesPerGlassFragment}};
        return v;
    }

    demos::GroundTruth groundTruth(const ray::Camera& camera) override {
        ray::Accel accel(scene_.scene);
        ray::RenderOptions ro;
        ro.width = options_.width;
        ro.height = options_.height;
        ro.maxDepth = kReferenceDepth;  // the reproduction's reference
        ro.threads = options_.threads;
        demos::GroundTruth g;
        g.image = ray::renderWhitted(accel, camera, ro);
        g.coverage = ray::Image(ro.width, ro.height, 1);
        for (int y = 0; y < ro.height; ++y)
            for (int x = 0; x < ro.width; ++x) {
                const ray::Hit h = accel.intersect(ray::primaryRay(camera, ro.width, ro.height, float(x) + 0.5f, float(y) + 0.5f));
                g.coverage.at(x, y, 0) = h.valid() && std::find(scene_.glass.begin(), scene_.glass.end(), h.object) != scene_.glass.end();
            }
        g.tracer = "raycore Whitted, depth " + std::to_string(ro.maxDepth) + ", 1 sample at the pixel centre";
        return g;
    }

  private:
    ImpostorScene scene_;
    demos::PrepareOptions options_;
    ImpostorSettings settings_;
    std::unique_ptr<ImpostorRenderer> renderer_;
    double precomputeSeconds_ = 0;
};

// A §8 frame at 600² in one mode, with raycore's Whitted tracer on the same view as the peer.
demos::BenchCase frameCase(Mode mode, int envSize, double paperFps) {
    demos::BenchCase c;
    c.name = std::string("impostors_") + modeName(mode) + "_600_env" + std::to_string(envSize);
    c.paper = {{"paper_fps", paperFps}};
    c.setup = [mode, envSize](int threads) {
        struct Fixture {
            ImpostorScene scene;
            std::unique_ptr<ImpostorRenderer> renderer;
            ImpostorSettings settings;
            int frame = 0;
        };
        auto f = std::make_shared<Fixture>();
        f->scene = makeChessScene();
        f->renderer = std::make_unique<ImpostorRenderer>(f->scene, threads);
        f->settings.mode = mode;
        f->settings.envSize = envSize;
        f->renderer->render(f->scene.camera, f->settings);  // the maps built once
        return std::function<std::map<std::string, double>()>([f] {
            // The mover moves every frame (static: it stays).
            f->settings.moverU = f->settings.mode == Mode::Static ? 0.0f : float(++f->frame % 16) / 16.0f;
            const ImpostorFrame fr = f->renderer->render(f->scene.camera, f->settings);
            std::map<std::string, double> m{{"fetches_per_glass_fragment", fr.fetchesPerGlassFragment},
                                            {"maps_ms", fr.mapsMs},
                                            {"glass_fragments", double(fr.glassFragments)}};
            // The frame's two passes, so that the bench shows where a frame's time goes.
            for (const PassTiming& p : fr.passes) {
                if (p.name.rfind("frame: board", 0) == 0) m["board_sky_ms"] = p.ms;
                if (p.name.rfind("frame: glass", 0) == 0) m["glass_ms"] = p.ms;
            }
            return m;
        });
    };
    // The peer: raycore's Whitted tracer (Embree) on the same view, one ray per pixel, depth 8.
    c.peer = "raycore";
    c.setupPeer = [](int threads) {
        struct Fixture {
            ImpostorScene scene;
            std::unique_ptr<ray::Accel> accel;
            ray::RenderOptions render;
        };
        auto f = std::make_shared<Fixture>();
        f->scene = makeChessScene();
        f->accel = std::make_unique<ray::Accel>(f->scene.scene);
        f->render.width = f->render.height = 600;
        f->render.maxDepth = 8;
        f->render.threads = threads;
        return std::function<std::map<std::string, double>()>([f] {
            const ray::Image im = ray::renderWhitted(*f->accel, f->scene.camera, f->render);
            return std::map<std::string, double>{{"checksum", double(im.pixels[0])}};
        });
    };
    return c;
}

}  // namespace

std::unique_ptr<demos::Technique> makeImpostorTechnique(const ray::Scene& scene, const demos::PrepareOptions& options) {
    return std::make_unique<ImpostorTechnique>(scene, options);
}

std::vector<demos::BenchCase> impostorBenchCases() {
    // §8: static 75 FPS, separated 11.3 FPS (256² maps).
    return {frameCase(Mode::Static, 256, 75.0), frameCase(Mode::Separated, 256, 11.3)};
}

}  // namespace rg::impostors
