// tir behind the shared interfaces (reproduction.h): the technique `retroglass compare`
// runs on any scene with a glass object, and the frames `retroglass bench` times.
#include <chrono>

#include "core/error.h"
#include "raycore/accel.h"
#include "raycore/tracer_refract_tir.h"

#include "figures.h"
#include "reproduce_tir.h"
#include "tir_demo.h"

namespace rg::tir {

namespace {

using Clock = std::chrono::steady_clock;

// No precompute (004: "requires no precomputation"): each view is four passes.
class TirTechnique final : public demos::Technique {
  public:
    TirTechnique(const ray::Scene& scene, const demos::PrepareOptions& options) : options_(options) {
        // The scene as a tir scene: its first glass object refracts.
        scene_.scene = scene;
        for (size_t i = 0; i < scene.objects.size(); ++i)
            if (scene.materials.at(scene.objects[i].material).type == ray::MaterialType::Glass) {
                scene_.refractor = uint32_t(i);
                break;
            }
        renderer_ = std::make_unique<TirRenderer>(scene_, options.threads);
    }
    std::vector<std::string> variants() const override { return {"tir_3_bounces", "tir_1_bounce", "wyman05"}; }
    std::string mainVariant() const override { return "tir_3_bounces"; }
    std::string object() const override { return scene_.scene.objects.at(scene_.refractor).name; }
    double precomputeSeconds() const override { return 0.0; }
    uint64_t textureBytes(const std::string&) const override { return renderer_->textureBytes(); }

    demos::RenderedView render(const std::string& variant, const ray::Camera& camera) override {
        TirSettings s;
        s.width = options_.width;
        s.height = options_.height;
        s.bounces = variant == "tir_1_bounce" ? 1 : 3;
        s.method = variant == "wyman05" ? Method::Wyman05 : Method::Ours;
        const TirFrame f = renderer_->render(camera, s);
        demos::RenderedView v;
        v.image = renderer_->frame();
        // Where the refractor was drawn: the reference's coverage decides the mask, so every
        // pixel counts as drawn.
        v.drawn = ray::Image(s.width, s.height, 1, 1.0f);
        v.frameMs = f.totalMs;
        v.passes = int(f.passes.size());
        v.counters = {{"refractive_fragments", f.refractiveFragments},
                      {"fetches_per_refractive_fragment", f.fetchesPerRefractiveFragment}};
        return v;
    }

    demos::GroundTruth groundTruth(const ray::Camera& camera) override {
        demos::GroundTruth g;
        Reference ref = traceReference(scene_, camera, options_.width, 2, 10, options_.threads);
        g.image = ref.color;
        g.coverage = ref.refractor;
        g.tracer = "raycore refraction-and-TIR tracer, depth 10, 2×2 samples";
        return g;
    }

  private:
    TirScene scene_;
    demos::PrepareOptions options_;
    std::unique_ptr<TirRenderer> renderer_;
};

demos::BenchCase frameCase(const std::string& scene, int size, int bounces, double paperFps) {
    demos::BenchCase c;
    c.name = "tir_" + scene + "_" + std::to_string(size) + "_b" + std::to_string(bounces);
    c.paper = {{"paper_fps", paperFps}};
    c.setup = [scene, size, bounces](int threads) {
        struct Fixture {
            TirScene scene;
            std::unique_ptr<TirRenderer> renderer;
            TirSettings settings;
        };
        auto f = std::make_shared<Fixture>();
        f->scene = makeTirScene(scene);
        f->renderer = std::make_unique<TirRenderer>(f->scene, threads);
        f->settings.width = f->settings.height = size;
        f->settings.bounces = bounces;
        f->renderer->render(f->scene.camera, f->settings);  // targets and the surroundings
        return std::function<std::map<std::string, double>()>([f] {
            const TirFrame fr = f->renderer->render(f->scene.camera, f->settings);
            std::map<std::string, double> m{{"fetches_per_fragment", fr.fetchesPerRefractiveFragment}};
            for (size_t i = 0; i < fr.passes.size(); ++i) m["pass" + std::to_string(i + 1) + "_ms"] = fr.passes[i].ms;
            return m;
        });
    };
    // The peer: raycore's refraction-and-TIR tracer on the same view, one ray per pixel,
    // the same bounce budget (the exact answer the image-space method approximates).
    c.peer = "raycore";
    c.setupPeer = [scene, size, bounces](int threads) {
        struct Fixture {
            TirScene scene;
            ray::Scene without;
            std::unique_ptr<ray::Accel> accel, accelWithout;
            ray::RenderOptions render;
            ray::TirPathOptions paths;
        };
        auto f = std::make_shared<Fixture>();
        f->scene = makeTirScene(scene);
        f->without = f->scene.scene;
        f->without.objects.erase(f->without.objects.begin() + f->scene.refractor);
        f->accel = std::make_unique<ray::Accel>(f->scene.scene);
        if (!f->without.objects.empty()) f->accelWithout = std::make_unique<ray::Accel>(f->without);
        f->render.width = f->render.height = size;
        f->render.threads = threads;
        f->paths.refractor = f->scene.refractor;
        f->paths.maxSegments = bounces;
        return std::function<std::map<std::string, double>()>([f] {
            const ray::TirImages im = ray::renderTirPaths(*f->accel, f->accelWithout.get(), f->scene.camera,
                                                          f->render, f->paths);
            return std::map<std::string, double>{{"checksum", double(im.color.pixels[0])}};
        });
    };
    return c;
}

}  // namespace

std::string TirReproduction::appliesTo(const ray::Scene& scene) const {
    for (const auto& o : scene.objects)
        if (scene.materials.at(o.material).type == ray::MaterialType::Glass) return o.name;
    return {};
}

std::unique_ptr<demos::Technique> TirReproduction::prepare(const ray::Scene& scene,
                                                           const std::vector<ray::Camera>&,
                                                           const demos::PrepareOptions& options) const {
    if (options.width != options.height)
        throw Error("tir: compare renders square views (the reference tracer's images are square); "
                    "give --width equal to --height");
    return std::make_unique<TirTechnique>(scene, options);
}

std::unique_ptr<viewer::Demo> TirReproduction::makeDemo(const viewer::DemoOptions& options) const {
    return std::make_unique<TirDemo>(options);
}

void TirReproduction::registerPrograms() const { registerTirPrograms(); }

std::vector<demos::BenchCase> TirReproduction::benchCases() const {
    // Table 1's kitchen row at 3 bounces, 512² and 1024² (paper: 92 and 51 FPS).
    return {frameCase("kitchen", 512, 3, 92.0), frameCase("kitchen", 1024, 3, 51.0)};
}

}  // namespace rg::tir
