// `retroglass view lightfield` (lightfield_demo.h).
#include "lightfield_demo.h"

#include "core/error.h"
#include "raycore/accel.h"
#include "reproduce_lightfield.h"

namespace rg::lightfield {

namespace {

enum ParamIndex { kRoute, kEnvironment, kVqMode, kVqRoute };

const BlockShape kShapes[3] = {{2, 2, 1, 1}, {1, 1, 2, 2}, {2, 2, 2, 2}};

}  // namespace

struct LightfieldDemo::PerProfile {
    std::shared_ptr<tex::TextureMemory> memory;
    std::unique_ptr<SliceTextures> slices;
    std::shared_ptr<tex::Texture> env[2];  // only where the profile has 3D textures
    std::map<int, std::unique_ptr<VqTextures>> vq;
    std::map<int, std::unique_ptr<VqTextures4D>> vq4d;
};

LightfieldDemo::LightfieldDemo(const viewer::DemoOptions& options) : scene_(makeScene(options.scene)), threads_(options.threads) {
    const LightfieldSettings s = lightfieldSettingsFor(demos::Quality::Quick);
    accel_ = std::make_unique<ray::Accel>(scene_.scene);
    geo_ = captureParaboloidField(*accel_, scene_.object, geometrySlab(s.geoS, s.geoU), scene_.mode, scene_.ior, threads_);
    const ray::Environment* envs[2] = {&scene_.envA, &scene_.envB};
    for (int k = 0; k < 2; ++k) {
        env_[k] = makeParaboloidMap(*envs[k], s.envSize, autoExposure(*envs[k]), 2);
        host_[k] = hostParaboloidMap(env_[k]);
        lookup_[k] = std::make_unique<SoftwareLookup>(host_[k], true);
    }
    params_ = {
        {"route", "lookup route", "§4: pixel texture on the Octane, or the O2's software lookup (any profile)",
         viewer::Param::Kind::Enum, 0, 0, 1, {"pixel texture", "software"}},
        {"environment", "environment", "the same light field lit by either map (no recompute)", viewer::Param::Kind::Enum, 0, 0, 1,
         {scene_.envAName, scene_.envBName}},
        {"vq_mode", "light field", "the geometry light field with a lookup, or a radiance light field vector-quantized (§5)",
         viewer::Param::Kind::Enum, 0, 0, 3, {"geometry + lookup", "VQ (s, t) halved", "VQ (u, v) halved", "VQ all halved"}},
        {"vq_route", "VQ route", "§5's two ways to draw the VQ light field: the Gortler polygons through colour tables with "
                                 "the alpha basis, or one polygon with 4D index and basis textures (SGIS_texture4D; the O2 refuses it)",
         viewer::Param::Kind::Enum, 0, 0, 1, {"colour tables + alpha basis", "4D textures"}},
    };
}

LightfieldDemo::~LightfieldDemo() = default;

std::string LightfieldDemo::title() const {
    return "Heidrich, Lensch, Cohen & Seidel, Light Field Techniques for Reflections and Refractions, EGWR 1999";
}

viewer::OrbitRig LightfieldDemo::rig() const {
    viewer::OrbitRig r;
    r.start = evalCamera(0);
    r.start.name = "start";
    r.minDistance = 6.5f;  // in front of the eye-point plane (z = 6)
    r.maxDistance = 20.0f;
    return r;
}

std::vector<viewer::ViewpointSample> LightfieldDemo::viewpointSamples() const {
    return {{"between eye points", evalCamera(0)}, {"off axis", evalCamera(1)}};
}

std::vector<std::string> LightfieldDemo::passDescriptions() const {
    return {"geometry light field: per eye point its hexagon of triangles, weights in the vertex colour, ONE/ONE (§3)",
            "read back: the colour-coded paraboloid coordinates (R, G = s, t; B = back map)",
            "lookup: pixel texture into the 256²×2 map, or in software and written back (§4)",
            "VQ: per eye point and parity the basis into alpha, then the index through its colour table (§5)",
            "VQ, 4D textures: per parity class the 2^4 basis texture into alpha, then the 4D index texture through its colour table, "
            "one window polygon each (§5 \"4D VQ\")"};
}

LightfieldDemo::PerProfile& LightfieldDemo::resources(const Profile& p) {
    auto& slot = perProfile_[p.id];
    if (!slot) {
        slot = std::make_unique<PerProfile>();
        slot->memory = std::make_shared<tex::TextureMemory>(p);
        if (p.has(Feature::Texture3D))
            for (int k = 0; k < 2; ++k) slot->env[k] = uploadParaboloidMap(*slot->memory, env_[k]);
    }
    return *slot;
}

const VqLightField& LightfieldDemo::vq(int mode) {
    auto it = vq_.find(mode);
    if (it != vq_.end()) return it->second;
    const LightfieldSettings s = lightfieldSettingsFor(demos::Quality::Quick);
    if (radiance_.data.empty())
        radiance_ = captureRadianceField(geometrySlab(s.radS, s.radU), [&](const ray::Ray& ry) {
            return sampleParaboloidMap(env_[0], traceExit(*accel_, scene_.object, ry, scene_.mode, scene_.ior).dir);
        }, threads_);
    VqOptions o;
    o.codebookSize = s.vqK;
    o.trainingBlocks = s.vqTraining;
    o.iterations = s.vqIterations;
    o.threads = threads_;
    return vq_.emplace(mode, quantize(radiance_, kShapes[mode - 1], o)).first->second;
}

viewer::FrameNotes LightfieldDemo::render(raster::Device& dev, const ray::Camera& camera) {
    const int route = int(viewer::paramValue(params_, "route"));
    const int envIndex = int(viewer::paramValue(params_, "environment"));
    const int mode = int(viewer::paramValue(params_, "vq_mode"));
    PerProfile& res = resources(dev.profile());
    dev.textureUnits().setTextureMemory(res.memory);
    const int w = dev.framebuffer().width(), h = dev.framebuffer().height();
    viewer::FrameNotes notes;
    dev.beginFrame();
    // One texture memory per machine, as on the hardware: the geometry slices and the VQ
    // index textures of a mode take turns in it.
    if (mode > 0) {
        const bool route4d = int(viewer::paramValue(params_, "vq_route")) == 1;
        res.slices.reset();
        for (auto& [m, t] : res.vq)
            if (m != mode || route4d) t.reset();
        for (auto& [m, t] : res.vq4d)
            if (m != mode || !route4d) t.reset();
        const VqLightField& q = vq(mode);
        VqStats st;
        if (route4d) {
            // Refused by a profile without SGIS_texture4D (rg::UnsupportedFeature names it),
            // never drawn through the 2D route instead.
            auto& tx = res.vq4d[mode];
            if (!tx) tx = std::make_unique<VqTextures4D>(res.memory, q);
            dev.beginPass("VQ passes, 4D textures");
            st = renderVq4D(dev, *tx, q, camera);
        } else {
            auto& tx = res.vq[mode];
            if (!tx) tx = std::make_unique<VqTextures>(res.memory, q);  // refuses K > the profile's tables
            dev.beginPass("VQ passes");
            st = renderVq(dev, *tx, q, camera);
        }
        dev.endFrame();
        notes.push_back({"codebook", std::to_string(q.K) + " entries, " + std::to_string(q.indexBytes()) + "-byte indices"});
        notes.push_back({"table loads", std::to_string(st.tableLoads)});
        notes.push_back({"colour / basis passes", std::to_string(st.colorPasses) + " / " + std::to_string(st.basisPasses)});
        return notes;
    }
    res.vq.clear();
    res.vq4d.clear();
    if (!res.slices) res.slices = std::make_unique<SliceTextures>(res.memory, geo_);
    dev.beginPass("geometry light field (Gortler)");
    const GortlerStats gs = renderGortler(dev, *res.slices, geo_, camera);
    const std::vector<Rgba8> coords = dev.readPixels(0, 0, w, h);
    if (route == 0) {
        // Pixel texture: refused by a profile without it (rg::UnsupportedFeature names it).
        if (!res.env[envIndex]) dev.profile().require(Feature::Texture3D, "the dual-paraboloid map of the pixel-texture route");
        dev.beginPass("pixel texture lookup");
        pixelTextureLookup(dev, res.env[envIndex], tex::PixelTexGenMode::Rgb, coords);
    } else {
        std::vector<Rgba8> px = coords;
        lookup_[envIndex]->apply(px, threads_);
        dev.beginPass("software lookup, written back");
        dev.drawPixels(0, 0, w, h, px);
    }
    dev.endFrame();
    notes.push_back({"eye points", std::to_string(gs.eyePoints)});
    notes.push_back({"slices", res.slices->resident() ? "resident" : "swapped (" + std::to_string(gs.uploadBytes) + " B / frame)"});
    notes.push_back({"read back", std::to_string(size_t(w) * h * 4) + " B"});
    return notes;
}

}  // namespace rg::lightfield
