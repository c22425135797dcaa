// The hybrid reproduction: layers clustered over every viewpoint, EMs inferred at the
// evaluated samples (with and without disocclusion prevention, and the single-layer
// baseline), hybrid frames on the emulated GeForce 256 against the ray tracer, the §6
// table against a uniform ray tracer on the same rays, the figures, report.md and
// results.json with the paper's claims.
#include "reproduce_hybrid.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numeric>
#include <sstream>

#include <tbb/parallel_for.h>

#include "core/error.h"
#include "core/profile.h"
#include "core/progress.h"
#include "figures.h"
#include "rasterizer/trace.h"
#include "raycore/builtin_scenes.h"
#include "raycore/metrics.h"
#include "raycore/scene_json.h"
#include "raycore/shapes.h"
#include "raycore/tracer_two_term.h"
#include "raycore/tracer_whitted.h"
#include "report.h"

namespace fs = std::filesystem;

namespace rg::hybrid {

HybridSettings settingsFor(demos::Quality q) {
    HybridSettings s;
    if (q == demos::Quality::Paper) {
        // 000 §6: 640×480 with 3×3 subsamples, τ = 3 and 5, viewpoints every 8° around the
        // teapot, ~40k triangles; the EM resolution is ours (the paper gives none).
        s.pre.width = 640;
        s.pre.height = 480;
        s.pre.subsample = 3;
        s.pre.clusterWidth = 160;
        s.pre.clusterHeight = 120;
        s.pre.emSize = 128;
        s.teapotLevel = 25;
        s.tableFrames = 5;
        s.neighbourViews = 5;
    }
    return s;
}

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}
double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// The ray tracer's view: 000 §3's greedy two-term model over the whole scene (the exit
// radiance Whitted-traced on), n×n rays per pixel.
struct Reference {
    ray::Image image, lens, confidence;  // sum; lens coverage; min of the terms' confidence
    ray::RayCounts rays;
    double seconds = 0;
    uint64_t triangleTests = 0;
};
Reference traceReference(const ray::Accel& accel, const ray::Camera& cam, const HybridSettings& S) {
    Reference r;
    ray::RenderOptions o;
    o.width = S.pre.width;
    o.height = S.pre.height;
    o.spp = S.pre.subsample;
    o.maxDepth = S.pre.maxDepth;
    o.threads = S.threads;
    ray::RenderCounters rc;
    o.counters = &rc;
    accel.resetTriangleTests();
    auto t0 = Clock::now();
    ray::TwoTermImages t = ray::renderTwoTerm(accel, cam, o);
    r.seconds = since(t0);
    r.triangleTests = accel.triangleTests();
    r.image = std::move(t.sum);
    r.lens = std::move(t.lensCoverage);
    r.confidence = ray::Image(o.width, o.height, 1);
    for (size_t i = 0; i < r.confidence.pixels.size(); ++i)
        r.confidence.pixels[i] =
            std::min(t.reflectConfidence.pixels[i], t.refractConfidence.pixels[i]);
    for (size_t k = 0; k < r.rays.n.size(); ++k) r.rays.n[k] = rc.count(ray::RayKind(k));
    return r;
}

struct Frame {
    ray::Image image, coverage;
    FrameTimes times;
    FrameCounts counts;
    int devicePasses = 0;
    uint64_t textureBytes = 0;
};
Frame renderFrame(HybridRenderer& r, const ray::Camera& cam, const SampleMaps& a,
                  const SampleMaps* b, float wB) {
    Frame f;
    f.times = r.render(cam, a, b, wB);
    f.image = r.displayImage(&f.coverage);
    f.counts = r.counts();
    f.devicePasses = int(r.device().counters().passes);
    return f;
}

// Lens pixels: every ray of the ray tracer and every subpixel of the frame on a lens
// object (the metric mask, as pem's).
ray::Image lensMask(const Reference& ref, const Frame& f) {
    ray::Image m(ref.lens.width, ref.lens.height, 1);
    for (size_t i = 0; i < m.pixels.size(); ++i)
        m.pixels[i] = ref.lens.pixels[i] >= 0.999f && f.coverage.pixels[i] >= 0.999f ? 1.0f : 0.0f;
    return m;
}

// The frame where it drew, the ray tracer's image elsewhere (for the figures).
ray::Image composite(const Frame& f, const Reference& ref) {
    ray::Image out = f.image;
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const float c = f.coverage.at(x, y, 0);
            out.setRgb(x, y, f.image.rgb(x, y) +
                                 (1.0f - c) * glm::min(ref.image.rgb(x, y), glm::vec3(1.0f)));
        }
    return out;
}

// Lens pixels near a silhouette (within 2 pixels of a pixel the frame or the ray tracer
// does not fully cover) or where the ray tracer's paths diverge inside the pixel (000
// §4.3's confidence below ½, i.e. exit directions more than 3.5° apart: the bottom of the
// teapot, where the spout joins the body): the band where 000 §6 sees τ = 5's extra noise.
ray::Image edgeBand(const ray::Image& mask, const Reference& ref) {
    ray::Image band(mask.width, mask.height, 1);
    for (int y = 0; y < mask.height; ++y)
        for (int x = 0; x < mask.width; ++x) {
            if (mask.at(x, y, 0) < 0.5f) continue;
            bool edge = ref.confidence.at(x, y, 0) < 0.5f;
            for (int dy = -2; dy <= 2 && !edge; ++dy)
                for (int dx = -2; dx <= 2 && !edge; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    edge = xx < 0 || yy < 0 || xx >= mask.width || yy >= mask.height ||
                           mask.at(xx, yy, 0) < 0.5f;
                }
            band.at(x, y, 0) = edge ? 1.0f : 0.0f;
        }
    return band;
}

double meanAbsError(const ray::Image& truth, const ray::Image& img, const ray::Image& mask) {
    double sum = 0;
    int64_t n = 0;
    for (int y = 0; y < mask.height; ++y)
        for (int x = 0; x < mask.width; ++x) {
            if (mask.at(x, y, 0) < 0.5f) continue;
            const glm::vec3 d = glm::abs(glm::min(truth.rgb(x, y), glm::vec3(1.0f)) - img.rgb(x, y));
            sum += (d.x + d.y + d.z) / 3.0;
            ++n;
        }
    return n ? sum / double(n) : std::numeric_limits<double>::quiet_NaN();
}

double meanAbsDifference(const ray::Image& a, const ray::Image& b, const ray::Image& mask) {
    return meanAbsError(a, b, mask);
}

ray::Image maskAnd(const ray::Image& a, const ray::Image& b) {
    ray::Image m = a;
    for (size_t i = 0; i < m.pixels.size(); ++i) m.pixels[i] = a.pixels[i] > 0.5f && b.pixels[i] > 0.5f;
    return m;
}

// A layer map's finest level as an image: cube faces side by side (+X −X +Y −Y +Z −Z),
// or the quad's 2D texture; premultiplied rgb shown over black.
ray::Image mapImage(const LayerMap& map) {
    const pem::TexelLayout& L = map.layout;
    ray::Image out(L.baseSize * L.faces + 2 * (L.faces - 1), L.baseSize, 3, 1.0f);
    for (int f = 0; f < L.faces; ++f)
        for (int y = 0; y < L.baseSize; ++y)
            for (int x = 0; x < L.baseSize; ++x) {
                const Rgba8 t = map.texels[size_t(L.index(0, f, x, y))];
                out.setRgb(f * (L.baseSize + 2) + x, y, glm::vec3(t.r, t.g, t.b) / 255.0f);
            }
    return out;
}

ray::Image rgbOf(const ray::Image& rgba) {
    ray::Image out(rgba.width, rgba.height, 3);
    for (int y = 0; y < rgba.height; ++y)
        for (int x = 0; x < rgba.width; ++x)
            out.setRgb(x, y, {rgba.at(x, y, 0), rgba.at(x, y, 1), rgba.at(x, y, 2)});
    return out;
}

nlohmann::json raysJson(const ray::RayCounts& c) {
    nlohmann::json j;
    for (size_t k = 0; k < c.n.size(); ++k) j[ray::rayKindName(ray::RayKind(k))] = c.n[k];
    j["total"] = c.total();
    return j;
}

// An integer with thousands separators, as the paper's table prints its counts.
std::string count(double v) {
    const auto n = int64_t(std::llround(v));
    std::string s = std::to_string(n), out;
    for (size_t i = 0; i < s.size(); ++i) {
        if (i && (s.size() - i) % 3 == 0) out += ',';
        out += s[i];
    }
    return out;
}

}  // namespace

nlohmann::json runHybrid(HybridSettings S, const demos::ReproduceOptions& options) {
    const auto tStart = Clock::now();
    // ---- bad input first: nothing written half-way ---------------------------------------
    if (!(S.pre.tau > 0.0f) || !(S.tauFast > 0.0f))
        throw Error("hybrid: τ must be > 0 (got " + std::to_string(S.pre.tau) + " and " +
                    std::to_string(S.tauFast) + " subpixels)");
    if (S.glassLayers < 1 || S.mirrorLayers < 1)
        throw Error("hybrid: a layer count of 0: every lens object needs at least one EM layer");
    if (S.pre.subsample < 1 || S.pre.width < 8 || S.pre.height < 8)
        throw Error("hybrid: the image must be at least 8×8 with at least one subsample");
    const Profile& profile = profileByName("geforce256");
    ray::BuiltinOptions bo;
    bo.teapotLevel = S.teapotLevel;
    ray::Scene scene = options.scene.empty() ? ray::makeBuiltinScene("glass-teapot", bo)
                                             : ray::loadSceneByName(options.scene);
    const bool builtin = options.scene.empty();
    int pathIndex = scene.findViewpointPath("circle");
    if (pathIndex < 0 && !scene.viewpointPaths.empty()) pathIndex = 0;
    if (pathIndex < 0)
        throw Error("hybrid: scene '" + scene.name + "' has no viewpoint path to sample the EMs "
                    "along (docs/scene-format.md)");
    ray::ViewpointPath path = scene.viewpointPaths[size_t(pathIndex)];
    if (builtin) {
        path.count = uint32_t(S.views);
        path.stepDegrees = S.stepDegrees;
    } else {
        S.views = int(path.count);
        S.stepDegrees = path.stepDegrees;
        S.sample = std::clamp(S.sample, 0, std::max(0, S.views - 2));
    }
    if (S.views < 2) throw Error("hybrid: at least two viewpoint samples are needed");
    LensSceneOptions lso;
    lso.glassLayers = S.glassLayers;
    lso.mirrorLayers = S.mirrorLayers;
    LensScene lens(std::move(scene), lso);
    for (const std::string& w : lens.warnings()) std::printf("warning: %s\n", w.c_str());
    const size_t lensCount = lens.objects().size();
    const int coordSets = profile.maxTexCoordSets;
    for (const LensObject& L : lens.objects())
        if ((L.twoTerms ? 2 : 1) * L.layers > coordSets)
            throw Error("hybrid: lens object '" + L.name + "': " + std::to_string(L.layers) +
                        " layers need " + std::to_string((L.twoTerms ? 2 : 1) * L.layers) +
                        " texture-coordinate sets per vertex (terms × layers); the " +
                        std::string(profile.name) + " has " + std::to_string(coordSets));
    {
        // Two samples' maps must be resident at once (blending between samples).
        std::vector<LensLayers> budget;
        for (const LensObject& L : lens.objects()) {
            LensLayers ll;
            ll.emSize = S.pre.emSize;
            for (int l = 0; l < L.layers; ++l) ll.shells.push_back(sphereShell({}, 1));
            budget.push_back(ll);
        }
        const uint64_t bytes = 2 * HybridRenderer::sampleBytes(budget) * 4 / 3 + 1;
        if (bytes > profile.textureMemoryBytes)
            throw Error("hybrid: " + std::to_string(S.glassLayers) + " glass and " +
                        std::to_string(S.mirrorLayers) + " mirror layers of " +
                        std::to_string(S.pre.emSize) + "² cube maps for two viewpoint samples "
                        "need " + std::to_string(bytes >> 20) + " MiB; the " +
                        std::string(profile.name) + " has " +
                        std::to_string(profile.textureMemoryBytes >> 20) + " MiB of texture memory");
    }
    S.pre.threads = S.threads;
    const fs::path out = options.outDir;
    fs::create_directories(out);
    const int W = S.pre.width, H = S.pre.height, n = S.pre.subsample;
    auto angleOf = [&](int view) { return path.startDegrees + float(view) * S.stepDegrees; };
    auto cameraAt = [&](float angle, float height) {
        return ray::cameraOnCircle(path.center, path.radius, height, angle, path.fovYDegrees);
    };
    const int k = std::clamp(S.sample, 0, S.views - 2);
    std::printf("hybrid: scene '%s', %zu lens objects, %d viewpoints at %.1f°, %dx%d with %dx%d "
                "subsamples, EM %d², profile %s\n",
                lens.scene().name.c_str(), lensCount, S.views, S.stepDegrees, W, H, n, n,
                S.pre.emSize, std::string(profile.name).c_str());

    // ---- 000 §4.2: layers over every viewpoint at once --------------------------------------
    auto t0 = Clock::now();
    std::vector<ray::Camera> allViews;
    for (int v = 0; v < S.views; ++v) allViews.push_back(path.at(uint32_t(v)));
    std::vector<LensLayers> multi, single;
    nlohmann::json clusteringJson = nlohmann::json::object();
    for (size_t i = 0; i < lensCount; ++i) {
        const LensObject& L = lens.objects()[i];
        ClusterPass pass = clusterPass(lens, i, allViews, S.pre);
        ShellChoice choice;
        if (builtin && L.name == "teapot") choice.kinds = S.teapotShells;
        multi.push_back(buildLayers(lens, i, pass, L.layers, choice, S.pre.emSize));
        single.push_back(buildLayers(lens, i, pass, 1, {}, S.pre.emSize));
        nlohmann::json layers = nlohmann::json::array();
        for (size_t l = 0; l < multi.back().assignment.layers.size(); ++l) {
            const LayerInfo& info = multi.back().assignment.layers[l];
            nlohmann::json objs = nlohmann::json::array();
            for (uint32_t o : info.objects) objs.push_back(lens.scene().objects[o].name);
            layers.push_back({{"radius", info.radius},
                              {"lbg_center", info.lbgCenter},
                              {"shell", multi.back().shells[l].describe()},
                              {"objects", objs},
                              {"records", info.records},
                              {"frontmost", info.frontmost},
                              {"distance_range", {info.minDistance, info.maxDistance}}});
        }
        clusteringJson[L.name] = {{"requested_layers", L.layers},
                                  {"layers", layers},
                                  {"lbg_iterations", multi.back().assignment.iterations},
                                  {"records", pass.records.size()},
                                  {"single_layer_radius", single.back().assignment.layers.at(0).radius},
                                  {"origin", {L.origin.x, L.origin.y, L.origin.z}}};
        std::printf("hybrid: %s: %zu layers:", L.name.c_str(), multi.back().shells.size());
        for (size_t l = 0; l < multi.back().shells.size(); ++l) {
            std::printf(" [%s:", multi.back().shells[l].describe().c_str());
            for (uint32_t o : multi.back().assignment.layers[l].objects)
                std::printf(" %s", lens.scene().objects[o].name.c_str());
            std::printf("]");
        }
        std::printf("\n");
    }
    const double clusterS = since(t0);

    // ---- the device and the renderers --------------------------------------------------------
    const Path rasterPath = options.referencePath ? Path::Reference : Path::Fast;
    raster::Device device(profile, W * n, H * n, raster::DepthFormat::D24, {rasterPath, S.threads});
    auto memory = std::make_shared<tex::TextureMemory>(profile);
    TessellationSettings ts;
    ts.tau = S.pre.tau;
    ts.maxDepth = S.pre.maxDepth;
    ts.threads = S.threads;
    HybridRenderer multiR(device, memory, lens, multi, n, ts);
    HybridRenderer singleR(device, memory, lens, single, n, ts);

    // ---- 000 §4.3: the EMs of samples k and k + 1 ----------------------------------------------
    auto neighbourhood = [&](int view, bool prevention) {
        std::vector<ray::Camera> cams{path.at(uint32_t(view))};
        if (!prevention) return cams;
        const int m = std::max(1, S.neighbourViews);
        for (int j = 1; j < m; ++j) {
            // Evenly over the span, the sample itself first: ±span/2, ±span/4, ...
            const int step = (j + 1) / 2;
            const float off = (j % 2 ? -1.0f : 1.0f) * S.neighbourSpanDegrees * 0.5f * float(step) /
                              float((m - 1 + 1) / 2);
            cams.push_back(cameraAt(angleOf(view) + off, path.height));
        }
        return cams;
    };
    struct Variant {
        const char* name;
        HybridRenderer* renderer;
        bool prevention;
        SampleSolution sol[2];
        SampleMaps maps[2];
        bool direct = false;      // 000 §4.3's direct images stacked too
        bool neighbours = true;   // the nearby viewpoints stacked (with prevention)
    };
    // 3 and 4: 000 §4.3's direct images of the environment, with the nearby viewpoints and
    // (the paper's alternative to them) with ray continuation alone.
    Variant variants[5] = {{"multi_layer", &multiR, true, {}, {}},
                           {"single_layer", &singleR, true, {}, {}},
                           {"without_prevention", &multiR, false, {}, {}},
                           {"with_direct_images", &multiR, true, {}, {}, true, true},
                           {"direct_images_only", &multiR, true, {}, {}, true, false}};
    t0 = Clock::now();
    {
        Progress progress("hybrid precompute", 10);
        for (Variant& v : variants)
            for (int s = 0; s < 2; ++s) {
                RecordOptions ro{v.prevention, v.prevention};
                ro.directImages = v.direct;
                ro.direct.source = S.directSource;
                v.sol[s] = inferSample(*v.renderer, k + s, neighbourhood(k + s, v.prevention && v.neighbours),
                                       S.pre, ro);
                progress.advance();
            }
    }
    const double precomputeS = since(t0);
    for (Variant& v : variants)
        for (int s = 0; s < 2; ++s) v.maps[s] = uploadSample(*v.renderer, v.sol[s]);

    // ---- evaluation views ---------------------------------------------------------------------
    const float between = angleOf(k) + 0.5f * S.stepDegrees;
    struct View {
        std::string name;
        ray::Camera camera;
        Reference ref;
        std::map<std::string, Frame> frames;
        std::map<std::string, ray::MaskedScore> scores;
    };
    View on{"on_sample", path.at(uint32_t(k)), {}, {}, {}};
    View mid{"between", cameraAt(between, path.height), {}, {}, {}};
    View above{"above", cameraAt(between, path.height + S.aboveHeight), {}, {}, {}};
    t0 = Clock::now();
    for (View* v : {&on, &mid, &above}) v->ref = traceReference(lens.accel(), v->camera, S);
    const double referenceS = since(t0);
    auto evaluate = [&](View& v, const std::string& name, Variant& var, bool blended, float tau) {
        HybridRenderer& r = *var.renderer;
        r.tessellation().tau = tau;
        Frame f = blended ? renderFrame(r, v.camera, var.maps[0], &var.maps[1], 0.5f)
                          : renderFrame(r, v.camera, var.maps[0], nullptr, 0.0f);
        r.tessellation().tau = S.pre.tau;
        v.frames[name] = std::move(f);
    };
    evaluate(on, "multi_layer", variants[0], false, S.pre.tau);
    evaluate(on, "single_layer", variants[1], false, S.pre.tau);
    for (View* v : {&mid, &above}) {
        evaluate(*v, "multi_layer", variants[0], true, S.pre.tau);
        evaluate(*v, "single_layer", variants[1], true, S.pre.tau);
        evaluate(*v, "without_prevention", variants[2], true, S.pre.tau);
        evaluate(*v, "with_direct_images", variants[3], true, S.pre.tau);
        evaluate(*v, "direct_images_only", variants[4], true, S.pre.tau);
    }
    evaluate(mid, "multi_layer_tau_fast", variants[0], true, S.tauFast);
    // 000 §4.3: "To conserve texture memory, it is beneficial to share more distant EM
    // layers between local lens objects ... add more equations to the linear system (1)
    // corresponding to multiple lens objects and simultaneously solving for a single EM x."
    // Every lens object's outermost layer takes the first object's outermost shell, and
    // one map is inferred over all their rows (with prevention, as multi_layer).
    std::vector<LensLayers> sharedLayers = multi;
    nlohmann::json sharedJson;
    std::unique_ptr<HybridRenderer> sharedR;
    Variant sharedV{"shared_distant_layer", nullptr, true, {}, {}};
    // A clustering whose outermost glass layer is not a cube shell (one glass layer: Figure
    // 7's quad) has nothing to share: the variant is left out and the report says why,
    // rather than stopping a run that measured everything else.
    const std::string whyNotShared = whyDistantLayersCannotBeShared(multi);
    if (lensCount > 1 && whyNotShared.empty()) {
        shareDistantLayers(sharedLayers);
        sharedR = std::make_unique<HybridRenderer>(device, memory, lens, sharedLayers, n, ts);
        sharedV.renderer = sharedR.get();
        for (int s = 0; s < 2; ++s) {
            sharedV.sol[s] = inferSample(*sharedR, k + s, neighbourhood(k + s, true), S.pre, RecordOptions{true, true});
            sharedV.maps[s] = uploadSample(*sharedR, sharedV.sol[s]);
        }
        for (View* v : {&mid, &above}) evaluate(*v, sharedV.name, sharedV, true, S.pre.tau);
        const LensLayers& owner = sharedLayers[0];
        const int64_t rowsShared = sharedV.sol[0].maps[0][size_t(owner.layers() - 1)].rows;
        int64_t rowsOwn = 0;
        for (size_t i = 0; i < lensCount; ++i) rowsOwn += variants[0].sol[0].maps[i].back().rows;
        nlohmann::json members = nlohmann::json::object();
        for (size_t i = 0; i < lensCount; ++i) {
            nlohmann::json objs = nlohmann::json::array();
            for (uint32_t o : multi[i].assignment.layers.back().objects) objs.push_back(lens.scene().objects[o].name);
            members[lens.objects()[i].name] = objs;
        }
        sharedJson = {{"shell", sharedLayers[0].shells.back().describe()},
                      {"owner", lens.objects()[0].name},
                      {"texture_bytes_per_sample", {{"shared", HybridRenderer::sampleBytes(sharedLayers)},
                                                    {"own", HybridRenderer::sampleBytes(multi)}}},
                      {"rows", {{"shared_system", rowsShared}, {"own_systems_together", rowsOwn}}},
                      {"outer_layer_members", members}};
    }
    // A common mask per view (every variant covers it), so the scores compare the same pixels.
    for (View* v : {&on, &mid, &above}) {
        ray::Image mask = lensMask(v->ref, v->frames.at("multi_layer"));
        for (auto& [name, f] : v->frames) mask = maskAnd(mask, lensMask(v->ref, f));
        for (auto& [name, f] : v->frames)
            v->scores[name] = ray::compareMasked(
                v->ref.image, f.image, mask,
                "hybrid: the lens objects in view '" + v->name + "' (" + name + ")");
    }
    // 000 §5's forecast on a four-stage board: the same EMs on the geforce3 profile, the two
    // samples lerped inside each pass.
    nlohmann::json geforce3;
    {
        const Profile& p3 = profileByName("geforce3");
        raster::Device d3(p3, W * n, H * n, raster::DepthFormat::D24, {rasterPath, S.threads});
        HybridRenderer r3(d3, std::make_shared<tex::TextureMemory>(p3), lens, multi, n, ts);
        const SampleMaps a3 = uploadSample(r3, variants[0].sol[0]), b3 = uploadSample(r3, variants[0].sol[1]);
        const Frame f3 = renderFrame(r3, mid.camera, a3, &b3, 0.5f);
        const Frame f3on = renderFrame(r3, on.camera, a3, nullptr, 0.0f);
        const ray::MaskedScore sc = ray::compareMasked(
            mid.ref.image, f3.image, maskAnd(lensMask(mid.ref, mid.frames.at("multi_layer")), lensMask(mid.ref, f3)),
            "hybrid: the lens objects between samples on geforce3");
        geforce3 = {{"blended", {{"layer_passes", f3.counts.layerPasses}, {"alpha_clears", f3.counts.alphaClears}}},
                    {"on_sample", {{"layer_passes", f3on.counts.layerPasses}, {"alpha_clears", f3on.counts.alphaClears}}},
                    {"psnr_db_between", sc.psnr},
                    {"psnr_db_between_geforce256_same_pixels",
                     ray::compareMasked(mid.ref.image, mid.frames.at("multi_layer").image,
                                        maskAnd(lensMask(mid.ref, mid.frames.at("multi_layer")), lensMask(mid.ref, f3)),
                                        "hybrid: the lens objects between samples on geforce256").psnr},
                    {"draw_s", f3.times.drawS}};
    }
    // Edge band of Figure 10.
    const ray::Image midMask = [&] {
        ray::Image m = lensMask(mid.ref, mid.frames.at("multi_layer"));
        return maskAnd(m, lensMask(mid.ref, mid.frames.at("multi_layer_tau_fast")));
    }();
    const ray::Image band = edgeBand(midMask, mid.ref);
    const double edgeTau3 = meanAbsError(mid.ref.image, mid.frames.at("multi_layer").image, band);
    const double edgeTau5 = meanAbsError(mid.ref.image, mid.frames.at("multi_layer_tau_fast").image, band);
    const int64_t bandPixels = int64_t(std::count_if(band.pixels.begin(), band.pixels.end(),
                                                     [](float v) { return v > 0.5f; }));

    // ---- popping (000 §6, video): switching samples at the midpoint -------------------------
    // Nearest-sample frames just before and after the midpoint between k and k + 1: the
    // frame-to-frame change beyond the ray tracer's own.
    nlohmann::json popping;
    {
        const float eps = 0.25f;
        const ray::Camera c0 = cameraAt(between - eps, path.height), c1 = cameraAt(between + eps, path.height);
        Reference r0 = traceReference(lens.accel(), c0, S), r1 = traceReference(lens.accel(), c1, S);
        for (int vi : {0, 1}) {
            Variant& var = variants[vi];
            Frame f0 = renderFrame(*var.renderer, c0, var.maps[0], nullptr, 0.0f);
            Frame f1 = renderFrame(*var.renderer, c1, var.maps[1], nullptr, 0.0f);
            ray::Image mask = maskAnd(lensMask(r0, f0), lensMask(r1, f1));
            const double hybridChange = meanAbsDifference(f0.image, f1.image, mask);
            const double rayChange = meanAbsDifference(r0.image, r1.image, mask);
            popping[var.name] = {{"frame_change", hybridChange},
                                 {"ray_traced_change", rayChange},
                                 {"excess", hybridChange - rayChange}};
        }
    }

    // ---- Figure 2: the full ray tree against the greedy two-term paths ----------------------
    nlohmann::json shading;
    ray::Image fig2Full, fig2Two, fig2Mask;
    {
        const ray::Camera cam = on.camera;
        const ray::Accel& accel = lens.accel();
        fig2Full = ray::Image(W, H, 3);
        fig2Two = ray::Image(W, H, 3);
        fig2Mask = ray::Image(W, H, 1);
        std::vector<ray::RayCounts> fullRows(static_cast<size_t>(H)), twoRows(static_cast<size_t>(H));
        ray::RenderOptions o;
        o.width = W;
        o.height = H;
        o.spp = n;
        o.threads = S.threads;
        ray::parallelRows(o, [&](int y, ray::RayCounts&) {
            for (int x = 0; x < W; ++x) {
                glm::vec3 full(0.0f), two(0.0f);
                int lensSamples = 0;
                for (int sy = 0; sy < n; ++sy)
                    for (int sx = 0; sx < n; ++sx) {
                        const glm::vec2 f = ray::samplePosition(x, y, sx, sy, n);
                        const ray::Ray r = ray::primaryRay(cam, W, H, f.x, f.y);
                        ray::Hit hit;
                        const ray::SurfacePoint s = accel.intersectSurface(r, hit);
                        ray::RayCounts cf, ct;
                        full += ray::whittedShade(accel, r, hit, s, 0, S.pre.maxDepth, cf);
                        const ray::TwoTermSample t = ray::traceTwoTerm(accel, r, hit, s, S.pre.maxDepth, ct);
                        two += t.direct + (t.reflect.valid ? t.reflect.radiance * t.reflect.F * t.reflect.G : glm::vec3(0.0f)) +
                               (t.refract.valid ? t.refract.radiance * t.refract.F * t.refract.G : glm::vec3(0.0f));
                        if (t.hitLens) {
                            ++lensSamples;
                            for (size_t q = 0; q < cf.n.size(); ++q) {
                                fullRows[size_t(y)].n[q] += cf.n[q];
                                twoRows[size_t(y)].n[q] += ct.n[q];
                            }
                        }
                    }
                fig2Full.setRgb(x, y, full / float(n * n));
                fig2Two.setRgb(x, y, two / float(n * n));
                fig2Mask.at(x, y, 0) = lensSamples == n * n ? 1.0f : 0.0f;
            }
        });
        ray::RayCounts fullRays, twoRays;
        for (int y = 0; y < H; ++y)
            for (size_t q = 0; q < fullRays.n.size(); ++q) {
                fullRays.n[q] += fullRows[size_t(y)].n[q];
                twoRays.n[q] += twoRows[size_t(y)].n[q];
            }
        const ray::MaskedScore sc = ray::compareMasked(fig2Full, fig2Two, fig2Mask,
                                                       "hybrid: Figure 2's lens pixels");
        shading = {{"full_tree_rays", raysJson(fullRays)},
                   {"two_term_rays", raysJson(twoRays)},
                   {"ratio", double(fullRays.total()) / double(std::max<uint64_t>(1, twoRays.total()))},
                   {"psnr_db", sc.psnr},
                   {"ssim", sc.ssim},
                   {"pixels", sc.pixels},
                   {"note", "rays spawned below the primary hit of samples that hit a lens object "
                            "(no primary rays), including the shadow rays of the exits' shading"}};
    }

    // ---- the §6 table: the hybrid frame against a uniform ray tracer -------------------------
    nlohmann::json table;
    {
        Variant& v = variants[0];
        std::map<std::string, std::vector<double>> rows;
        FrameCounts countsTau[2];
        Reference uniform;
        std::vector<double> uniformS;
        // --capture FILE (docs/trace-format.md): the device commands of the frame this table
        // times (between the samples, τ = the slow setting), recorded in an extra frame before
        // the timed ones so that recording stays out of the timings. `retroglass bench
        // --trace FILE` then times its 4n layer passes and alpha clears on ours and on Mesa.
        if (!options.capture.empty()) {
            auto capture = std::make_shared<raster::TraceRecorder>();
            device.setRecorder(capture);
            (void)v.renderer->render(mid.camera, v.maps[0], &v.maps[1], 0.5f);
            device.setRecorder(nullptr);
            capture->save(options.capture);
            std::printf("hybrid: captured the table's frame (τ = %g) into %s (%zu bytes, sha256 %s)\n",
                        double(S.pre.tau), options.capture.c_str(), capture->bytes().size(),
                        raster::framebufferHash(device.framebuffer()).c_str());
        }
        for (int rep = 0; rep < std::max(1, S.tableFrames); ++rep) {
            for (int ti = 0; ti < 2; ++ti) {
                const float tau = ti == 0 ? S.pre.tau : S.tauFast;
                const std::string key = ti == 0 ? "tau_slow" : "tau_fast";
                v.renderer->tessellation().tau = tau;
                FrameTimes t = v.renderer->render(mid.camera, v.maps[0], &v.maps[1], 0.5f);
                countsTau[ti] = v.renderer->counts();
                rows[key + "/vertex_raytrace_s"].push_back(t.vertexRaysS);
                rows[key + "/texgen_s"].push_back(t.texgenS);
                rows[key + "/tessellation_s"].push_back(t.tessellationS);
                rows[key + "/other_s"].push_back(t.otherS());
                rows[key + "/draw_s"].push_back(t.drawS);
                rows[key + "/frame_s"].push_back(t.totalS());
            }
            uniform = traceReference(lens.accel(), mid.camera, S);
            uniformS.push_back(uniform.seconds);
        }
        v.renderer->tessellation().tau = S.pre.tau;
        // Triangle tests: the same frames on the counting twins (untimed).
        uint64_t tests[2] = {0, 0};
        uint64_t uniformTests = 0;
        if (S.countTests) {
            for (int ti = 0; ti < 2; ++ti) {
                v.renderer->tessellation().tau = ti == 0 ? S.pre.tau : S.tauFast;
                lens.countingVisibility().resetTriangleTests();
                for (size_t i = 0; i < lensCount; ++i) lens.countingLocal(i).resetTriangleTests();
                v.renderer->prepare(mid.camera, true);
                tests[ti] = lens.countingVisibility().triangleTests();
                for (size_t i = 0; i < lensCount; ++i) tests[ti] += lens.countingLocal(i).triangleTests();
            }
            v.renderer->tessellation().tau = S.pre.tau;
            uniformTests = traceReference(lens.countingAccel(), mid.camera, S).triangleTests;
        }
        // 000 §6: "more complicated environmental geometry will increase the benefit of our
        // use of approximating shells". The same scene with 64× finer columns: the uniform
        // ray tracer meets them, the hybrid frame's rays (local geometry only) do not.
        uint64_t heavyTests = 0, heavyTriangles = 0;
        if (S.countTests && builtin) {
            ray::Scene heavy = lens.scene();
            const int c0 = heavy.findObject("column0");
            if (c0 >= 0) {
                heavy.meshes[heavy.objects[size_t(c0)].mesh] = ray::makeCylinder(0.35f, 8.0f, 32 * 64);
                for (const auto& o : heavy.objects) heavyTriangles += heavy.meshes[o.mesh].triangleCount();
                const ray::Accel heavyCounting(heavy, ray::AccelOptions{true});
                heavyTests = traceReference(heavyCounting, mid.camera, S).triangleTests;
            }
        }
        const double uT = median(uniformS);
        const double uRays = double(uniform.rays.total());
        auto tauJson = [&](int ti) {
            const std::string key = ti == 0 ? "tau_slow" : "tau_fast";
            const double frame = median(rows[key + "/frame_s"]);
            const double raysN = double(countsTau[ti].rays.total());
            return nlohmann::json{
                {"tau", ti == 0 ? S.pre.tau : S.tauFast},
                {"vertex_raytrace_s", median(rows[key + "/vertex_raytrace_s"])},
                {"texgen_s", median(rows[key + "/texgen_s"])},
                {"tessellation_s", median(rows[key + "/tessellation_s"])},
                {"other_s", median(rows[key + "/other_s"])},
                {"emulated_rasterization_s", median(rows[key + "/draw_s"])},
                {"frame_s", frame},
                {"time_reduction", uT / frame},
                {"rays", raysJson(countsTau[ti].rays)},
                {"ray_reduction", uRays / std::max(1.0, raysN)},
                {"triangle_tests", tests[ti]},
                {"test_reduction", tests[ti] ? double(uniformTests) / double(tests[ti]) : 0.0},
                {"vertices_traced", countsTau[ti].verticesTraced},
                {"triangles", countsTau[ti].trianglesOut},
                {"max_level", countsTau[ti].maxLevel}};
        };
        table = {{"tau3", tauJson(0)},
                 {"tau5", tauJson(1)},
                 {"uniform", {{"frame_s", uT}, {"rays", raysJson(uniform.rays)}, {"triangle_tests", uniformTests}}},
                 {"heavy_environment", {{"columns_segments", 32 * 64}, {"scene_triangles", heavyTriangles},
                                        {"uniform_triangle_tests", heavyTests},
                                        {"test_reduction_tau3", tests[0] ? double(heavyTests) / double(tests[0]) : 0.0},
                                        {"test_reduction_tau5", tests[1] ? double(heavyTests) / double(tests[1]) : 0.0}}},
                 {"threads", S.threads},
                 {"repetitions", S.tableFrames},
                 {"view", "between"},
                 {"paper", {{"tau3", {{"vertex_raytrace_s", 13.48}, {"texgen_s", 0.71}, {"tessellation_s", 2.11},
                                      {"other_s", 2.57}, {"frame_s", 18.87}, {"time_reduction", 25.4},
                                      {"rays", 1023876}, {"ray_reduction", 6.0}, {"triangle_tests", 11878133},
                                      {"test_reduction", 14.2}}},
                            {"tau5", {{"vertex_raytrace_s", 7.82}, {"texgen_s", 0.38}, {"tessellation_s", 0.83},
                                      {"other_s", 1.45}, {"frame_s", 10.48}, {"time_reduction", 45.8},
                                      {"rays", 570481}, {"ray_reduction", 10.8}, {"triangle_tests", 6543993},
                                      {"test_reduction", 25.7}}},
                            {"uniform", {{"frame_s", 480}, {"rays", 6153735}, {"triangle_tests", 168313768}}}}}};
    }

    // ---- figures ------------------------------------------------------------------------------
    demos::Report rep(hybridReproduction(), options.quality);
    auto label = [](const View& v, const std::string& name, const std::string& text) {
        const auto& s = v.scores.at(name);
        return text + ", " + demos::num(s.psnr) + " dB";
    };
    ray::writeImage(out / "figure8_novel_views.png",
                    demos::labelledGrid({{mid.ref.image, "(a) between samples: ray traced"},
                                         {composite(mid.frames["multi_layer"], mid.ref), label(mid, "multi_layer", "hybrid, multi-layer")},
                                         {composite(mid.frames["single_layer"], mid.ref), label(mid, "single_layer", "hybrid, single layer")},
                                         {above.ref.image, "(b) above: ray traced"},
                                         {composite(above.frames["multi_layer"], above.ref), label(above, "multi_layer", "hybrid, multi-layer")},
                                         {composite(above.frames["single_layer"], above.ref), label(above, "single_layer", "hybrid, single layer")}},
                                        3));
    ray::writeImage(out / "figure2_shading_models.png",
                    demos::labelledGrid({{fig2Full, "(a) full ray tree, " + count(shading["full_tree_rays"]["total"].get<double>()) + " rays"},
                                         {fig2Two, "(b) two-term greedy, " + count(shading["two_term_rays"]["total"].get<double>()) + " rays"}},
                                        2));
    {
        multiR.prepare(mid.camera);
        multiR.drawLevels();
        ray::Image levels = multiR.displayImage();
        ray::writeImage(out / "figure5_subdivision_levels.png",
                        demos::labelledGrid({{levels, "subdivision level (darker: deeper), tau = " + demos::num(S.pre.tau, 0)}}, 1));
    }
    {
        std::vector<demos::Cell> cells;
        const SampleSolution& sol = variants[0].sol[0];
        const size_t t = 0;  // the first lens object (the teapot in the built-in scene)
        for (size_t l = 0; l < sol.maps[t].size(); ++l) {
            const std::string name = "L" + std::to_string(l + 1) + " (" + multi[t].shells[l].describe() + ")";
            cells.push_back({rgbOf(sol.images[t].b[l][0]), name + ": b_R"});
            cells.push_back({rgbOf(sol.images[t].b[l][1]), "b_T"});
            cells.push_back({mapImage(sol.maps[t][l]), "inferred EM x (finest level)"});
        }
        ray::writeImage(out / "figure7_layers.png", demos::labelledGrid(cells, 3));
    }
    {
        // Per-pixel error against the ray tracer over the lens pixels (0 to 0.25).
        std::vector<demos::Cell> cells;
        for (View* v : {&on, &mid, &above})
            for (const auto& [name, f] : v->frames) {
                const ray::Image m = lensMask(v->ref, f);
                cells.push_back({ray::errorHeatMap(demos::masked(v->ref.image, m),
                                                   demos::masked(f.image, m), 0.25f),
                                 v->name + ": " + name});
            }
        ray::writeImage(out / "error_maps.png", demos::labelledGrid(cells, 4));
    }
    ray::writeImage(out / "figure9_disocclusion.png",
                    demos::labelledGrid({{mid.ref.image, "ray traced"},
                                         {composite(mid.frames["multi_layer"], mid.ref), label(mid, "multi_layer", "(a) with prevention")},
                                         {composite(mid.frames["without_prevention"], mid.ref), label(mid, "without_prevention", "(b) without prevention")},
                                         {composite(mid.frames["with_direct_images"], mid.ref), label(mid, "with_direct_images", "(c) + direct images")}},
                                        4));
    ray::writeImage(out / "figure10_tau.png",
                    demos::labelledGrid({{mid.ref.image, "ray traced (" + demos::num(table["uniform"]["frame_s"].get<double>(), 2) + " s)"},
                                         {composite(mid.frames["multi_layer"], mid.ref), label(mid, "multi_layer", "tau = " + demos::num(S.pre.tau, 0)) + " (" + demos::num(table["tau3"]["frame_s"].get<double>(), 3) + " s)"},
                                         {composite(mid.frames["multi_layer_tau_fast"], mid.ref), label(mid, "multi_layer_tau_fast", "tau = " + demos::num(S.tauFast, 0)) + " (" + demos::num(table["tau5"]["frame_s"].get<double>(), 3) + " s)"}},
                                        3));

    // ---- results.json -------------------------------------------------------------------------
    nlohmann::json r;
    auto viewJson = [&](const View& v) {
        nlohmann::json j;
        for (const auto& [name, s] : v.scores) {
            j["psnr_db"][name] = s.psnr;
            j["ssim"][name] = s.ssim;
            j["pixels"] = s.pixels;
        }
        return j;
    };
    r["novel_views"] = {{"on_sample", viewJson(on)}, {"between", viewJson(mid)}, {"above", viewJson(above)}};
    r["disocclusion"] = {{"psnr_db", {{"with", mid.scores["multi_layer"].psnr}, {"without", mid.scores["without_prevention"].psnr}}}};
    {
        nlohmann::json holes;
        for (const Variant& v : {variants[0], variants[2]}) {
            int64_t unconstrained = 0, texels = 0;
            for (const auto& lensMaps : v.sol[0].maps)
                for (const LayerMap& m : lensMaps) {
                    unconstrained += m.unconstrained;
                    texels += m.layout.levelOffset(1);
                }
            holes[v.name] = {{"unconstrained_texels", unconstrained}, {"finest_texels", texels}};
        }
        r["disocclusion"]["holes"] = holes;
    }
    r["tau_quality"] = {{"psnr_db", {{"tau3", mid.scores["multi_layer"].psnr}, {"tau5", mid.scores["multi_layer_tau_fast"].psnr}}},
                        {"edge_error", {{"tau3", edgeTau3}, {"tau5", edgeTau5}}},
                        {"edge_pixels", bandPixels}};
    r["popping"] = popping;
    r["shading_model"] = shading;
    r["clustering"] = clusteringJson;
    r["table"] = table;
    {
        const Frame& fb = mid.frames.at("multi_layer");
        const Frame& fo = on.frames.at("multi_layer");
        r["passes"] = {{"blended", {{"layer_passes", fb.counts.layerPasses}, {"alpha_clears", fb.counts.alphaClears}, {"device_passes", fb.devicePasses}}},
                       {"on_sample", {{"layer_passes", fo.counts.layerPasses}, {"alpha_clears", fo.counts.alphaClears}, {"device_passes", fo.devicePasses}}},
                       {"geforce3", geforce3}};
    }
    nlohmann::json residuals = nlohmann::json::object();
    for (size_t i = 0; i < lensCount; ++i)
        for (size_t l = 0; l < variants[0].sol[0].maps[i].size(); ++l)
            residuals[lens.objects()[i].name].push_back(variants[0].sol[0].maps[i][l].residual);
    r["precompute"] = {{"clustering_s", clusterS}, {"samples_s", precomputeS},
                       {"records_s", variants[0].sol[0].recordsS}, {"matrices_s", variants[0].sol[0].matrixS},
                       {"solve_s", variants[0].sol[0].solveS}, {"views_per_sample", variants[0].sol[0].views},
                       {"residuals", residuals}, {"reference_s", referenceS}};
    r["settings"] = {{"quality", demos::qualityName(options.quality)},
                     {"image_size", {W, H}}, {"subsamples", n * n}, {"em_size", S.pre.emSize},
                     {"teapot_level", S.teapotLevel}, {"viewpoints", S.views}, {"step_degrees", S.stepDegrees},
                     {"sample", k}, {"tau", {S.pre.tau, S.tauFast}}, {"neighbour_views", S.neighbourViews},
                     {"neighbour_span_degrees", S.neighbourSpanDegrees}, {"threads", S.threads},
                     {"profile", std::string(profile.name)}, {"scene", lens.scene().name}};

    // ---- 000 §4.3: direct images of the environment, where disocclusion matters ------------
    // Twelve views between samples k and k + 1 (¼, ½ and ¾ of the step, blended as the
    // frame blends them) at four heights (the plane, and ½, 1 and 1.5 × the Figure 8b height
    // above it): off, the nearby viewpoints, the nearby viewpoints with direct images, and
    // direct images with ray continuation alone. Scores over the lens pixels every variant
    // covers in that view; the gains are paired per view, their spread gives the claim's
    // margin (below).
    nlohmann::json directJson;
    {
        const char* names[4] = {"without_prevention", "multi_layer", "with_direct_images", "direct_images_only"};
        const int index[4] = {2, 0, 3, 4};
        std::map<std::string, std::vector<double>> psnrs, ssims;
        nlohmann::json views = nlohmann::json::array();
        for (float fa : {0.25f, 0.5f, 0.75f})
            for (float fh : {0.0f, 0.5f, 1.0f, 1.5f}) {
                const ray::Camera cam = cameraAt(angleOf(k) + fa * S.stepDegrees, path.height + fh * S.aboveHeight);
                const Reference ref = traceReference(lens.accel(), cam, S);
                std::map<std::string, Frame> frames;
                for (int j = 0; j < 4; ++j) {
                    Variant& var = variants[index[j]];
                    frames[names[j]] = renderFrame(*var.renderer, cam, var.maps[0], &var.maps[1], fa);
                }
                ray::Image mask = lensMask(ref, frames.at(names[0]));
                for (auto& [name, f] : frames) mask = maskAnd(mask, lensMask(ref, f));
                nlohmann::json vj = {{"azimuth_degrees", angleOf(k) + fa * S.stepDegrees},
                                     {"height_above_plane", fh * S.aboveHeight}};
                for (auto& [name, f] : frames) {
                    const ray::MaskedScore sc = ray::compareMasked(
                        ref.image, f.image, mask, "hybrid: direct-image view (" + name + ")");
                    psnrs[name].push_back(sc.psnr);
                    ssims[name].push_back(sc.ssim);
                    vj["psnr_db"][name] = sc.psnr;
                    vj["ssim"][name] = sc.ssim;
                    vj["pixels"] = sc.pixels;
                }
                views.push_back(vj);
            }
        auto mean = [](const std::vector<double>& v) {
            return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
        };
        // Paired gain a − b over the views: mean, standard deviation, standard error.
        auto gain = [&](const char* a, const char* b) {
            std::vector<double> d;
            for (size_t i = 0; i < psnrs[a].size(); ++i) d.push_back(psnrs[a][i] - psnrs[b][i]);
            const double m = mean(d);
            double ss = 0;
            for (double x : d) ss += (x - m) * (x - m);
            const double sd = d.size() > 1 ? std::sqrt(ss / double(d.size() - 1)) : 0.0;
            return nlohmann::json{{"mean_db", m}, {"sd_db", sd},
                                  {"se_db", d.empty() ? 0.0 : sd / std::sqrt(double(d.size()))},
                                  {"min_db", d.empty() ? 0.0 : *std::min_element(d.begin(), d.end())},
                                  {"max_db", d.empty() ? 0.0 : *std::max_element(d.begin(), d.end())}};
        };
        directJson["views"] = views;
        // The same gain in the plane of the samples and above it (Figure 8's two cases).
        for (const bool inPlane : {true, false}) {
            std::vector<double> d;
            for (size_t i = 0; i < views.size(); ++i)
                if ((views[i]["height_above_plane"].get<double>() == 0.0) == inPlane)
                    d.push_back(psnrs["with_direct_images"][i] - psnrs["multi_layer"][i]);
            directJson["gain_direct_images_over_neighbourhood_by_height"][inPlane ? "in_plane" : "above"] = mean(d);
        }
        for (const char* name : names) {
            directJson["mean_psnr_db"][name] = mean(psnrs[name]);
            directJson["mean_ssim"][name] = mean(ssims[name]);
        }
        directJson["gain"] = {{"direct_images_over_neighbourhood", gain("with_direct_images", "multi_layer")},
                              {"direct_images_only_over_off", gain("direct_images_only", "without_prevention")},
                              {"neighbourhood_over_off", gain("multi_layer", "without_prevention")},
                              {"direct_images_only_over_neighbourhood", gain("direct_images_only", "multi_layer")}};
        nlohmann::json holes, direct;
        for (int j : {2, 0, 3, 4}) {
            const Variant& v = variants[j];
            int64_t unconstrained = 0, texels = 0, directRows = 0, rows = 0;
            for (const auto& lensMaps : v.sol[0].maps)
                for (const LayerMap& m : lensMaps) {
                    unconstrained += m.unconstrained;
                    texels += m.layout.levelOffset(1);
                    directRows += m.directRows;
                    rows += m.rows;
                }
            holes[v.name] = {{"unconstrained_texels", unconstrained}, {"finest_texels", texels},
                             {"rows", rows}, {"direct_rows", directRows},
                             {"direct_images", v.sol[0].directImages},
                             {"direct_s", v.sol[0].directS}};
        }
        directJson["sample_k"] = holes;
        directJson["sources"] = nlohmann::json::object();
        for (size_t i = 0; i < lensCount; ++i) {
            const LensObject& L = lens.objects()[i];
            directJson["sources"][L.name] =
                resolveDirectSource(L, S.directSource) == DirectSource::Viewpoint
                    ? "the viewpoint sample (refractive)" : "the object centre, six 90° views (reflective)";
        }
        directJson["confidence"] = {{"function", "min(1, d / d0)"},
                                    {"d0_texels", RecordOptions{}.direct.confidenceTexels}};
        directJson["between"] = {{"psnr_db", mid.scores["with_direct_images"].psnr}, {"ssim", mid.scores["with_direct_images"].ssim}};
        directJson["above"] = {{"psnr_db", above.scores["with_direct_images"].psnr}, {"ssim", above.scores["with_direct_images"].ssim}};
        r["disocclusion"]["direct_images"] = directJson;
        if (!sharedJson.is_null()) {
            sharedJson["psnr_db"] = {{"between", {{"shared", mid.scores[sharedV.name].psnr}, {"own", mid.scores["multi_layer"].psnr}}},
                                     {"above", {{"shared", above.scores[sharedV.name].psnr}, {"own", above.scores["multi_layer"].psnr}}}};
            sharedJson["ssim"] = {{"between", {{"shared", mid.scores[sharedV.name].ssim}, {"own", mid.scores["multi_layer"].ssim}}},
                                  {"above", {{"shared", above.scores[sharedV.name].ssim}, {"own", above.scores["multi_layer"].ssim}}}};
            r["shared_distant_layers"] = sharedJson;
        } else if (!whyNotShared.empty()) {
            r["shared_distant_layers_left_out"] = whyNotShared;
        }
        // The claim: 000 §4.3 says direct images "fill in the missing portions of the
        // environment". Measured as their gain on top of the nearby viewpoints (the
        // prevention of §6), mean over the twelve views; the margin is twice the standard
        // error of the paired gains (a gain inside the views' own scatter does not count),
        // fixed before the numbers were seen.
        const auto& g = directJson["gain"]["direct_images_over_neighbourhood"];
        rep.claim(demos::claimAtLeast("direct_images_help", "§4.3, Figure 9",
                                      "Direct images of the environment, stacked with the lens object images, fill in missing portions "
                                      "of the EMs: novel views between and above the samples match the ray tracer better than with the nearby viewpoints alone",
                                      "with_direct_images_mean", directJson["mean_psnr_db"]["with_direct_images"].get<double>(),
                                      "neighbourhood_only_mean", directJson["mean_psnr_db"]["multi_layer"].get<double>(),
                                      2.0 * g["se_db"].get<double>(), "dB (margin 2 × the standard error of the 12 paired gains)"));
    }

    // ---- claims --------------------------------------------------------------------------------
    // Margins (docs/reports.md, "Margins"). The frames are deterministic, so a margin is the
    // size a difference must have to be the paper's effect rather than the choice of view or
    // 8-bit rounding; each comes from a spread measured at quick quality:
    // - PSNR orderings, 0.5 dB: one technique's PSNR moves by 0.2 dB between the sample's own
    //   view and the view between samples (multi-layer 25.17 → 24.97 dB), the change a view
    //   alone makes; the margin is over twice that.
    // - "at least as good" (τ = 3 against τ = 5): a deficit within that 0.2 dB is a tie.
    // - Mean 8-bit differences: popping 0.5 levels, twice the multi-layer frame's own excess
    //   change (0.22 levels: the floor of the measurement for frames that do not pop); edge
    //   error 0.25 levels, the mean |error| that rounding to 8 bits alone adds (uniform on ±½).
    // - Ray and test counts are exact: "several times" and "far more" are the bar (≥ 2×); the
    //   heavier environment must raise the test reduction by 0.5×, a quarter of that bar.
    // - The two-term model "approximates the full tree well": 30 dB, 5 dB better than the
    //   multi-layer frame's own agreement with the ray tracer (about 25 dB), so the shading
    //   model is not what limits the technique.
    constexpr double kMarginDb = 0.5;
    constexpr double kViewSpreadDb = 0.2;
    auto psnr = [](const View& v, const char* name) { return v.scores.at(name).psnr; };
    rep.claim(demos::claimAtLeast("multi_beats_single_between", "§6, Figure 8a",
                                  "Between viewpoint samples (in the plane) the multi-layer EMs match the ray tracer better than a single layer",
                                  "multi_layer", psnr(mid, "multi_layer"), "single_layer", psnr(mid, "single_layer"), kMarginDb, "dB"));
    rep.claim(demos::claimAtLeast("multi_beats_single_above", "§6, Figure 8b",
                                  "Above the plane of the samples the multi-layer EMs match the ray tracer better than a single layer",
                                  "multi_layer", psnr(above, "multi_layer"), "single_layer", psnr(above, "single_layer"), kMarginDb, "dB"));
    rep.claim(demos::claimAtLeast("single_layer_pops", "§6 (video)",
                                  "The single layer shows more popping than the multi-layer solution when switching between viewpoint samples",
                                  "single_layer_excess_change", 255.0 * popping["single_layer"]["excess"].get<double>(),
                                  "multi_layer_excess_change", 255.0 * popping["multi_layer"]["excess"].get<double>(), 0.5,
                                  "8-bit levels, mean |Δ| per channel"));
    rep.claim(demos::claimAtLeast("disocclusion_prevention_helps", "§6, Figure 9",
                                  "EM disocclusion prevention (ray continuation and simultaneous inference over nearby viewpoints) improves a novel view",
                                  "with", psnr(mid, "multi_layer"), "without", psnr(mid, "without_prevention"), kMarginDb, "dB"));
    rep.claim(demos::claimAtLeast("tau3_at_least_tau5", "§6, Figure 10",
                                  "τ = 3 is at least as good as τ = 5",
                                  "tau3", psnr(mid, "multi_layer"), "tau5", psnr(mid, "multi_layer_tau_fast"), -kViewSpreadDb, "dB"));
    rep.claim(demos::claimAtLeast("tau5_noisier_at_edges", "§6, Figure 10",
                                  "τ = 5 is noisier along edges (the bottom of the teapot, where the spout joins the body)",
                                  "tau5_edge_error", 255.0 * edgeTau5, "tau3_edge_error", 255.0 * edgeTau3, 0.25,
                                  "8-bit levels, mean |error| per channel"));
    rep.claim(demos::claimAtLeast("two_term_far_fewer_rays", "§3, Figure 2",
                                  "The full ray tree needs far more ray queries than the two-term greedy model (paper: 5×)",
                                  "ratio", shading["ratio"].get<double>(), "one", 1.0, 1.0, "×"));
    {
        demos::Claim c = demos::claimAtLeast("two_term_similar_error", "§3, Figure 2",
                                             "The two-term greedy model approximates the full ray tree well",
                                             "psnr_two_term_vs_full_tree", shading["psnr_db"].get<double>(), "threshold", 30.0, 0.0, "dB");
        rep.claim(c);
    }
    for (const char* key : {"tau3", "tau5"}) {
        const auto& t = table[key];
        rep.claim(demos::claimAtLeast(std::string("fewer_rays_") + key, "§6 table",
                                      std::string("The hybrid frame (") + key + ") needs several times fewer rays than uniform ray tracing",
                                      "ray_reduction", t["ray_reduction"].get<double>(), "one", 1.0, 1.0, "×"));
        if (S.countTests)
            rep.claim(demos::claimAtLeast(std::string("fewer_tests_") + key, "§6 table",
                                          std::string("The hybrid frame (") + key + ") needs several times fewer triangle tests than uniform ray tracing",
                                          "test_reduction", t["test_reduction"].get<double>(), "one", 1.0, 1.0, "×"));
    }
    if (builtin && S.countTests) {
        const auto& h = table["heavy_environment"];
        rep.claim(demos::claimAtLeast("complex_environment_increases_benefit", "§6",
                                      "More complicated environmental geometry increases the benefit of the shells "
                                      "(columns 64× finer: the uniform ray tracer's tests grow, the hybrid frame's do not)",
                                      "test_reduction_heavy", h["test_reduction_tau3"].get<double>(),
                                      "test_reduction", table["tau3"]["test_reduction"].get<double>(), 0.5, "×"));
    }
    if (builtin) {
        // Figure 7: k = 3 for the teapot gives the cup, the columns and the walls.
        demos::Claim c;
        c.id = "clustering_cup_columns_walls";
        c.section = "§4.2, §6, Figure 7";
        c.statement = "The clustering segments the glass teapot's environment into three layers: "
                      "the cup, the columns and the walls";
        c.test = "the cup in L1, all 12 columns in L2, the four walls in L3 (other objects may join "
                 "a layer: they are listed)";
        const auto& layers = clusteringJson["teapot"]["layers"];
        auto layerOf = [&](const std::string& name) {
            for (size_t l = 0; l < layers.size(); ++l)
                for (const auto& o : layers[l]["objects"])
                    if (o.get<std::string>() == name) return int(l);
            return -1;
        };
        c.holds = layers.size() == 3 && layerOf("cup") == 0;
        for (int i = 0; i < 12; ++i) c.holds = c.holds && layerOf("column" + std::to_string(i)) == 1;
        for (const char* w : {"room_wall_-x", "room_wall_+x", "room_wall_-z", "room_wall_+z"})
            c.holds = c.holds && layerOf(w) == 2;
        for (size_t l = 0; l < layers.size(); ++l) c.measured["L" + std::to_string(l + 1)] = layers[l]["objects"];
        rep.claim(c);
    }
    {
        demos::Claim c;
        c.id = "passes_4n_2n";
        c.section = "§5";
        c.statement = "4n passes between two samples and 2n on a sample for a two-term object of n layers (one layer per pass on the GeForce), with an alpha clear before the second term";
        int expectBlended = 0, expectOn = 0, clearsBlended = 0, clearsOn = 0;
        for (size_t i = 0; i < lensCount; ++i) {
            const int nl = multi[i].layers(), terms = lens.objects()[i].twoTerms ? 2 : 1;
            expectBlended += 2 * terms * nl;
            expectOn += terms * nl;
            clearsBlended += 2 * terms - 1;
            clearsOn += terms - 1;
        }
        const auto& p = r["passes"];
        c.test = "layer passes = Σ 2·terms·n and Σ terms·n, alpha clears = Σ (2·terms − 1) and Σ (terms − 1)";
        c.measured = {{"blended_layer_passes", p["blended"]["layer_passes"]}, {"expected_blended", expectBlended},
                      {"on_sample_layer_passes", p["on_sample"]["layer_passes"]}, {"expected_on_sample", expectOn},
                      {"blended_alpha_clears", p["blended"]["alpha_clears"]}, {"expected_blended_clears", clearsBlended},
                      {"on_sample_alpha_clears", p["on_sample"]["alpha_clears"]}, {"expected_on_sample_clears", clearsOn}};
        c.holds = p["blended"]["layer_passes"].get<int>() == expectBlended && p["on_sample"]["layer_passes"].get<int>() == expectOn &&
                  p["blended"]["alpha_clears"].get<int>() == clearsBlended && p["on_sample"]["alpha_clears"].get<int>() == clearsOn;
        rep.claim(c);
    }

    // ---- report ---------------------------------------------------------------------------------
    using demos::num;
    std::ostringstream& md = rep.md();
    md << "Hakura & Snyder, *Realistic Reflections and Refractions on Graphics Hardware With Hybrid "
          "Rendering and Layered Environment Maps*, EGWR 2001, on the emulated `geforce256` profile "
          "(Direct3D 7, two texture stages per pass).\n\n"
       << "Quality `" << demos::qualityName(options.quality) << "`: scene `" << lens.scene().name << "`, "
       << S.views << " viewpoint samples at " << num(S.stepDegrees, 1) << "°, display " << W << "×" << H
       << " with " << n << "×" << n << " subsamples, EMs " << S.pre.emSize << "² per face, "
       << "τ = " << num(S.pre.tau, 0) << " and " << num(S.tauFast, 0) << " subpixels, evaluated between samples "
       << k << " and " << k + 1 << ".\n\n";
    rep.heading("The §6 table, ours beside the paper's");
    {
        const auto& t3 = table["tau3"];
        const auto& t5 = table["tau5"];
        const auto& P = table["paper"];
        demos::Table t{{"", "paper τ=3", "ours τ=" + num(S.pre.tau, 0), "paper τ=5", "ours τ=" + num(S.tauFast, 0)}, {}};
        auto row = [&](const std::string& name, const std::string& key, int dec) {
            t.rows.push_back({name, num(P["tau3"][key].get<double>(), dec), num(t3[key].get<double>(), dec + 3),
                              num(P["tau5"][key].get<double>(), dec), num(t5[key].get<double>(), dec + 3)});
        };
        row("ray tracing at vertices (s)", "vertex_raytrace_s", 2);
        row("texture coord. generation (s)", "texgen_s", 2);
        row("tessellation (s)", "tessellation_s", 2);
        row("other, incl. rendering (s)", "other_s", 2);
        row("total frame (s)", "frame_s", 2);
        row("time reduction", "time_reduction", 1);
        t.rows.push_back({"rays", count(P["tau3"]["rays"].get<double>()), count(t3["rays"]["total"].get<double>()),
                          count(P["tau5"]["rays"].get<double>()), count(t5["rays"]["total"].get<double>())});
        row("ray reduction", "ray_reduction", 1);
        t.rows.push_back({"triangle intersection tests", count(P["tau3"]["triangle_tests"].get<double>()),
                          count(t3["triangle_tests"].get<double>()), count(P["tau5"]["triangle_tests"].get<double>()),
                          count(t5["triangle_tests"].get<double>())});
        row("intersection reduction", "test_reduction", 1);
        rep.table(t);
        md << "Uniform ray tracer (the same scene, view and ray code: raycore's greedy two-term tracer "
           << "over the whole scene, " << W << "×" << H << " with " << n << "×" << n << " rays per pixel): "
           << num(table["uniform"]["frame_s"].get<double>(), 3) << " s, "
           << count(table["uniform"]["rays"]["total"].get<double>()) << " rays, "
           << count(table["uniform"]["triangle_tests"].get<double>()) << " triangle tests (paper: 480 s, "
           << "6,153,735 rays, 168,313,768 tests). With the columns 64× finer ("
           << count(table["heavy_environment"]["scene_triangles"].get<double>()) << " triangles in the scene) the uniform "
           << "ray tracer makes " << count(table["heavy_environment"]["uniform_triangle_tests"].get<double>())
           << " tests and the reduction at τ = " << num(S.pre.tau, 0) << " becomes "
           << num(table["heavy_environment"]["test_reduction_tau3"].get<double>(), 1)
           << " (the hybrid frame's rays see the lens objects only). Times are medians of " << S.tableFrames
           << " interleaved frames on this machine's CPU (" << (S.threads > 0 ? std::to_string(S.threads) : std::string("all"))
           << " threads); the emulated GeForce's passes are inside \"other\" ("
           << num(t3["emulated_rasterization_s"].get<double>(), 3) << " s at τ = " << num(S.pre.tau, 0) << "). "
           << "Triangle tests come from the counting twins of the same accelerators (an Embree user "
           << "geometry testing one triangle per call), run on the same frame outside the timings.\n\n";
    }
    rep.heading("Why our reductions differ from the paper's");
    {
        const auto& t3 = table["tau3"];
        const auto& U = table["uniform"];
        const double uRays = U["rays"]["total"].get<double>(), hRays = t3["rays"]["total"].get<double>();
        const double uTests = U["triangle_tests"].get<double>(), hTests = t3["triangle_tests"].get<double>();
        const double samples = double(W) * H * n * n;
        md << "- **Tests per ray.** The uniform ray tracer makes " << num(uTests / std::max(1.0, uRays), 1)
           << " triangle tests per ray here (paper: 27.4), the hybrid frame " << num(hTests / std::max(1.0, hRays), 1)
           << " (paper: 11.6). Embree's BVH makes the environment's rays cheap — most primary rays meet a "
              "wall or the floor after a few tests — while the hybrid frame's rays start on the lens surface "
              "and end near it (a visibility ray grazes the vertex's own triangles), so the test reduction "
              "follows the ray reduction instead of exceeding it as the paper's does. With 64× finer columns "
              "the uniform tracer's tests grow by "
           << num(100.0 * (table["heavy_environment"]["uniform_triangle_tests"].get<double>() / std::max(1.0, uTests) - 1.0), 0)
           << "% only: a BVH's cost grows with the logarithm of the geometry, which is the paper's point about "
              "complicated environments made weak by a modern accelerator.\n"
           << "- **Rays per sample.** The uniform tracer casts " << num(uRays / samples, 2)
           << " rays per sample (paper: 2.23), shadow rays of the diffuse surfaces included; the vertex rays of "
              "the hybrid frame depend on τ in subpixels, so their reduction grows with τ (here "
           << num(t3["ray_reduction"].get<double>(), 1) << "× and " << num(table["tau5"]["ray_reduction"].get<double>(), 1)
           << "×; paper 6 and 10.8).\n"
           << "- **Time.** Embree traces a ray in well under a microsecond where the paper's tracer took "
              "78 µs, and our graphics card is emulated on the same CPU: the passes (\"other\") take "
           << num(100.0 * t3["other_s"].get<double>() / std::max(1e-9, t3["frame_s"].get<double>()), 0)
           << "% of the hybrid frame, where the paper's GeForce drew them in hardware. So the time reduction ("
           << num(t3["time_reduction"].get<double>(), 2) << "× at τ = " << num(S.pre.tau, 0)
           << ") does not follow the ray and test reductions; the paper's 25–45× came from 78 µs rays and "
              "hardware texturing. How fast the emulated passes are for what they draw is measured against "
              "Mesa's llvmpipe on the same commands, captured from the frame: `retroglass bench --filter "
              "'hybrid_.*_passes'` (docs/performance.md, \"The frame's passes against llvmpipe\"; "
              "`retroglass --capture FILE reproduce hybrid` records this table's frame).\n\n";
    }
    rep.heading("Quality against the ray tracer");
    {
        demos::Table t{{"view", "multi-layer", "single layer", "without prevention", "τ = " + num(S.tauFast, 0)}, {}};
        for (View* v : {&on, &mid, &above}) {
            auto cell = [&](const char* name) {
                auto it = v->scores.find(name);
                return it == v->scores.end() ? std::string("—") : num(it->second.psnr) + " / " + num(it->second.ssim, 3);
            };
            t.rows.push_back({v->name, cell("multi_layer"), cell("single_layer"), cell("without_prevention"), cell("multi_layer_tau_fast")});
        }
        rep.table(t);
        md << "PSNR (dB) / SSIM over the pixels every ray of the ray tracer and every subpixel of each "
              "frame puts on a lens object (" << mid.scores["multi_layer"].pixels << " pixels between samples).\n\n";
    }
    rep.heading("Passes (000 §5)");
    {
        const auto& p = r["passes"];
        demos::Table t{{"", "layer passes between samples", "alpha clears", "layer passes on a sample", "alpha clears"}, {}};
        t.rows.push_back({"geforce256 (2 stages)", std::to_string(p["blended"]["layer_passes"].get<int>()),
                          std::to_string(p["blended"]["alpha_clears"].get<int>()),
                          std::to_string(p["on_sample"]["layer_passes"].get<int>()),
                          std::to_string(p["on_sample"]["alpha_clears"].get<int>())});
        t.rows.push_back({"geforce3 (4 stages)", std::to_string(geforce3["blended"]["layer_passes"].get<int>()),
                          std::to_string(geforce3["blended"]["alpha_clears"].get<int>()),
                          std::to_string(geforce3["on_sample"]["layer_passes"].get<int>()),
                          std::to_string(geforce3["on_sample"]["alpha_clears"].get<int>())});
        rep.table(t);
        md << "On the GeForce 256 each layer takes a pass per term and per sample (4n between samples, "
              "2n on one, for a glass object of n layers; 2n and n for the mirror), and destination alpha "
              "restarts with an alpha-clear polygon before every further (term, sample) sequence. The paper "
              "forecasts n passes and no clear with four texture accesses; on the GeForce3 the two samples "
              "lerp inside a pass (BLENDFACTORALPHA), which gives 2n passes and one clear: both terms in one "
              "pass would need two running alphas, each term's layers compositing under its own, and a pass "
              "has one destination alpha. The lerp mixes the samples' texels before compositing (the "
              "GeForce 256 mixes the composited stacks): between samples "
           << num(geforce3["psnr_db_between"].get<double>()) << " dB against "
           << num(geforce3["psnr_db_between_geforce256_same_pixels"].get<double>()) << " dB on the same pixels.\n\n";
    }
    rep.heading("Direct images of the environment (000 §4.3)");
    {
        const auto& D = r["disocclusion"]["direct_images"];
        md << "000 §4.3: \"An alternative method to fill in the missing portions in the environment map is to "
              "infer it using extra rays in addition to the ones that exit the lens object ... Direct images from "
              "the lens object center tend to work better for reflective objects while direct images from the "
              "viewpoint are better suited for refractive (transparent) objects.\" Here: ";
        bool first = true;
        for (const auto& [name, src] : D["sources"].items()) {
            md << (first ? "" : "; ") << name << " from " << src.get<std::string>();
            first = false;
        }
        md << ". Each direct image is traced without the lens object (every front-facing hit, the first of each "
              "layer shaded, as the records), and its rows join each layer's stacked system with the lens object "
              "images'. Their A is the layer's shell seen from the direct camera on the same device. Per-pixel "
              "confidence, \"a function of the likelihood that the pixel represents a missing portion\", is [D] "
              "min(1, d/d0) with d the distance from the ray's point in the layer to the nearest point of the "
              "lens images' records (all stacked views), d0 = "
           << num(D["confidence"]["d0_texels"].get<double>(), 0)
           << " texels of the layer's finest level at its distance; no row where a ray meets a quad only by the "
              "forced intersection.\n\n";
        demos::Table t{{"variant", "between", "above", "mean of 12 views", "unconstrained texels (sample k)", "direct rows"}, {}};
        const std::pair<const char*, const char*> rows[] = {
            {"without_prevention", "off (first hits, the sample's view)"},
            {"multi_layer", "ray continuation + nearby viewpoints (§6)"},
            {"with_direct_images", "... + direct images"},
            {"direct_images_only", "ray continuation + direct images"}};
        for (const auto& [key, text] : rows) {
            auto sc = [&](const View& v) {
                auto it = v.scores.find(key);
                return it == v.scores.end() ? std::string("—") : num(it->second.psnr) + " / " + num(it->second.ssim, 3);
            };
            const auto& h = D["sample_k"][key];
            t.rows.push_back({text, sc(mid), sc(above),
                              num(D["mean_psnr_db"][key].get<double>()) + " / " + num(D["mean_ssim"][key].get<double>(), 3),
                              count(h["unconstrained_texels"].get<double>()) + " of " + count(h["finest_texels"].get<double>()),
                              count(h["direct_rows"].get<double>())});
        }
        rep.table(t);
        auto gainText = [&](const char* key) {
            const auto& g = D["gain"][key];
            return num(g["mean_db"].get<double>()) + " dB (sd " + num(g["sd_db"].get<double>()) + ", se " +
                   num(g["se_db"].get<double>()) + ", range " + num(g["min_db"].get<double>()) + " to " +
                   num(g["max_db"].get<double>()) + ")";
        };
        md << "PSNR (dB) / SSIM over the lens pixels. The twelve views lie between samples " << k << " and " << k + 1
           << " (¼, ½, ¾ of the step) at 0, ½, 1 and 1.5 × " << num(S.aboveHeight, 1)
           << " above the plane. Paired gains over those views: direct images on top of the nearby viewpoints "
           << gainText("direct_images_over_neighbourhood") << "; direct images with ray continuation over off "
           << gainText("direct_images_only_over_off") << "; the nearby viewpoints over off "
           << gainText("neighbourhood_over_off") << "; direct images alone against the nearby viewpoints "
           << gainText("direct_images_only_over_neighbourhood")
           << ". On top of the nearby viewpoints the direct images change PSNR by "
           << num(D["gain_direct_images_over_neighbourhood_by_height"]["in_plane"].get<double>())
           << " dB in the plane of the samples and by "
           << num(D["gain_direct_images_over_neighbourhood_by_height"]["above"].get<double>())
           << " dB above it (means over the views there). The claim `direct_images_help` asks the mean gain on "
              "top of the nearby viewpoints to exceed twice its standard error, a rule fixed before the "
              "measurement. The sources are a setting (`HybridSettings::directSource`; Auto follows the paper's "
              "advice).\n\n";
    }
    if (r.contains("shared_distant_layers")) {
        rep.heading("Shared distant layers (000 §4.3)");
        const auto& J = r["shared_distant_layers"];
        md << "000 §4.3: \"To conserve texture memory, it is beneficial to share more distant EM layers between "
              "local lens objects. To do this, we can add more equations to the linear system (1) corresponding to "
              "multiple lens objects and simultaneously solving for a single EM x.\" Here every lens object's "
              "outermost layer takes " << J["owner"].get<std::string>() << "'s outermost shell ("
           << J["shell"].get<std::string>() << ") and one map is inferred over the rows of all of them ("
           << count(J["rows"]["shared_system"].get<double>()) << " rows; "
           << count(J["rows"]["own_systems_together"].get<double>()) << " in the separate systems together), with "
              "disocclusion prevention as the multi-layer EMs. Texture memory per sample: "
           << count(J["texture_bytes_per_sample"]["shared"].get<double>()) << " bytes shared against "
           << count(J["texture_bytes_per_sample"]["own"].get<double>()) << " with a map each. The outer layers hold:";
        for (const auto& [name, objs] : J["outer_layer_members"].items()) {
            md << " " << name << " [";
            for (size_t i = 0; i < objs.size(); ++i) md << (i ? " " : "") << objs[i].get<std::string>();
            md << "]";
        }
        md << " (the clustering is per object, so the shared map also reconciles different members).\n\n";
        demos::Table t{{"view", "own outer layers", "one shared outer layer"}, {}};
        for (const char* v : {"between", "above"})
            t.rows.push_back({v, num(J["psnr_db"][v]["own"].get<double>()) + " / " + num(J["ssim"][v]["own"].get<double>(), 3),
                              num(J["psnr_db"][v]["shared"].get<double>()) + " / " + num(J["ssim"][v]["shared"].get<double>(), 3)});
        rep.table(t);
        md << "PSNR (dB) / SSIM over the lens pixels against the ray tracer.\n\n";
    } else if (r.contains("shared_distant_layers_left_out")) {
        rep.heading("Shared distant layers (000 §4.3)");
        md << "Left out in this run: " << r["shared_distant_layers_left_out"].get<std::string>() << ".\n\n";
    }
    rep.figure("figure8_novel_views.png", "Figure 8: novel views (a) between samples in the plane, (b) above it; ray traced, hybrid multi-layer, hybrid single layer (the last two on the emulated GeForce 256).");
    rep.figure("figure2_shading_models.png", "Figure 2: (a) the full ray tree, (b) the two-term greedy paths (ray counts below the lens objects).");
    rep.figure("figure5_subdivision_levels.png", "Figure 5: adaptive tessellation, shaded darker with each subdivision level.");
    rep.figure("figure7_layers.png", "Figure 7: the teapot's layers at the sample: b_R, b_T and the inferred EM x (finest MIPMAP level; cube faces +X −X +Y −Y +Z −Z, or the quad's texture).");
    rep.figure("figure9_disocclusion.png", "Figure 9: EM disocclusion (a) with and (b) without prevention, (c) prevention with 000 §4.3's direct images of the environment.");
    rep.figure("figure10_tau.png", "Figure 10: ray traced, τ = 3, τ = 5.");
    rep.figure("error_maps.png", "Per-pixel error against the ray tracer over the lens pixels (black 0 → blue → green → yellow → red → white 0.25).");
    rep.heading("Layers (000 §4.2)");
    for (const auto& [name, c] : clusteringJson.items()) {
        md << "- **" << name << "**, " << c["requested_layers"].get<int>() << " layers asked:";
        for (const auto& l : c["layers"]) {
            md << " [" << l["shell"].get<std::string>() << ":";
            for (const auto& o : l["objects"]) md << " " << o.get<std::string>();
            md << "]";
        }
        md << " (LBG " << c["lbg_iterations"].get<int>() << " rounds over " << c["records"].get<size_t>() << " intersections)\n";
    }
    md << "\n";
    rep.heading("Choices where the paper is silent");
    md << "- **Passes.** Premultiplied texels; stage 0 MODULATE(TEXTURE, DIFFUSE = F·G), stage 1 "
          "MODULATE(CURRENT, TFACTOR = the sample's weight) when blending; blending INVDESTALPHA/ONE "
          "composites the layers front to back. Destination alpha must restart for every (term, "
          "sample) sequence, so blending two samples takes 3 alpha clears for a glass object, 1 for a mirror "
          "(the paper names the one before the second term).\n"
       << "- **Layers.** LBG starts from the distances' quantiles (the paper: random); the "
          "environment (a ray meeting nothing) joins the outermost layer. Shells: teapot quad, cylinder, "
          "sphere as in §6; otherwise the outermost is a sphere, a layer in one direction a quad, a ring of "
          "tall objects a cylinder, else a sphere. The quad is a 2D texture; cubes elsewhere.\n"
       << "- **Inference.** b premultiplied, each ray's colour clipped to [0, 1]; rows only where every "
          "ray of the pixel reached the object with a valid path of the term (confidence 0 otherwise); "
          "pem's regulariser (λ " << S.pre.inference.smoothness << ", level coupling " << S.pre.inference.levelCoupling
       << ", prior " << S.pre.inference.prior << "), CG, bounds pinned.\n"
       << "- **Disocclusion prevention.** Ray continuation (incoming and outgoing) and " << S.neighbourViews
       << " viewpoints stacked per sample over " << num(S.neighbourSpanDegrees, 1) << "° of azimuth; without it: "
          "first hits only and the sample's own view. Direct images (000 §4.3) are a further variant, "
          "below.\n"
       << "- **Vertex paths.** From the welded vertex with its normal (midpoints: normalised sum); a normal "
          "facing away from the eye is tilted to d·n = −0.02; the visibility ray and the paths see the lens "
          "objects only; an invalid path has F·G = 0 and borrows the other term's exit for its coordinates.\n"
       << "- **τ** is measured in subpixels of the " << n << "×" << n << " grid the device draws; a split "
          "cuts the triangle's edges longer than τ (1-to-4, 1-to-3 along the shorter diagonal, 1-to-2); "
          "levels are capped at " << ts.maxLevel << ".\n"
       << "- **Reference.** raycore's greedy two-term tracer (exit radiance Whitted-traced), " << n << "×" << n
       << " rays per pixel; the table's uniform ray tracer is the same render.\n"
       << "- **Popping** is the mean change over lens pixels between the nearest-sample frames just before and "
          "after the midpoint (±0.25°), minus the ray tracer's change there. **Edge error**: lens pixels within "
          "2 pixels of a silhouette or where the ray tracer's paths diverge inside the pixel.\n"
       << "- **Claims' margins.** PSNR orderings by " << num(kMarginDb, 1) << " dB, over twice the "
       << num(kViewSpreadDb, 1) << " dB a change of view alone moves one technique's PSNR at quick quality "
          "(multi-layer on the sample against between samples); τ = 3 \"at least as good\" as τ = 5 allows a "
          "deficit within that spread. Popping by 0.5 8-bit levels, twice the multi-layer frames' own excess "
          "change (0.22); edge error by 0.25 levels, the mean error 8-bit rounding alone adds. Ray and test "
          "counts are exact: \"several times\" is at least 2×, and the heavier environment must raise the "
          "test reduction by 0.5×. The two-term model within 30 dB of the full tree, 5 dB better than the "
          "frame's own agreement with the ray tracer.\n\n";
    rep.heading("Left out");
    md << "- **A 1D texture for G** (§3, [11]): F·G is interpolated per vertex in the diffuse colour, 8 bits.\n"
       << "\n";
    r["seconds_total"] = since(tStart);
    r = rep.write(out, r);
    std::printf("hybrid: between PSNR multi %.2f, single %.2f, without prevention %.2f, tau5 %.2f; above multi %.2f single %.2f\n",
                mid.scores["multi_layer"].psnr, mid.scores["single_layer"].psnr, mid.scores["without_prevention"].psnr,
                mid.scores["multi_layer_tau_fast"].psnr, above.scores["multi_layer"].psnr, above.scores["single_layer"].psnr);
    std::printf("hybrid: wrote %s (%.1f s)\n", (out / "report.md").string().c_str(), since(tStart));
    return r;
}

// ---- the registry entry -------------------------------------------------------------------

std::string HybridReproduction::paper() const {
    return "Hakura & Snyder, \"Realistic Reflections and Refractions on Graphics Hardware With "
           "Hybrid Rendering and Layered Environment Maps\", EGWR 2001";
}

nlohmann::json HybridReproduction::settings(demos::Quality quality) const {
    const HybridSettings s = settingsFor(quality);
    return {{"image_size", {s.pre.width, s.pre.height}}, {"subsamples", s.pre.subsample * s.pre.subsample},
            {"em_size", s.pre.emSize}, {"teapot_level", s.teapotLevel}, {"viewpoints", s.views},
            {"step_degrees", s.stepDegrees}, {"tau", {s.pre.tau, s.tauFast}},
            {"layers", {s.glassLayers, s.mirrorLayers}}};
}

nlohmann::json HybridReproduction::reproduce(const demos::ReproduceOptions& options) const {
    HybridSettings s = settingsFor(options.quality);
    s.threads = options.threads;
    return runHybrid(s, options);
}

const HybridReproduction& hybridReproduction() {
    static const HybridReproduction instance;
    return instance;
}

}  // namespace rg::hybrid
