#include "hybrid_demo.h"

#include <cstdio>

#include "core/error.h"
#include "core/profile.h"
#include "pem_demo.h"
#include "raycore/builtin_scenes.h"
#include "raycore/scene_json.h"
#include "rasterizer/device.h"
#include "reproduce_hybrid.h"

namespace rg::hybrid {

namespace {

enum ParamIndex { kTau, kLayers, kBlend, kPrevention, kLevels };

std::vector<viewer::Param> hybridParams() {
    std::vector<viewer::Param> p(5);
    p[kTau] = {"tau", "τ (subpixels)", "000 §5: subdivision stops below this screen edge length (paper: 3 and 5)",
               viewer::Param::Kind::Float, 5, 1, 16, {}};
    p[kLayers] = {"layers", "glass EM layers", "layers of a glass object's EM (000 §6: 3; a mirror gets min(2, this)); "
                  "a new count clusters and infers again",
                  viewer::Param::Kind::Int, 3, 1, 4, {}};
    p[kBlend] = {"blend", "blend two samples", "4n passes from the two nearest samples (off: the nearest, 2n)",
                 viewer::Param::Kind::Bool, 1, 0, 1, {}};
    p[kPrevention] = {"prevention", "disocclusion prevention", "EMs inferred with ray continuation over three "
                      "viewpoints around each sample (off: first hits, the sample alone)",
                      viewer::Param::Kind::Bool, 0, 0, 1, {}};
    p[kLevels] = {"levels", "show subdivision levels", "Figure 5: the adaptive mesh, darker with each level",
                  viewer::Param::Kind::Bool, 0, 0, 1, {}};
    return p;
}

}  // namespace

HybridDemo::HybridDemo(const viewer::DemoOptions& options, HybridDemoSettings settings)
    : settings_(settings), threads_(options.threads), params_(hybridParams()) {
    builtin_ = options.scene.empty();
    ray::BuiltinOptions bo;
    bo.teapotLevel = settings_.teapotLevel;
    ray::Scene scene = builtin_ ? ray::makeBuiltinScene("glass-teapot", bo) : ray::loadSceneByName(options.scene);
    int pi = scene.findViewpointPath("circle");
    if (pi < 0 && !scene.viewpointPaths.empty()) pi = 0;
    if (pi < 0) throw Error("view hybrid: the scene has no viewpoint path to sample the EMs along");
    path_ = scene.viewpointPaths[size_t(pi)];
    scene_ = std::make_unique<LensScene>(std::move(scene), LensSceneOptions{});
    for (const std::string& w : scene_->warnings()) std::printf("view hybrid: warning: %s\n", w.c_str());
    PrecomputeSettings pre;
    pre.clusterWidth = settings_.clusterWidth;
    pre.clusterHeight = settings_.clusterHeight;
    pre.threads = threads_;
    std::vector<ray::Camera> views;
    for (uint32_t v = 0; v < path_.count; ++v) views.push_back(path_.at(v));
    for (size_t i = 0; i < scene_->objects().size(); ++i) passes_.push_back(clusterPass(*scene_, i, views, pre));
    precomputeDevice_ = std::make_unique<raster::Device>(profileByName("geforce256"), settings_.width,
                                                         settings_.height, raster::DepthFormat::D24,
                                                         raster::DeviceOptions{Path::Fast, threads_});
    precomputeMemory_ = std::make_shared<tex::TextureMemory>(precomputeDevice_->profile());
}

HybridDemo::~HybridDemo() = default;

std::string HybridDemo::title() const { return hybridReproduction().paper(); }

viewer::OrbitRig HybridDemo::rig() const {
    viewer::OrbitRig r;
    r.start = path_.at(std::min<uint32_t>(40, path_.count - 1));
    r.start.name = "start";
    const float d = glm::length(r.start.eye - r.start.target);
    r.minDistance = 0.3f * d;
    r.maxDistance = 3.0f * d;
    return r;
}

std::vector<viewer::ViewpointSample> HybridDemo::viewpointSamples() const {
    std::vector<viewer::ViewpointSample> s;
    for (uint32_t v = 0; v < path_.count; ++v) s.push_back({"sample " + std::to_string(v), path_.at(v)});
    return s;
}

std::vector<std::string> HybridDemo::passDescriptions() const {
    return {"per lens object, term (reflection, then refraction) and viewpoint sample: its EM layers front to back, "
            "one per pass — stage 0 MODULATE(layer texel, F·G), stage 1 × the sample's weight, blended "
            "INVDESTALPHA/ONE over what the term has so far",
            "before each further (term, sample): the alpha-clear polygon, rgb × 1 and alpha × 0 (000 §5)",
            "traced every frame on the CPU: the vertices' greedy paths from this camera, the adaptive tessellation "
            "(τ), the texture coordinates where the exit rays meet each layer's shell"};
}

const std::vector<LensLayers>& HybridDemo::layersFor(int glassLayers) {
    auto it = layers_.find(glassLayers);
    if (it != layers_.end()) return it->second;
    std::vector<LensLayers> layers;
    const HybridSettings hs = settingsFor(demos::Quality::Quick);
    for (size_t i = 0; i < scene_->objects().size(); ++i) {
        const LensObject& L = scene_->objects()[i];
        const int k = L.twoTerms ? glassLayers : std::min(2, glassLayers);
        ShellChoice choice;
        if (builtin_ && L.name == "teapot" && k == 3) choice.kinds = hs.teapotShells;
        layers.push_back(buildLayers(*scene_, i, passes_[i], k, choice, settings_.emSize));
    }
    return layers_.emplace(glassLayers, std::move(layers)).first->second;
}

const SampleSolution& HybridDemo::solution(int glassLayers, bool prevention, int view) {
    const auto key = std::make_tuple(glassLayers, prevention, view);
    auto it = solutions_.find(key);
    if (it != solutions_.end()) return it->second;
    auto& r = precomputeRenderers_[glassLayers];
    if (!r)
        r = std::make_unique<HybridRenderer>(*precomputeDevice_, precomputeMemory_, *scene_,
                                             layersFor(glassLayers), 1, TessellationSettings{});
    PrecomputeSettings pre;
    pre.width = settings_.width;
    pre.height = settings_.height;
    pre.subsample = 1;
    pre.emSize = settings_.emSize;
    pre.threads = threads_;
    std::vector<ray::Camera> views{path_.at(uint32_t(view))};
    if (prevention)
        for (float off : {-0.5f, 0.5f})
            views.push_back(ray::cameraOnCircle(path_.center, path_.radius, path_.height,
                                                path_.startDegrees + (float(view) + off) * path_.stepDegrees,
                                                path_.fovYDegrees));
    std::printf("view hybrid: inferring the EMs of sample %d (%d glass layers%s)\n", view, glassLayers,
                prevention ? ", disocclusion prevention" : "");
    return solutions_.emplace(key, inferSample(*r, view, views, pre, {prevention, prevention})).first->second;
}

viewer::FrameNotes HybridDemo::render(raster::Device& device, const ray::Camera& camera) {
    const int layers = std::clamp(int(params_[kLayers].value), 1, 4);
    const bool prevention = params_[kPrevention].value != 0;
    if (&device != bound_ || layers != boundLayers_) {
        memory_ = std::make_shared<tex::TextureMemory>(device.profile());
        TessellationSettings ts;
        ts.threads = threads_;
        renderer_ = std::make_unique<HybridRenderer>(device, memory_, *scene_, layersFor(layers), 1, ts);
        bound_ = &device;
        boundLayers_ = layers;
        uploads_.clear();
    }
    const pem::SampleBlend sb = pem::blendForAngle(path_, pem::angleOnPath(path_, camera), params_[kBlend].value != 0);
    auto uploaded = [&](int view) -> const SampleMaps& {
        auto it = uploads_.find({prevention, view});
        if (it == uploads_.end())
            it = uploads_.emplace(std::make_pair(prevention, view),
                                  uploadSample(*renderer_, solution(layers, prevention, view))).first;
        return it->second;
    };
    const SampleMaps& a = uploaded(sb.a);
    const SampleMaps* b = sb.b != sb.a ? &uploaded(sb.b) : nullptr;
    renderer_->tessellation().tau = float(params_[kTau].value);
    FrameTimes t;
    if (params_[kLevels].value != 0) {
        renderer_->prepare(camera);
        renderer_->drawLevels();
    } else {
        t = renderer_->render(camera, a, b, sb.w);
    }
    const FrameCounts& n = renderer_->counts();
    viewer::FrameNotes notes;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%d and %d, weight %.2f", sb.a, sb.b, sb.w);
    notes.push_back({"samples", buf});
    std::snprintf(buf, sizeof buf, "%lld vertices, %llu rays, %lld triangles, level ≤ %d", (long long)n.verticesTraced,
                  (unsigned long long)n.rays.total(), (long long)n.trianglesOut, n.maxLevel);
    notes.push_back({"tessellation", buf});
    std::snprintf(buf, sizeof buf, "%d layer passes, %d alpha clears", n.layerPasses, n.alphaClears);
    notes.push_back({"passes", buf});
    std::snprintf(buf, sizeof buf, "rays %.1f ms, texgen %.1f ms, tessellation %.1f ms, draw %.1f ms", 1e3 * t.vertexRaysS,
                  1e3 * t.texgenS, 1e3 * t.tessellationS, 1e3 * t.drawS);
    notes.push_back({"times", buf});
    return notes;
}

}  // namespace rg::hybrid
