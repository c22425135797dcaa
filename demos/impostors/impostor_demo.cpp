#include "impostor_demo.h"

#include <cstdio>

#include "rasterizer/device.h"

namespace rg::impostors {

namespace {

enum ParamIndex { kMode, kDepth, kIterations, kEnvSize, kMover, kExit, kCaustics };
const int kEnvSizes[4] = {64, 128, 256, 512};

std::vector<viewer::Param> impostorParams() {
    std::vector<viewer::Param> p(7);
    p[kMode] = {"mode", "mode",
                "§8: static (maps built once), classical (every map rebuilt every frame), separated (§5.2: only the "
                "mover's), refractor-maps-only (§4.2, mode A)",
                viewer::Param::Kind::Enum, 2, 0, 3, {"static", "classical", "separated", "refractor-maps-only"}};
    p[kDepth] = {"depth", "DEPTH", "§5.1: passes of the surrounding objects into every impostor", viewer::Param::Kind::Int,
                 2, 1, 4, {}};
    p[kIterations] = {"iterations", "secant iterations", "after the first guesses p and l (002 §3 gives none)",
                      viewer::Param::Kind::Int, 8, 0, 16, {}};
    p[kEnvSize] = {"env_size", "impostor size", "§8: 256² (and 512²)", viewer::Param::Kind::Enum, 1, 0, 3,
                   {"64", "128", "256", "512"}};
    p[kMover] = {"mover", "moving piece", "its place along its path (the white d-pawn: d2 → d4)", viewer::Param::Kind::Float,
                 0, 0, 1, {}};
    p[kExit] = {"exit", "refracted ray's exit",
                "§3: the refractor distance map from the piece's centre; §6: the refractor height map over its plane of "
                "symmetry, on a billboard",
                viewer::Param::Kind::Enum, 0, 0, 1, {"distance-map", "height-map"}};
    p[kCaustics] = {"caustics", "caustics",
                    "§7: photon maps of every piece from each light, splatted into the board's caustic light maps "
                    "(vertex texture fetch); off matches the Whitted reference, which has none",
                    viewer::Param::Kind::Enum, 0, 0, 1, {"off", "on"}};
    return p;
}

viewer::TargetImage crossImage(const ray::Image& im, const std::string& name, viewer::TargetImage::Kind kind) {
    viewer::TargetImage t;
    t.name = name;
    t.kind = kind;
    t.width = im.width;
    t.height = im.height;
    t.values.resize(size_t(im.width) * size_t(im.height));
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const glm::vec3 c = im.rgb(x, y);
            t.values[size_t(y) * size_t(im.width) + size_t(x)] =
                kind == viewer::TargetImage::Kind::Depth ? glm::vec4(c.x, 0.0f, 0.0f, 1.0f) : glm::vec4(c, 1.0f);
        }
    return t;
}

}  // namespace

ImpostorDemo::ImpostorDemo(const viewer::DemoOptions& options)
    : ProgrammableDemo(impostorParams()),
      scene_(options.scene.empty() ? makeChessScene() : impostorSceneFromFile(options.scene)) {
    for (const std::string& w : scene_.warnings) std::printf("view impostors: warning: %s\n", w.c_str());
    renderer_ = std::make_unique<ImpostorRenderer>(scene_, options.threads);
}

ImpostorDemo::~ImpostorDemo() = default;

std::string ImpostorDemo::title() const {
    return "Dancsik & Minarik, Real-time multi-bounce many-object ray tracing with distance-normal impostors";
}

viewer::OrbitRig ImpostorDemo::rig() const { return viewer::orbitAround(scene_.camera, 0.1f, 4.0f); }

std::vector<viewer::ViewpointSample> ImpostorDemo::viewpointSamples() const {
    return {{"the whole scene (Figure 10)", scene_.camera}, {"through the sphere (Figure 9)", scene_.closeUp}};
}

std::vector<std::string> ImpostorDemo::passDescriptions() const {
    return {"refractor distance maps: each mesh from its centre, normal + distance (RGBA16F cube, once)",
            "light maps (§7): shadow maps of the two lights, resolved into the board's texture space",
            "caustics (§7, when on): per piece and light a photon map from the light (refraction, the refractor-map "
            "exit, the board plane), splatted by vertex texture fetch into RGBA32F caustic light maps",
            "impostors (§5.1): board and sky, then DEPTH passes of the surrounding objects through their own "
            "impostors, six 90° faces each",
            "the mover's impostor (§5.2, separated mode): the static scene through the static impostors",
            "frame: board and sky, then every glass object: refraction through its refractor distance map (or, with "
            "the height-map exit, its refractor height map on a billboard, §6), both rays "
            "searched in its impostor (and the mover's refractor map from outside), Fresnel"};
}

ImpostorSettings ImpostorDemo::settings() const {
    ImpostorSettings s;
    s.width = frameSize().first;
    s.height = frameSize().second;
    s.mode = Mode(std::clamp(int(params_[kMode].value), 0, 3));
    s.depth = int(params_[kDepth].value);
    s.iterations = int(params_[kIterations].value);
    s.envSize = kEnvSizes[std::clamp(int(params_[kEnvSize].value), 0, 3)];
    s.refractorSize = 256;
    s.moverU = float(std::clamp(params_[kMover].value, 0.0, 1.0));
    s.exit = Exit(std::clamp(int(params_[kExit].value), 0, 1));
    s.caustics = int(params_[kCaustics].value) == 1;
    return s;
}

void ImpostorDemo::checkParams() const {
    ImpostorSettings s = settings();
    validate(s);
    if (s.mode == Mode::RefractorMapsOnly) {
        // Whether the scene has the board mode A walks (ImpostorRenderer's own test, which
        // raises the error naming it), on an 8² frame.
        s.width = s.height = 8;
        renderer_->render(scene_.camera, s);
    }
}

viewer::FrameNotes ImpostorDemo::render(raster::Device& device, const ray::Camera& camera) {
    requireProgrammable(device, "programmable shaders, float cube render targets");
    const ImpostorSettings s = settings();
    const ImpostorFrame f = renderer_->render(camera, s);
    handOver(device, renderer_->frameTexture(), s.width, s.height);
    passes_.clear();
    if (capture_) {
        using K = viewer::TargetImage::Kind;
        char state[160];
        std::snprintf(state, sizeof state, "geforce8800, %s, impostors %d² RGBA16F, DEPTH %d, %d iterations, exit %s",
                      modeName(s.mode), s.envSize, s.depth, s.iterations, exitName(s.exit));
        std::vector<viewer::TargetImage> maps;
        for (int m = 0; m < renderer_->refractorMaps(); ++m)
            maps.push_back(crossImage(renderer_->refractorImage(m),
                                      "refractor map: " + scene_.scene.meshes[renderer_->refractorMesh(m)].name, K::Color8));
        passes_.push_back({"refractor distance maps", state, maps});
        if (s.exit == Exit::HeightMap) {
            std::vector<viewer::TargetImage> heights;
            for (int m = 0; m < renderer_->refractorMaps(); ++m)
                heights.push_back(crossImage(renderer_->heightMapImage(m),
                                             "height map: " + scene_.scene.meshes[renderer_->refractorMesh(m)].name, K::Color8));
            passes_.push_back({"refractor height maps (§6)", state, heights});
        }
        passes_.push_back({"light maps", state, {crossImage(renderer_->lightMapImage(), "visibility (key, fill)", K::Color8)}});
        if (s.caustics) {
            std::vector<viewer::TargetImage> photons;
            photons.push_back(crossImage(renderer_->causticImage(), "caustic irradiance (static + mover)", K::Float));
            passes_.push_back({"caustics (§7)", state, photons});
        }
        if (s.mode != Mode::RefractorMapsOnly) {
            std::vector<viewer::TargetImage> env;
            const int mover = renderer_->moverIndex();
            if (mover >= 0) {
                env.push_back(crossImage(renderer_->impostorImage(mover, false), "the mover's impostor: radiance", K::Float));
                env.push_back(crossImage(renderer_->impostorImage(mover, true, 8.0f), "distance", K::Depth));
            }
            for (size_t i = 0; i < scene_.glass.size() && env.size() < 12; ++i)
                if (int(i) != mover)
                    env.push_back(crossImage(renderer_->impostorImage(int(i), false),
                                             scene_.scene.objects[scene_.glass[i]].name, K::Float));
            passes_.push_back({"environment impostors", state, env});
        }
        passes_.push_back({"frame", state, {crossImage(renderer_->frame(), "frame", K::Color8)}});
    }
    viewer::FrameNotes notes;
    for (const PassTiming& p : f.passes) viewer::addPassNote(notes, p.name, p.ms, p.counters.fragmentInvocations);
    char b[128];
    std::snprintf(b, sizeof b, "%lld, %.1f fetches each", (long long)f.glassFragments, f.fetchesPerGlassFragment);
    notes.push_back({"glass fragments", b});
    std::snprintf(b, sizeof b, "%d (%lld texels)", f.impostorsRebuilt, (long long)f.impostorTexels);
    notes.push_back({"impostors rebuilt", b});
    return notes;
}

}  // namespace rg::impostors
