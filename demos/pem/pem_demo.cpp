// The PEM demo behind `retroglass view pem` (see pem_demo.h).
#include "pem_demo.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "pem_assets.h"
#include "raycore/accel.h"
#include "raycore/builtin_scenes.h"
#include "raycore/scene_json.h"
#include "reproduce_pem.h"

namespace fs = std::filesystem;

namespace rg::pem {

namespace {

// Parameter order is the panel's order; the record file names them.
enum ParamIndex { kEmMode = 0, kBlending = 1 };

std::vector<viewer::Param> pemParams() {
    std::vector<viewer::Param> p(2);
    p[kEmMode].name = "em";
    p[kEmMode].label = "environment maps";
    p[kEmMode].help = "layered PEM (local ellipsoid over distant box, the paper), one EM per "
                      "part at infinity (Figure 6 baseline), the static EM from the object's "
                      "centre (Figure 1c), or parameterized texture maps (Figure 7 baseline)";
    p[kEmMode].kind = viewer::Param::Kind::Enum;
    p[kEmMode].choices = {"layered", "single_infinite", "static", "ptm"};
    p[kEmMode].max = 3;
    p[kBlending].name = "blending";
    p[kBlending].label = "viewpoint blending";
    p[kBlending].help = "blend the two nearest viewpoint samples by angle (3 passes between "
                        "samples); off: the nearest sample alone (2 passes)";
    p[kBlending].kind = viewer::Param::Kind::Bool;
    p[kBlending].value = 1;
    return p;
}

EmMode modeOf(double v) {
    switch (int(v)) {
        case 1: return EmMode::SingleInfinite;
        case 2: return EmMode::Static;
        case 3: return EmMode::Ptm;
        default: return EmMode::Layered;
    }
}

std::optional<nlohmann::json> readManifest(const fs::path& assets) {
    std::ifstream f(assets / "manifest.json");
    if (!f) return std::nullopt;
    try {
        return nlohmann::json::parse(f);
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

}  // namespace

float angleOnPath(const ray::ViewpointPath& path, const ray::Camera& camera) {
    glm::vec3 d = camera.eye - path.center;
    float a = std::atan2(-d.z, d.x) * 180.0f / std::numbers::pi_v<float>;
    // The angle nearest the path's middle (the circle wraps at 360°).
    float mid = path.startDegrees + 0.5f * path.stepDegrees * float(path.count - 1);
    while (a - mid > 180.0f) a -= 360.0f;
    while (a - mid < -180.0f) a += 360.0f;
    return a;
}

SampleBlend blendForAngle(const ray::ViewpointPath& path, float angleDegrees, bool blending) {
    SampleBlend s;
    const int last = int(path.count) - 1;
    float t = path.stepDegrees != 0.0f ? (angleDegrees - path.startDegrees) / path.stepDegrees : 0.0f;
    t = std::clamp(t, 0.0f, float(std::max(0, last)));
    s.position = t;
    if (!blending) {
        s.a = s.b = int(std::lround(t));
        return s;
    }
    s.a = std::min(int(std::floor(t)), last);
    s.b = std::min(s.a + 1, last);
    s.w = s.b == s.a ? 0.0f : t - float(s.a);
    // The renderer's TFACTOR holds round(w·255): at 0 the frame is sample a alone, drawn
    // in the on-manifold 2 passes as the paper's viewer does on a sample.
    if (std::lround(s.w * 255.0f) == 0) s.b = s.a, s.w = 0.0f;
    if (std::lround(s.w * 255.0f) == 255) s.a = s.b, s.w = 0.0f;
    return s;
}

PemDemo::PemDemo(const viewer::DemoOptions& options) : params_(pemParams()) {
    const fs::path assets = options.outDir / "assets";
    const bool userScene = !options.scene.empty();
    ray::Scene probeScene = userScene ? ray::loadSceneByName(options.scene)
                                      : ray::makeBuiltinScene("teapot-in-room");
    auto manifest = readManifest(assets);
    auto usable = [&](const std::optional<nlohmann::json>& m) {
        return m && m->value("format", "") == "retroglass-pem" &&
               m->value("scene", "") == probeScene.name;
    };
    // ---- precompute when out/pem has no PEMs for this scene -------------------------------
    auto precompute = [&] {
        std::printf("view pem: no PEMs for scene '%s' in %s; running the quick precompute "
                    "(`retroglass reproduce pem`) first\n",
                    probeScene.name.c_str(), assets.string().c_str());
        std::fflush(stdout);
        demos::ReproduceOptions ro;
        ro.outDir = options.outDir;
        ro.threads = options.threads;
        ro.scene = options.scene;
        PemSettings quick;
        quick.threads = options.threads;
        runPem(quick, ro);
        manifest = readManifest(assets);
        if (!usable(manifest)) throw Error("PEM: the precompute left no usable " +
                                           (assets / "manifest.json").string());
    };
    if (!usable(manifest)) precompute();

    // ---- the scene and viewpoint path exactly as the precompute saw them --------------------
    auto load = [&] {
        const nlohmann::json& m = *manifest;
        ray::BuiltinOptions bo;
        bo.teapotLevel = m.value("teapot_level", 12);
        ray::Scene scene = userScene ? ray::loadSceneByName(options.scene)
                                     : ray::makeBuiltinScene("teapot-in-room", bo);
        int pathIndex = scene.findViewpointPath("circle");
        if (pathIndex < 0 && !scene.viewpointPaths.empty()) pathIndex = 0;
        if (pathIndex < 0) throw Error("PEM: the scene has no viewpoint path");
        path_ = scene.viewpointPaths[size_t(pathIndex)];
        path_.count = uint32_t(m.value("views", 8));
        path_.stepDegrees = m.value("step_degrees", 4.0f);
        PemSceneOptions pso = userScene ? reflectorOptionsFor(scene) : PemSceneOptions{};
        scene_ = std::make_unique<PemScene>(makePemScene(std::move(scene), pso));
        emSize_ = m.value("em_size", 64);
        const int ptmSize = m.value("ptm_size", 128);
        samples_.clear();
        for (int v = 0; v < int(path_.count); ++v) {
            auto s = loadView(assets, *scene_, v, emSize_, ptmSize);
            if (!s) return false;
            samples_.push_back(std::move(*s));
        }
        return true;
    };
    if (!load()) {
        // Views missing (a split precompute): the reproduction fills them in, reusing the
        // ones that are there.
        precompute();
        if (!load()) throw Error("PEM: views missing in " + assets.string() + " after the precompute");
    }
    std::printf("view pem: %zu viewpoint samples at %.1f° from %s, EMs %d²×6, %zu triangles\n",
                samples_.size(), path_.stepDegrees, assets.string().c_str(), emSize_,
                scene_->triangles);
}

PemDemo::~PemDemo() = default;

std::string PemDemo::title() const {
    return "Hakura, Snyder & Lengyel, Parameterized Environment Maps, I3D 2001";
}

viewer::OrbitRig PemDemo::rig() const {
    viewer::OrbitRig r;
    float mid = 0.5f * float(path_.count - 1);
    r.start = ray::cameraOnCircle(path_.center, path_.radius, path_.height,
                                  path_.startDegrees + path_.stepDegrees * std::floor(mid),
                                  path_.fovYDegrees);
    r.start.name = "start";
    float d = glm::length(r.start.eye - r.start.target);
    r.minDistance = 0.2f * d;
    r.maxDistance = 5.0f * d;
    return r;
}

std::vector<viewer::ViewpointSample> PemDemo::viewpointSamples() const {
    std::vector<viewer::ViewpointSample> v;
    for (uint32_t i = 0; i < path_.count; ++i) {
        ray::Camera c = path_.at(i);
        v.push_back({c.name, c});
    }
    return v;
}

std::vector<std::string> PemDemo::passDescriptions() const {
    return {"on a sample: pass 1 distant EM x Fresnel; pass 2 local EM x Fresnel over "
            "(SRCALPHA/INVSRCALPHA, off-hull triangles)",
            "between samples: pass 1 the two distant EMs blended by TFACTOR alpha; pass 2 the "
            "two local EMs blended, over; pass 3 Fresnel modulates the framebuffer "
            "(DESTCOLOR/ZERO)",
            "single EM, PTM and static EM draw pass 1 (and pass 3 between samples) only"};
}

const PemSample& PemDemo::uploaded(int view, EmMode mode) {
    auto key = std::make_pair(view, int(mode));
    auto it = uploads_.find(key);
    if (it != uploads_.end()) return it->second;
    PemSample s;
    if (mode == EmMode::Static) {
        if (!static_) {
            ray::Accel accel(scene_->scene);
            PemSettings S;
            static_ = traceStaticEm(accel, *scene_, emSize_, S);
        }
        s.distant.push_back(uploadMap(*renderer_, *static_));
    } else {
        s = uploadSample(*renderer_, samples_.at(size_t(view)), mode);
    }
    return uploads_.emplace(key, std::move(s)).first->second;
}

viewer::FrameNotes PemDemo::render(raster::Device& device, const ray::Camera& camera) {
    if (&device != bound_ || !renderer_) {
        uploads_.clear();
        renderer_ = std::make_unique<PemRenderer>(device, *scene_);
        bound_ = &device;
    }
    // The paper's viewer keeps the samples it draws in texture memory; we keep a few.
    if (uploads_.size() > 8) uploads_.clear();
    const EmMode mode = modeOf(params_[kEmMode].value);
    const bool blending = params_[kBlending].value != 0;
    const float angle = angleOnPath(path_, camera);
    SampleBlend sb = blendForAngle(path_, angle, blending);
    FrameTiming t;
    char buf[96];
    viewer::FrameNotes notes;
    notes.push_back({"em mode", emModeName(mode)});
    std::snprintf(buf, sizeof buf, "%.2f° (sample position %.3f)", angle, sb.position);
    notes.push_back({"angle on path", buf});
    if (mode == EmMode::SingleInfinite || mode == EmMode::Ptm) {
        // The reproduction infers the baselines' maps only at the samples it evaluates
        // (runPem); the frame uses the nearest samples that have them.
        auto nearestWith = [&](int v) {
            int best = -1;
            for (int i = 0; i < int(samples_.size()); ++i)
                if (samples_[size_t(i)].hasBaselines() && (best < 0 || std::abs(i - v) < std::abs(best - v)))
                    best = i;
            return best;
        };
        int a = nearestWith(sb.a), b = nearestWith(sb.b);
        if (a < 0) throw Error("PEM: no viewpoint sample has the single-EM/PTM baseline maps");
        if (a != sb.a || b != sb.b) {
            notes.push_back({"baselines", "maps only at samples with baselines; using " +
                                              std::to_string(a) + (b != a ? " and " + std::to_string(b) : "")});
            if (a == b) sb.b = sb.a = a, sb.w = 0;
            else sb.a = a, sb.b = b;
        }
    }
    if (mode == EmMode::Static) {
        t = renderer_->render(camera, mode, uploaded(-1, mode));
        notes.push_back({"samples", "static EM (no viewpoint samples)"});
    } else if (sb.b != sb.a) {
        const PemSample& a = uploaded(sb.a, mode);
        const PemSample& b = uploaded(sb.b, mode);
        t = renderer_->render(camera, mode, a, &b, sb.w);
        std::snprintf(buf, sizeof buf, "%d and %d, weight of %d = %.3f (TFACTOR %ld)", sb.a,
                      sb.b, sb.b, sb.w, std::lround(sb.w * 255.0f));
        notes.push_back({"samples", buf});
    } else {
        t = renderer_->render(camera, mode, uploaded(sb.a, mode));
        std::snprintf(buf, sizeof buf, "%d alone", sb.a);
        notes.push_back({"samples", buf});
    }
    std::snprintf(buf, sizeof buf, "%.2f ms", t.texgenMs);
    notes.push_back({"texgen (CPU, as in 001 §6)", buf});
    std::snprintf(buf, sizeof buf, "%.2f ms", t.drawMs);
    notes.push_back({"draw", buf});
    notes.push_back({"reflector passes", std::to_string(t.reflectorPasses)});
    return notes;
}

}  // namespace rg::pem
