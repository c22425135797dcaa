#include "tir_demo.h"

#include <cstdio>

#include "rasterizer/device.h"

namespace rg::tir {

namespace {

enum ParamIndex { kBounces, kItersFirst, kItersLater, kFrontAndBack, kMethod, kMapScale };

std::vector<viewer::Param> tirParams() {
    std::vector<viewer::Param> p(6);
    p[kBounces] = {"bounces", "internal bounces", "segments searched inside the refractor (Table 1: 1–4; 0: the front refraction only)",
                   viewer::Param::Kind::Int, 3, 0, double(kMaxBounces), {}};
    p[kItersFirst] = {"iterations_first", "search iterations, first ray", "004 §4: 8", viewer::Param::Kind::Int, 8, 1, 12, {}};
    p[kItersLater] = {"iterations_later", "search iterations, later rays", "004 §4: 5", viewer::Param::Kind::Int, 5, 1, 12, {}};
    p[kFrontAndBack] = {"front_and_back", "front and back faces", "also search the front faces' map (Figure 11)",
                        viewer::Param::Kind::Bool, 0, 0, 1, {}};
    p[kMethod] = {"method", "method", "ours (004) or image-space refraction (Wyman 2005, the baseline)",
                  viewer::Param::Kind::Enum, 0, 0, 1, {"ours", "wyman05"}};
    p[kMapScale] = {"map_scale", "intermediate maps", "the maps' size against the frame's (Figure 7)",
                    viewer::Param::Kind::Enum, 0, 0, 3, {"1", "1/2", "1/4", "1/8"}};
    return p;
}

TirScene sceneFor(const std::string& spec) {
    if (spec.empty()) return makeTirScene("kitchen");
    for (const std::string& n : tirSceneNames())
        if (n == spec) return makeTirScene(n);
    return tirSceneFromFile(spec);
}

// The texels of a render target as the inspector shows them.
viewer::TargetImage targetImage(const tex::Texture& t, const std::string& name, viewer::TargetImage::Kind kind,
                                int channel = -1) {
    viewer::TargetImage img;
    img.name = name;
    img.kind = kind;
    img.width = t.levelSize(0)[0];
    img.height = t.levelSize(0)[1];
    img.values.resize(size_t(img.width) * size_t(img.height));
    tex::Texture& m = const_cast<tex::Texture&>(t);
    for (size_t i = 0; i < img.values.size(); ++i) {
        glm::vec4 v;
        if (t.isFloat()) {
            v = m.renderDataF(0, 0)[i];
        } else {
            const Rgba8 c = m.renderData8(0, 0)[i];
            v = glm::vec4(c.r, c.g, c.b, c.a) / 255.0f;
        }
        // One channel shown alone (a map's depth in w): moved to x.
        img.values[i] = channel >= 0 ? glm::vec4(v[channel], 0.0f, 0.0f, 1.0f) : v;
    }
    return img;
}

}  // namespace

TirDemo::TirDemo(const viewer::DemoOptions& options)
    : ProgrammableDemo(tirParams()), scene_(sceneFor(options.scene)) {
    for (const std::string& w : scene_.warnings) std::printf("view tir: warning: %s\n", w.c_str());
    renderer_ = std::make_unique<TirRenderer>(scene_, options.threads);
}

TirDemo::~TirDemo() = default;

std::string TirDemo::title() const {
    return "Davis & Wyman, Interactive Refractions with Total Internal Reflection, GI 2007";
}

viewer::OrbitRig TirDemo::rig() const { return viewer::orbitAround(scene_.camera, 0.2f, 5.0f); }

std::vector<viewer::ViewpointSample> TirDemo::viewpointSamples() const { return {{"scene camera", scene_.camera}}; }

std::vector<std::string> TirDemo::passDescriptions() const {
    return {"pass 1: the refractor's back faces, eye normal and linear depth (RGBA16F)",
            "pass 2: its front faces, the same",
            "pass 3: the nearby geometry's colour and linear depth, the world behind",
            "pass 4: the background, then the refractor's front faces: refract, binary-search the "
            "back (and front) map per bounce, reflect on total internal reflection, exit through "
            "the nearby map or the environment"};
}

TirSettings TirDemo::settings() const {
    TirSettings s;
    s.width = frameSize().first;
    s.height = frameSize().second;
    s.bounces = int(params_[kBounces].value);
    s.itersFirst = int(params_[kItersFirst].value);
    s.itersLater = int(params_[kItersLater].value);
    s.frontAndBack = params_[kFrontAndBack].value != 0;
    s.method = params_[kMethod].value != 0 ? Method::Wyman05 : Method::Ours;
    static const float kScales[4] = {1.0f, 0.5f, 0.25f, 0.125f};
    s.mapScale = kScales[std::clamp(int(params_[kMapScale].value), 0, 3)];
    return s;
}

viewer::FrameNotes TirDemo::render(raster::Device& device, const ray::Camera& camera) {
    requireProgrammable(device, "programmable shaders, float render targets");
    const TirSettings s = settings();
    const TirFrame f = renderer_->render(camera, s);
    // The frame into the viewer's framebuffer, as it is.
    const tex::Texture& frame = renderer_->frameTexture();
    handOver(device, frame, s.width, s.height);
    passes_.clear();
    if (capture_) {
        using K = viewer::TargetImage::Kind;
        char state[160];
        std::snprintf(state, sizeof state, "geforce8800, maps %d×%d RGBA16F, bounces %d, iterations %d/%d, %s",
                      renderer_->backMap().levelSize(0)[0], renderer_->backMap().levelSize(0)[1], s.bounces,
                      s.itersFirst, s.itersLater, s.frontAndBack ? "front and back" : "back faces only");
        passes_.push_back({f.passes[0].name, state,
                           {targetImage(renderer_->backMap(), "normals", K::Normal),
                            targetImage(renderer_->backMap(), "linear depth", K::Depth, 3)}});
        passes_.push_back({f.passes[1].name, state,
                           {targetImage(renderer_->frontMap(), "normals", K::Normal),
                            targetImage(renderer_->frontMap(), "linear depth", K::Depth, 3)}});
        passes_.push_back({f.passes[2].name, state,
                           {targetImage(renderer_->nearbyMap(), "colour", K::Float),
                            targetImage(renderer_->nearbyMap(), "linear depth", K::Depth, 3)}});
        passes_.push_back({f.passes[3].name, state, {targetImage(frame, "frame", K::Color8)}});
    }
    viewer::FrameNotes notes;
    for (const PassTiming& p : f.passes) viewer::addPassNote(notes, p.name, p.ms, p.counters.fragmentInvocations);
    char b[128];
    std::snprintf(b, sizeof b, "%lld, %.1f fetches each", (long long)f.refractiveFragments, f.fetchesPerRefractiveFragment);
    notes.push_back({"refractive fragments", b});
    return notes;
}

}  // namespace rg::tir
