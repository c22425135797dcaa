// The impostors reproduction: §8's frame rates in the paper's four configurations, the
// figures against the ray-traced reference, the searches checked against analytic shapes
// and Embree, the claims, the report.
#include "reproduce_impostors.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <numeric>
#include <random>
#include <thread>

#include "core/error.h"
#include "core/progress.h"
#include "figures.h"
#include "impostor_demo.h"
#include "impostor_height_programs.h"
#include "impostor_search_linear.h"
#include "reproduce_caustics.h"
#include "raycore/accel.h"
#include "raycore/builtin_scenes.h"
#include "raycore/camera.h"
#include "raycore/fresnel.h"
#include "raycore/metrics.h"
#include "raycore/render.h"
#include "raycore/tracer_whitted.h"
#include "rasterizer/programmable_device.h"
#include "report.h"
#include "texunit/cube_mapping.h"

namespace fs = std::filesystem;

namespace rg::impostors {

namespace {

using Clock = std::chrono::steady_clock;
using demos::num;

// §8's frame rates on an Athlon 64 X2 4600+ with a GeForce 8800 GTX.
constexpr double kPaperStaticFps = 75.0, kPaperClassicalFps = 1.8, kPaperSeparatedFps = 11.3,
                 kPaperSeparated512Fps = 7.5;

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Fit {
    double slope = 0, intercept = 0, r2 = 0;
};
Fit fitLine(const std::vector<double>& x, const std::vector<double>& y) {
    const double n = double(x.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < x.size(); ++i) sx += x[i], sy += y[i], sxx += x[i] * x[i], sxy += x[i] * y[i];
    Fit f;
    const double den = n * sxx - sx * sx;
    f.slope = den != 0 ? (n * sxy - sx * sy) / den : 0.0;
    f.intercept = (sy - f.slope * sx) / n;
    double ssRes = 0, ssTot = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        const double e = y[i] - (f.intercept + f.slope * x[i]);
        ssRes += e * e;
        ssTot += (y[i] - sy / n) * (y[i] - sy / n);
    }
    f.r2 = ssTot > 0 ? 1.0 - ssRes / ssTot : 1.0;
    return f;
}


// The reference clamped to what an 8-bit frame holds.
ray::Image clamp01(ray::Image im) {
    for (float& v : im.pixels) v = std::clamp(v, 0.0f, 1.0f);
    return im;
}

// Per pixel the object the camera ray through the pixel's centre meets (−1: none).
std::vector<int> primaryObjects(const ray::Accel& accel, const ray::Camera& cam, int w, int h) {
    std::vector<int> out(size_t(w) * size_t(h), -1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const ray::Hit hit = accel.intersect(ray::primaryRay(cam, w, h, float(x) + 0.5f, float(y) + 0.5f));
            if (hit.valid()) out[size_t(y) * size_t(w) + size_t(x)] = int(hit.object);
        }
    return out;
}

struct Scores {
    double psnrAll = 0, ssimAll = 0, psnrGlass = 0, ssimGlass = 0;
    int64_t glassPixels = 0;
};
Scores scoreAgainst(const ray::Image& truth, const ray::Image& ours, const ray::Image& glassMask) {
    Scores s;
    const ray::Image all(truth.width, truth.height, 1, 1.0f);
    const ray::MaskedScore a = ray::compareMasked(truth, ours, all, "impostors: the whole frame");
    const ray::MaskedScore g = ray::compareMasked(truth, ours, glassMask, "impostors: the glass pixels");
    s.psnrAll = a.psnr;
    s.ssimAll = a.ssim;
    s.psnrGlass = g.psnr;
    s.ssimGlass = g.ssim;
    s.glassPixels = g.pixels;
    return s;
}
nlohmann::json scoresJson(const Scores& s) {
    return {{"psnr_db", s.psnrAll}, {"ssim", s.ssimAll}, {"glass_psnr_db", s.psnrGlass}, {"glass_ssim", s.ssimGlass},
            {"glass_pixels", s.glassPixels}};
}

// A nearest-texel cube map of a box room [lo, hi] seen from the origin: distance only.
struct AnalyticRoom {
    glm::vec3 lo, hi;
    int n;
    std::vector<float> dist;  // 6 faces × n²
    float hitDistance(const glm::vec3& o, const glm::vec3& d) const {
        float t = 1e30f;
        for (int a = 0; a < 3; ++a) {
            if (d[a] > 0) t = std::min(t, (hi[a] - o[a]) / d[a]);
            if (d[a] < 0) t = std::min(t, (lo[a] - o[a]) / d[a]);
        }
        return t;
    }
    AnalyticRoom(glm::vec3 l, glm::vec3 h, int size) : lo(l), hi(h), n(size), dist(size_t(6) * size_t(size) * size_t(size)) {
        for (int f = 0; f < 6; ++f)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const glm::vec3 dir = glm::normalize(
                        tex::cubeFaceDirection(tex::CubeFace(f), (float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n)));
                    dist[(size_t(f) * size_t(n) + size_t(y)) * size_t(n) + size_t(x)] = hitDistance(glm::vec3(0.0f), dir);
                }
    }
    // The device's point sampling of a cube map (NearestFloat2D::fetchCube).
    float fetch(const glm::vec3& d) const {
        const tex::CubeCoord c = tex::selectCubeFace(d);
        auto texel = [&](float v) { return std::clamp(int(std::floor(v * float(n))), 0, n - 1); };
        return dist[(size_t(int(c.face)) * size_t(n) + size_t(texel(c.t))) * size_t(n) + size_t(texel(c.s))];
    }
};

}  // namespace

AnalyticErrors analyticSearchErrors(int size, int maxIterations, int rays, uint32_t seed) {
    // A room 8 × 5 × 8 around the reference point, off centre; rays from points within 0.6
    // of the reference point (all inside the room, as a glass object's surface points are
    // inside its environment).
    const AnalyticRoom room({-3.0f, -0.8f, -2.5f}, {5.0f, 4.2f, 5.5f}, size);
    std::mt19937 rng(seed);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    AnalyticErrors e;
    e.meanError.assign(size_t(maxIterations) + 1, 0.0);
    auto fetch = [&](const Vec3L<float>& d, bool) {
        return Vec4L<float>(0.0f, 0.0f, 0.0f, room.fetch(glm::vec3(d.x, d.y, d.z)));
    };
    int bracketed = 0;
    for (int r = 0; r < rays; ++r) {
        glm::vec3 o(g(rng), g(rng), g(rng));
        o = glm::normalize(o) * (0.6f * std::cbrt(u(rng)));
        glm::vec3 d = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        const float truth = room.hitDistance(o, d);
        const Vec3L<float> x(o.x, o.y, o.z), R(d.x, d.y, d.z);
        for (int it = 0; it <= maxIterations; ++it) {
            const SearchResult<float, bool> s = secantSearch(x, R, it, true, fetch);
            e.meanError[size_t(it)] += std::fabs(double(s.d) - double(truth));
            if (it == maxIterations) bracketed += s.bracketed;
        }
        // Classical environment mapping: the surface seen from o along R, distance from x.
        const glm::vec3 rp = d * room.fetch(d);
        e.classicalError += double(glm::length(rp - o) - truth) * (glm::length(rp - o) > truth ? 1.0 : -1.0);
    }
    for (double& v : e.meanError) v /= double(rays);
    e.classicalError /= double(rays);
    e.bracketed = double(bracketed) / double(rays);
    return e;
}

ImpostorReproduceSettings impostorSettingsFor(demos::Quality quality) {
    ImpostorReproduceSettings s;
    if (quality == demos::Quality::Paper) {
        // §8: 600 × 600, environment maps 256² (and 512²).
        s.imageSize = 600;
        s.envSize = 256;
        s.envSizeLarge = 512;
        s.refractorSize = 256;
        s.heightMapSize = 512;
        s.timedFrames = 5;
        s.classicalFrames = 2;
        s.analyticRays = 20000;
        s.outsideRays = 20000;
        s.causticReferencePhotons = 256;
    }
    return s;
}

nlohmann::json runImpostors(const ImpostorReproduceSettings& S, const demos::ReproduceOptions& options) {
    const auto tStart = Clock::now();
    const fs::path out = options.outDir;
    fs::create_directories(out);
    const Path rasterPath = options.referencePath ? Path::Reference : Path::Fast;
    const int threads = S.threads;
    demos::Report rep(impostorReproduction(), options.quality);
    nlohmann::json r;
    Progress progress("impostors", 11);

    // ---- the scenes --------------------------------------------------------------------------
    const bool builtIn = options.scene.empty();
    ChessOptions co;
    co.segments = S.segments;
    co.sphereSlices = S.sphereSlices;
    const ImpostorScene scene = builtIn ? makeChessScene(co) : impostorSceneFromFile(options.scene, options.mover);
    for (const std::string& w : scene.warnings) std::printf("impostors: warning: %s\n", w.c_str());
    ChessOptions cm = co;
    cm.mirrorMover = true;
    const ImpostorScene mirrorScene = builtIn ? makeChessScene(cm) : scene;
    r["scene"] = {{"description", scene.description},
                  {"glass_objects", scene.glass.size()},
                  {"vertices", scene.vertices},
                  {"faces", scene.faces},
                  {"paper_vertices", 30838},
                  {"paper_faces", 47404}};

    ImpostorRenderer renderer(scene, threads, rasterPath);
    ImpostorSettings base;
    base.width = base.height = S.imageSize;
    base.envSize = S.envSize;
    base.refractorSize = S.refractorSize;
    base.depth = S.depth;
    base.iterations = S.iterations;

    // ---- Figure 2: the secant search on an analytic distance map -----------------------------
    // A fine map (1024² faces), so that the point sampling's staircase (half a texel) is
    // below what the iterations remove.
    const int maxIt = 16, analyticSize = 1024;
    const AnalyticErrors analytic = analyticSearchErrors(analyticSize, maxIt, S.analyticRays);
    {
        std::vector<double> xs;
        for (int i = 0; i <= maxIt; ++i) xs.push_back(i);
        demos::writeLinePlot(out / "figure2_error_by_iterations.svg",
                  "Secant search on a box room's distance map (" + std::to_string(analyticSize) + "² faces)",
                  "secant iterations after p and l", "mean |d − d_true|", xs,
                  {{"secant search", "#c03030", analytic.meanError},
                   {"classical environment mapping", "#3060c0", std::vector<double>(xs.size(), analytic.classicalError)}});
        r["figure2"] = {{"map_size", analyticSize},
                        {"rays", S.analyticRays},
                        {"mean_error_by_iterations", analytic.meanError},
                        {"classical_env_mapping_error", analytic.classicalError},
                        {"bracketed_fraction", analytic.bracketed}};
    }
    progress.advance();

    // ---- §8's frame rates: static, classical, separated, separated with larger maps ----------
    auto timed = [&](ImpostorSettings s, int frames, bool moving) {
        s.moverU = 0.0f;
        renderer.render(scene.camera, s);  // warm-up: the maps this mode builds once
        std::vector<double> ms, mapsMs;
        std::map<std::string, std::vector<double>> passMs;
        ImpostorFrame last;
        for (int f = 0; f < frames; ++f) {
            s.moverU = moving ? float(f + 1) / float(frames + 1) : 0.0f;
            last = renderer.render(scene.camera, s);
            ms.push_back(last.totalMs);
            mapsMs.push_back(last.mapsMs);
            for (const PassTiming& p : last.passes) passMs[p.name].push_back(p.ms);
        }
        nlohmann::json j;
        j["frame_ms"] = median(ms);
        j["fps"] = 1000.0 / median(ms);
        j["maps_ms"] = median(mapsMs);
        j["frames"] = frames;
        for (auto& [name, v] : passMs) j["passes_ms"][name] = median(v);
        j["glass_fragments"] = last.glassFragments;
        j["fetches_per_glass_fragment"] = last.fetchesPerGlassFragment;
        j["impostors_rebuilt_per_frame"] = last.impostorsRebuilt;
        j["impostor_texels_per_frame"] = last.impostorTexels;
        return j;
    };
    nlohmann::json timing;
    {
        ImpostorSettings s = base;
        s.mode = Mode::Static;
        timing["static"] = timed(s, S.timedFrames, false);
        progress.advance();
        s.mode = Mode::Separated;
        timing["separated"] = timed(s, S.timedFrames, true);
        s.envSize = S.envSizeLarge;
        timing["separated_large_maps"] = timed(s, S.timedFrames, true);
        progress.advance();
        s = base;
        s.mode = Mode::Classical;
        timing["classical"] = timed(s, S.classicalFrames, true);
        progress.advance();
    }
    timing["paper_fps"] = {{"static", kPaperStaticFps},
                           {"classical", kPaperClassicalFps},
                           {"separated", kPaperSeparatedFps},
                           {"separated_large_maps", kPaperSeparated512Fps}};
    const double fpsStatic = timing["static"]["fps"], fpsSep = timing["separated"]["fps"],
                 fpsClassical = timing["classical"]["fps"], fpsLarge = timing["separated_large_maps"]["fps"];
    timing["ratios"] = {{"static_over_separated", fpsStatic / fpsSep},
                        {"separated_over_classical", fpsSep / fpsClassical},
                        {"small_over_large_maps", fpsSep / fpsLarge},
                        {"paper_static_over_separated", kPaperStaticFps / kPaperSeparatedFps},
                        {"paper_separated_over_classical", kPaperSeparatedFps / kPaperClassicalFps},
                        {"paper_small_over_large_maps", kPaperSeparatedFps / kPaperSeparated512Fps}};
    r["timing"] = timing;

    // ---- §7: caustics against photon tracing ---------------------------------------------------
    // Ours in their own renderer (caustics change the board, so every impostor; the frames
    // compared with Whitted tracing above and below keep them off: it has none).
    nlohmann::json caustics;
    if (S.caustics) {
        const CausticsComparison cc = compareCaustics(scene, base, 0.0f, S.causticReferencePhotons, threads, rasterPath);
        caustics = cc.json;
        const double peak = std::max(1e-6, caustics["scores"]["reference_max_irradiance"].get<double>());
        // A light map with `white` as white, clamped.
        auto scaled = [](const ray::Image& im, double white) {
            ray::Image o(im.width, im.height, 3);
            for (int y = 0; y < im.height; ++y)
                for (int x = 0; x < im.width; ++x) o.setRgb(x, y, glm::min(im.rgb(x, y) * float(1.0 / white), glm::vec3(1.0f)));
            return o;
        };
        // Shown with a quarter of the reference's largest irradiance as white, so that the
        // pieces' weaker caustics show beside the sphere's focus.
        auto shown = [&](const ray::Image& im) { return scaled(im, 0.25 * peak); };
        ray::writeImage(out / "caustics.png",
                        demos::labelledGrid({{cc.shadows, "shadows: light maps (visibility)"},
                                             {shown(cc.ours), "caustics: ours (photon maps, splats)"},
                                             {shown(cc.reference), "caustics: photon-traced reference"},
                                             {ray::errorHeatMap(shown(cc.reference), shown(cc.ours), 0.5f),
                                              "|difference|, 0 to 1/8 of the peak"}},
                                            2));
        r["caustics"] = caustics;
        // The mirror pawn of Figure 9 alone on the board (§7: "refracting and reflecting
        // materials can focus the light"): its reflection caustic, which beside the sphere's
        // focus would fall under the peaks' 1/10 floor, against the reference.
        if (builtIn) {
            std::vector<uint32_t> keep;
            int moverAt = -1;
            for (uint32_t i = 0; i < mirrorScene.scene.objects.size(); ++i) {
                const ray::MaterialType t = mirrorScene.scene.materials[mirrorScene.scene.objects[i].material].type;
                if (int(i) == mirrorScene.mover) moverAt = int(keep.size());
                if (int(i) == mirrorScene.mover || t == ray::MaterialType::Diffuse) keep.push_back(i);
            }
            ImpostorScene alone = mirrorScene;
            alone.scene = ray::subScene(mirrorScene.scene, keep);
            alone.mover = moverAt;
            indexGlass(alone);
            const CausticsComparison mc = compareCaustics(alone, base, 0.0f, S.causticReferencePhotons, threads, rasterPath);
            const double mpeak = std::max(1e-6, mc.json["scores"]["reference_max_irradiance"].get<double>());
            auto shownMirror = [&](const ray::Image& im) { return scaled(im, mpeak); };
            ray::writeImage(out / "caustics_mirror.png",
                            demos::labelledGrid({{shownMirror(mc.ours), "the mirror pawn's caustic: ours"},
                                                 {shownMirror(mc.reference), "photon-traced reference"},
                                                 {ray::errorHeatMap(shownMirror(mc.reference), shownMirror(mc.ours), 0.5f),
                                                  "|difference|, 0 to 1/2 of the peak"}},
                                                3));
            r["caustics_mirror"] = mc.json;
        }
    }

    // ---- Figure 10 (left) and the whole scene against the ray tracer -------------------------
    const float uImage = 0.5f;
    auto reference = [&](const ImpostorScene& sc, const ray::Camera& cam, float u, int depth) {
        const ray::Scene at = sc.at(u);
        ray::Accel accel(at);
        ray::RenderOptions ro;
        ro.width = ro.height = S.imageSize;
        ro.spp = 1;
        ro.maxDepth = depth;
        ro.threads = threads;
        return clamp01(ray::renderWhitted(accel, cam, ro));
    };
    auto glassMaskOf = [&](const ImpostorScene& sc, const ray::Camera& cam, float u, std::vector<int>* objects = nullptr) {
        const ray::Scene at = sc.at(u);
        ray::Accel accel(at);
        const std::vector<int> obj = primaryObjects(accel, cam, S.imageSize, S.imageSize);
        ray::Image m(S.imageSize, S.imageSize, 1);
        for (int y = 0; y < S.imageSize; ++y)
            for (int x = 0; x < S.imageSize; ++x) {
                const int o = obj[size_t(y) * size_t(S.imageSize) + size_t(x)];
                m.at(x, y, 0) = o >= 0 && std::find(sc.glass.begin(), sc.glass.end(), uint32_t(o)) != sc.glass.end();
            }
        if (objects) *objects = obj;
        return m;
    };
    const ray::Image refWhole = reference(scene, scene.camera, uImage, S.referenceDepth);
    const ray::Image maskWhole = glassMaskOf(scene, scene.camera, uImage);
    std::map<std::string, ray::Image> images;
    nlohmann::json quality;
    for (Mode m : {Mode::Static, Mode::Separated, Mode::Classical}) {
        ImpostorSettings s = base;
        s.mode = m;
        s.moverU = uImage;
        renderer.render(scene.camera, s);
        images[modeName(m)] = renderer.frame();
        quality[modeName(m)] = scoresJson(scoreAgainst(refWhole, images[modeName(m)], maskWhole));
    }
    ray::writeImage(out / "figure10_whole_scene.png",
                    demos::labelledGrid({{images["separated"], "ours (separated, DEPTH " + std::to_string(S.depth) + ")"},
                                         {refWhole, "Whitted ray tracing, depth " + std::to_string(S.referenceDepth)},
                                         {ray::errorHeatMap(refWhole, images["separated"], 0.25f), "|difference|, 0 to 0.25"}},
                                        3));
    // Where the refracted ray reflects totally at its exit: ours (the exit point and normal
    // the refractor distance map gives, Figure 5's 4 searches) against the ray tracer's first
    // exit from the same glass object along the same primary ray. A distance map from the
    // centre holds one surface per direction; the pieces are lathes with necks and collars,
    // not star-shaped about it (what §6's height maps are for).
    nlohmann::json exitTir;
    {
        ImpostorSettings s = base;
        s.mode = Mode::Static;
        s.moverU = uImage;
        s.diagnostics = true;
        renderer.render(scene.camera, s);
        const ImpostorRenderer::Diagnostics d = renderer.readDiagnostics();
        const ray::Image oursImage = renderer.frame();
        glm::dvec3 oursMean(0.0), tracedMean(0.0);
        const ray::Scene at = scene.at(uImage);
        ray::Accel accel(at);
        int64_t glassPx = 0, ours = 0, traced = 0, both = 0;
        for (int y = 0; y < S.imageSize; ++y)
            for (int x = 0; x < S.imageSize; ++x) {
                const ray::Ray pr = ray::primaryRay(scene.camera, S.imageSize, S.imageSize, float(x) + 0.5f, float(y) + 0.5f);
                const ray::Hit h = accel.intersect(pr);
                if (!h.valid()) continue;
                const ray::SurfacePoint sp = accel.surface(pr, h);
                if (sp.material->type != ray::MaterialType::Glass || d.searches.rgb(x, y).x < 3.0f) continue;
                glm::vec3 t;
                if (!ray::refractDir(pr.dir, sp.frontFace ? sp.ns : -sp.ns, 1.0f / sp.material->ior, &t)) continue;
                ++glassPx;
                oursMean += glm::dvec3(glm::min(oursImage.rgb(x, y), glm::vec3(1.0f)));
                tracedMean += glm::dvec3(refWhole.rgb(x, y));
                const bool oursTir = d.searches.rgb(x, y).x >= 4.0f;
                ray::Ray in;
                in.dir = t;
                in.origin = accel.offsetOrigin(sp, t);
                const ray::Hit h2 = accel.intersect(in);
                bool tracedTir = false;
                if (h2.valid()) {
                    const ray::SurfacePoint s2 = accel.surface(in, h2);
                    glm::vec3 t2;
                    tracedTir = !ray::refractDir(t, s2.frontFace ? s2.ns : -s2.ns,
                                                 s2.frontFace ? 1.0f / s2.material->ior : s2.material->ior, &t2);
                }
                ours += oursTir;
                traced += tracedTir;
                both += oursTir && tracedTir;
            }
        const double n = double(std::max<int64_t>(glassPx, 1));
        exitTir = {{"glass_pixels", glassPx},
                   {"ours_fraction", double(ours) / n},
                   {"ray_tracer_fraction", double(traced) / n},
                   {"both_fraction", double(both) / n},
                   {"ours_mean_rgb", {oursMean.x / n, oursMean.y / n, oursMean.z / n}},
                   {"ray_tracer_mean_rgb", {tracedMean.x / n, tracedMean.y / n, tracedMean.z / n}}};
    }
    r["exit_total_reflection"] = exitTir;
    progress.advance();

    // ---- §6: refractor height maps against refractor distance maps ---------------------------
    // The same static frames with the refracted ray's exit found in each glass object's
    // refractor height map (§6) instead of its refractor distance map (§3), over a few views
    // of the whole scene: the glass PSNR against the ray tracer, and where the exit reflects
    // totally, ours against the ray tracer's first exit along the same primary ray.
    nlohmann::json heightJ;
    std::vector<double> psnrDistanceByView, psnrHeightByView;
    // The views of the whole scene with their references and glass masks, kept for the DEPTH
    // sweep below (the impostors do not depend on the camera, so more views cost frames only).
    struct DollyView {
        ray::Camera cam;
        ray::Image ref, mask;
    };
    std::vector<DollyView> dollyViews;
    {
        const ray::Scene at = scene.at(uImage);
        ray::Accel accel(at);
        // Per glass pixel whose primary hit refracts: does the exit reflect totally — ours
        // (target 3 counts 4 searches there), the ray tracer's first exit.
        struct ExitTir {
            int64_t pixels = 0, ours = 0, traced = 0, both = 0;
        };
        auto exitTirOf = [&](const ray::Camera& cam, const ImpostorRenderer::Diagnostics& d) {
            ExitTir e;
            for (int y = 0; y < S.imageSize; ++y)
                for (int x = 0; x < S.imageSize; ++x) {
                    const ray::Ray pr = ray::primaryRay(cam, S.imageSize, S.imageSize, float(x) + 0.5f, float(y) + 0.5f);
                    const ray::Hit h = accel.intersect(pr);
                    if (!h.valid()) continue;
                    const ray::SurfacePoint sp = accel.surface(pr, h);
                    if (sp.material->type != ray::MaterialType::Glass || d.searches.rgb(x, y).x < 3.0f) continue;
                    glm::vec3 t;
                    if (!ray::refractDir(pr.dir, sp.frontFace ? sp.ns : -sp.ns, 1.0f / sp.material->ior, &t)) continue;
                    ++e.pixels;
                    const bool oursTir = d.searches.rgb(x, y).x >= 4.0f;
                    ray::Ray in;
                    in.dir = t;
                    in.origin = accel.offsetOrigin(sp, t);
                    const ray::Hit h2 = accel.intersect(in);
                    bool tracedTir = false;
                    if (h2.valid()) {
                        const ray::SurfacePoint s2 = accel.surface(in, h2);
                        glm::vec3 t2;
                        tracedTir = !ray::refractDir(t, s2.frontFace ? s2.ns : -s2.ns,
                                                     s2.frontFace ? 1.0f / s2.material->ior : s2.material->ior, &t2);
                    }
                    e.ours += oursTir;
                    e.traced += tracedTir;
                    e.both += oursTir && tracedTir;
                }
            return e;
        };
        auto tirJson = [](const ExitTir& e) {
            const double n = double(std::max<int64_t>(e.pixels, 1));
            return nlohmann::json{{"glass_pixels", e.pixels},
                                  {"ours_fraction", double(e.ours) / n},
                                  {"ray_tracer_fraction", double(e.traced) / n},
                                  {"both_fraction", double(e.both) / n}};
        };
        nlohmann::json views = nlohmann::json::array();
        std::vector<demos::Cell> closeCells;
        ray::Image firstView[2];  // the first view's frames, distance map and height map (split by exit face below)
        for (size_t vi = 0; vi < S.heightViews.size(); ++vi) {
            ray::Camera cam = scene.camera;
            cam.eye = cam.target + (scene.camera.eye - scene.camera.target) * S.heightViews[vi];
            const ray::Image ref = vi == 0 && S.heightViews[vi] == 1.0f ? refWhole : reference(scene, cam, uImage, S.referenceDepth);
            const ray::Image mask = glassMaskOf(scene, cam, uImage);
            dollyViews.push_back({cam, ref, mask});
            nlohmann::json v;
            v["distance_factor"] = S.heightViews[vi];
            ray::Image shown[2];
            for (Exit e : {Exit::DistanceMap, Exit::HeightMap}) {
                ImpostorSettings s = base;
                s.mode = Mode::Static;
                s.moverU = uImage;
                s.diagnostics = true;
                s.exit = e;
                s.heightMapSize = S.heightMapSize;
                s.heightSteps = S.heightSteps;
                renderer.render(cam, s);
                const ray::Image im = renderer.frame();
                const Scores sc = scoreAgainst(ref, im, mask);
                nlohmann::json j = scoresJson(sc);
                j["exit_total_reflection"] = tirJson(exitTirOf(cam, renderer.readDiagnostics()));
                v[exitName(e)] = j;
                (e == Exit::HeightMap ? psnrHeightByView : psnrDistanceByView).push_back(sc.psnrGlass);
                shown[e == Exit::HeightMap] = im;
                if (vi == 0) firstView[e == Exit::HeightMap] = im;
            }
            if (vi + 1 == S.heightViews.size())
                closeCells = {{shown[0], "exit: refractor distance map"},
                              {shown[1], "exit: refractor height map"},
                              {ref, "Whitted ray tracing"},
                              {ray::errorHeatMap(ref, shown[0], 0.25f), "|difference|, distance map"},
                              {ray::errorHeatMap(ref, shown[1], 0.25f), "|difference|, height map"}};
            views.push_back(v);
        }
        heightJ["views"] = views;
        ray::writeImage(out / "figure10_double_refraction.png", demos::labelledGrid(closeCells, 3));
        // Figure 6: the maps themselves.
        std::vector<demos::Cell> maps;
        for (int m = 0; m < renderer.refractorMaps(); ++m)
            maps.push_back({renderer.heightMapImage(m), "height map: " + scene.scene.meshes[renderer.refractorMesh(m)].name});
        ray::writeImage(out / "figure6_height_maps.png", demos::labelledGrid(maps, 2));
        // Figure 7: the cases of the exit searches over the whole view's glass pixels, on the
        // scalar twin (the primary hit from Embree, the maps read back through the device's
        // point sampling).
        {
            tex::SamplerState point;
            point.magFilter = point.minFilter = tex::FilterMode::Nearest;
            point.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                             tex::AddressMode::ClampToEdge};
            int64_t cases[5] = {0, 0, 0, 0, 0}, retried = 0, unfound = 0, searched = 0;
            std::vector<double> exitErrH, exitErrD;
            int64_t normalOffH = 0, normalOffD = 0, normalOffHFlat = 0, flatExits = 0, compared = 0;
            // The glass pixels of the first view by the face their refracted ray first leaves
            // through (Embree's): flat (|n_y| > 0.9: the bases and tops a height map sees
            // edge-on) or curved (the lathes' sides, what a height map holds).
            ray::Image flatExitMask(S.imageSize, S.imageSize, 1), curvedExitMask(S.imageSize, S.imageSize, 1);
            for (int y = 0; y < S.imageSize; ++y)
                for (int x = 0; x < S.imageSize; ++x) {
                    const ray::Ray pr = ray::primaryRay(scene.camera, S.imageSize, S.imageSize, float(x) + 0.5f, float(y) + 0.5f);
                    const ray::Hit h = accel.intersect(pr);
                    if (!h.valid()) continue;
                    const auto gi = std::find(scene.glass.begin(), scene.glass.end(), h.object);
                    if (gi == scene.glass.end()) continue;
                    const ray::SurfacePoint sp = accel.surface(pr, h);
                    if (sp.material->type != ray::MaterialType::Glass) continue;
                    const int g = int(gi - scene.glass.begin());
                    const int map = renderer.refractorOf(g);
                    const raster::detail::NearestFloat2D nf = raster::detail::nearestFloat2D(&renderer.heightTexture(map), point);
                    auto fetch = [&nf](float u, float v, bool live) {
                        if (!live) return Vec4L<float>(0.0f, 0.0f, 0.0f, 0.0f);
                        const glm::vec4 t = nf.fetch(u, v);
                        return Vec4L<float>(t.x, t.y, t.z, t.w);
                    };
                    const HeightPaths<float, bool> hp =
                        tracePathsHeight(renderer.frames()[size_t(g)], renderer.heightFrame(map), Vec3L<float>(sp.p.x, sp.p.y, sp.p.z),
                                         Vec3L<float>(sp.ns.x, sp.ns.y, sp.ns.z), Vec3L<float>(pr.dir.x, pr.dir.y, pr.dir.z),
                                         true, fetch);
                    ++searched;
                    ++cases[std::clamp(int(hp.segmentCase), 0, 4)];
                    retried += hp.retried;
                    unfound += hp.unfound;
                    // The first exit of the refracted ray, each map's against Embree's along the
                    // same ray: the point, and whether the normal is off by more than 10°.
                    glm::vec3 T;
                    if (!ray::refractDir(pr.dir, sp.frontFace ? sp.ns : -sp.ns, 1.0f / sp.material->ior, &T)) continue;
                    ray::Ray in;
                    in.dir = T;
                    in.origin = accel.offsetOrigin(sp, T);
                    const ray::Hit h2 = accel.intersect(in);
                    if (!h2.valid() || h2.object != h.object) continue;
                    const ray::SurfacePoint s2 = accel.surface(in, h2);
                    const glm::vec3 xTrue = s2.p, nTrue = s2.ns;
                    const ObjectFrame& of = renderer.frames()[size_t(g)];
                    const Vec3L<float> c(of.centre[0], of.centre[1], of.centre[2]);
                    const Vec3L<float> xl = mul3(of.toLocal, Vec3L<float>(sp.p.x, sp.p.y, sp.p.z) - c);
                    const Vec3L<float> tl = mul3(of.toLocal, Vec3L<float>(T.x, T.y, T.z));
                    const HeightHit<float, bool> hh = heightSearch(renderer.heightFrame(map), xl, tl, true, true, fetch);
                    const Vec3L<float> xh = c + mulT3(of.toLocal, hh.point), nh = mulT3(of.toLocal, normalize3(hh.normal));
                    const raster::detail::NearestFloat2D nc = raster::detail::nearestFloat2D(&renderer.refractorTexture(map), point);
                    auto cubeFetch = [&nc](const Vec3L<float>& d, bool live) {
                        if (!live) return Vec4L<float>(0.0f, 0.0f, 0.0f, 0.0f);
                        const glm::vec4 t = nc.fetchCube(glm::vec3(d.x, d.y, d.z));
                        return Vec4L<float>(t.x, t.y, t.z, t.w);
                    };
                    const SearchResult<float, bool> sd = secantSearch(xl, tl, S.iterations, true, cubeFetch, /*seeded=*/true);
                    const Vec3L<float> xd = c + mulT3(of.toLocal, sd.point),
                                       nd = mulT3(of.toLocal, normalize3(Vec3L<float>(sd.texel.x, sd.texel.y, sd.texel.z)));
                    auto dist = [&](const Vec3L<float>& a) { return double(glm::length(glm::vec3(a.x, a.y, a.z) - xTrue)); };
                    auto off = [&](const Vec3L<float>& n) { return glm::dot(glm::vec3(n.x, n.y, n.z), nTrue) < 0.985f; };
                    exitErrH.push_back(dist(xh));
                    exitErrD.push_back(dist(xd));
                    normalOffH += off(nh);
                    normalOffD += off(nd);
                    // Faces seen edge-on from the plane's normal (flat tops and bases) are in no
                    // height map: the exits through them.
                    const bool flat = std::fabs(nTrue.y) > 0.9f;
                    flatExits += flat;
                    (flat ? flatExitMask : curvedExitMask).at(x, y, 0) = 1.0f;
                    normalOffHFlat += off(nh) && flat;
                    ++compared;
                }
            const double n = double(std::max<int64_t>(searched, 1));
            heightJ["figure7_exit_cases"] = {{"glass_pixels", searched},
                                             {"case_1", double(cases[1]) / n},
                                             {"case_2", double(cases[2]) / n},
                                             {"case_3", double(cases[3]) / n},
                                             {"case_3a", double(cases[4]) / n},
                                             {"missed_box", double(cases[0]) / n},
                                             {"mirrored_retry", double(retried) / n},
                                             {"no_crossing_found", double(unfound) / n}};
            auto med = [](std::vector<double> v) { return median(std::move(v)); };
            const double nc = double(std::max<int64_t>(compared, 1));
            heightJ["first_exit_against_embree"] = {{"rays", compared},
                                                    {"median_point_error_height_map", med(exitErrH)},
                                                    {"median_point_error_distance_map", med(exitErrD)},
                                                    {"normal_off_10deg_height_map", double(normalOffH) / nc},
                                                    {"normal_off_10deg_distance_map", double(normalOffD) / nc},
                                                    {"exits_through_flat_faces", double(flatExits) / nc},
                                                    {"normal_off_10deg_height_map_flat_faces", double(normalOffHFlat) / nc}};
            // The first view's glass PSNR split by that face, when the view is the whole
            // scene's (where the masks were taken).
            if (S.heightViews.front() == 1.0f && firstView[0].width == S.imageSize && firstView[1].width == S.imageSize) {
                nlohmann::json byFace;
                for (const auto& [name, mask] : {std::pair<const char*, const ray::Image*>{"flat", &flatExitMask},
                                                 std::pair<const char*, const ray::Image*>{"curved", &curvedExitMask}}) {
                    if (std::find(mask->pixels.begin(), mask->pixels.end(), 1.0f) == mask->pixels.end()) continue;
                    const Scores d = scoreAgainst(refWhole, firstView[0], *mask);
                    const Scores h = scoreAgainst(refWhole, firstView[1], *mask);
                    byFace[name] = {{"pixels", d.glassPixels},
                                    {"glass_psnr_distance_map_db", d.psnrGlass},
                                    {"glass_psnr_height_map_db", h.psnrGlass}};
                }
                heightJ["first_view_by_exit_face"] = byFace;
                // The same split as a picture: each glass pixel by its exit's face, and each
                // exit's error against the ray tracer.
                ray::Image faces(S.imageSize, S.imageSize, 3);
                for (int y = 0; y < S.imageSize; ++y)
                    for (int x = 0; x < S.imageSize; ++x) {
                        const glm::vec3 shade = glm::vec3(refWhole.rgb(x, y)) * 0.35f;  // the scene, dimmed
                        faces.setRgb(x, y, curvedExitMask.at(x, y, 0) > 0.5f ? glm::vec3(0.2f, 0.85f, 0.3f)
                                           : flatExitMask.at(x, y, 0) > 0.5f  ? glm::vec3(1.0f, 0.55f, 0.1f)
                                                                               : shade);
                    }
                ray::writeImage(out / "figure10_exit_faces.png",
                                demos::labelledGrid({{faces, "first exit (Embree): curved green, flat orange"},
                                                     {ray::errorHeatMap(refWhole, firstView[0], 0.25f), "|difference|, distance map"},
                                                     {ray::errorHeatMap(refWhole, firstView[1], 0.25f), "|difference|, height map"}},
                                                    3));
            }
        }
        // Frame time of the two exits (static: no map is rebuilt in the timed frames).
        for (Exit e : {Exit::DistanceMap, Exit::HeightMap}) {
            ImpostorSettings s = base;
            s.mode = Mode::Static;
            s.exit = e;
            s.heightMapSize = S.heightMapSize;
            s.heightSteps = S.heightSteps;
            nlohmann::json j = timed(s, S.timedFrames, false);
            heightJ["timing"][exitName(e)] = {{"frame_ms", j["frame_ms"]},
                                              {"glass_pass_ms", j["passes_ms"]["frame: glass (static)"]},
                                              {"fetches_per_glass_fragment", j["fetches_per_glass_fragment"]}};
        }
        // §5.2 with height maps: Figure 9's view (the mirror pawn moving, seen through the
        // sphere), separated, the static objects searching the mover's height map from
        // outside instead of its distance map.
        {
            ImpostorRenderer mr(mirrorScene, threads, rasterPath);
            const ray::Image ref = reference(mirrorScene, mirrorScene.closeUp, uImage, S.referenceDepth);
            const ray::Image mask = glassMaskOf(mirrorScene, mirrorScene.closeUp, uImage);
            for (Exit e : {Exit::DistanceMap, Exit::HeightMap}) {
                ImpostorSettings s = base;
                s.mode = Mode::Separated;
                s.moverU = uImage;
                s.exit = e;
                s.heightMapSize = S.heightMapSize;
                s.heightSteps = S.heightSteps;
                mr.render(mirrorScene.closeUp, s);
                heightJ["figure9_separated"][exitName(e)] = scoresJson(scoreAgainst(ref, mr.frame(), mask));
            }
        }
        heightJ["height_map_size"] = S.heightMapSize;
        heightJ["height_steps"] = S.heightSteps;
        heightJ["refractor_distance_map_size"] = S.refractorSize;
    }
    // The claim (§6, Figure 10 right): over every view, the height map's glass PSNR above the
    // distance map's, by a margin from the spread of the gain across the views (twice its
    // standard error: the gain is then unlikely to be one view's accident), and in the whole
    // view the total reflections at the exit closer to the ray tracer's share.
    {
        const size_t n = psnrHeightByView.size();
        std::vector<double> gain(n);
        double mean = 0, minGain = 1e30;
        for (size_t i = 0; i < n; ++i) {
            gain[i] = psnrHeightByView[i] - psnrDistanceByView[i];
            mean += gain[i] / double(n);
            minGain = std::min(minGain, gain[i]);
        }
        double var = 0;
        for (double g : gain) var += (g - mean) * (g - mean) / double(std::max<size_t>(n - 1, 1));
        const double margin = 2.0 * std::sqrt(var / double(n));
        const auto& v0 = heightJ["views"][0];
        const double tirRt = v0["height-map"]["exit_total_reflection"]["ray_tracer_fraction"];
        const double tirH = v0["height-map"]["exit_total_reflection"]["ours_fraction"];
        const double tirD = v0["distance-map"]["exit_total_reflection"]["ours_fraction"];
        demos::Claim c;
        c.id = "height_maps_beat_distance_maps_for_double_refraction";
        c.section = "§6, Figure 10";
        c.statement = "Refractor height maps represent the chess pieces (concave from their centres) better than "
                      "refractor distance maps, so the double refraction through them comes out closer to ray tracing";
        c.test = "glass PSNR (height map) − glass PSNR (distance map) > 0 dB in each of " + std::to_string(n) +
                 " views and its mean ≥ 2 × its standard error across the views (the margin, " + num(margin, 2) +
                 " dB here; the views are dollies of one scene, so this is their spread, not independent samples); and |TIR at the "
                 "exit − the ray tracer's| smaller with the height map (whole view)";
        c.measured = {{"glass_psnr_height_map_db", psnrHeightByView},
                      {"glass_psnr_distance_map_db", psnrDistanceByView},
                      {"mean_gain_db", mean},
                      {"margin_db", margin},
                      {"exit_tir_height_map", tirH},
                      {"exit_tir_distance_map", tirD},
                      {"exit_tir_ray_tracer", tirRt}};
        // Context, not the test: the first view split by the face the true exit is on.
        if (heightJ.contains("first_view_by_exit_face"))
            for (const auto& [face, j] : heightJ["first_view_by_exit_face"].items()) {
                c.measured["glass_psnr_" + face + "_exits_height_map_db"] = j["glass_psnr_height_map_db"];
                c.measured["glass_psnr_" + face + "_exits_distance_map_db"] = j["glass_psnr_distance_map_db"];
            }
        c.holds = n > 0 && minGain > 0.0 && mean >= margin && std::fabs(tirH - tirRt) < std::fabs(tirD - tirRt);
        heightJ["claim_gain_db"] = {{"mean", mean}, {"margin", margin}, {"min", minGain}};
        rep.claim(c);
    }
    r["height_maps"] = heightJ;
    progress.advance();

    // ---- DEPTH and iterations against the reference ------------------------------------------
    std::vector<double> psnrByDepth;
    nlohmann::json depthJ;
    // §5.1's claim is about the light paths a further DEPTH iteration adds: a glass object
    // seen in another's impostor, seen in a third's. Most glass pixels' paths meet one
    // object and then the board or the sky, and those do not change with DEPTH at all, so
    // over every glass pixel the claim drowns in the exit search's error, which DEPTH does
    // not touch (glass PSNR within 0.01 dB at quick quality). The claim is decided
    // on the glass pixels that the first and the last DEPTH of the sweep render differently
    // (any channel by more than one 8-bit level), over the dolly views of §6 (the closer
    // ones show the pieces inside pieces at more pixels): the pixels whose paths the
    // iterations change, chosen from our frames alone, never from the reference.
    if (dollyViews.empty()) dollyViews.push_back({scene.camera, refWhole, maskWhole});
    std::vector<std::vector<ray::Image>> depthFrames(S.depthSweep.size());  // [depth][view]
    for (size_t di = 0; di < S.depthSweep.size(); ++di) {
        ImpostorSettings s = base;
        s.mode = Mode::Static;
        s.moverU = uImage;
        s.depth = S.depthSweep[di];
        renderer.render(scene.camera, s);
        const Scores sc = scoreAgainst(refWhole, renderer.frame(), maskWhole);
        psnrByDepth.push_back(sc.psnrGlass);
        depthJ[std::to_string(S.depthSweep[di])] = scoresJson(sc);
        for (const DollyView& dv : dollyViews) {
            renderer.render(dv.cam, s);
            depthFrames[di].push_back(renderer.frame());
        }
    }
    // Over the views side by side: the references, the changed glass pixels, each DEPTH's frames.
    auto sideBySide = [](const std::vector<ray::Image>& ims) {
        ray::Image o(0, 0, ims.front().channels);
        o.height = ims.front().height;
        for (const ray::Image& im : ims) o.width += im.width;
        o.pixels.assign(size_t(o.width) * size_t(o.height) * size_t(o.channels), 0.0f);
        int x0 = 0;
        for (const ray::Image& im : ims) {
            for (int y = 0; y < im.height; ++y)
                for (int x = 0; x < im.width; ++x)
                    for (int c = 0; c < o.channels; ++c) o.at(x0 + x, y, c) = im.at(x, y, std::min(c, im.channels - 1));
            x0 += im.width;
        }
        return o;
    };
    std::vector<ray::Image> refs, changedMasks;
    int64_t depthChangedPixels = 0, depthGlassPixels = 0;
    for (size_t vi = 0; vi < dollyViews.size(); ++vi) {
        const DollyView& dv = dollyViews[vi];
        ray::Image changed(dv.ref.width, dv.ref.height, 1, 0.0f);
        const ray::Image &first = depthFrames.front()[vi], &last = depthFrames.back()[vi];
        for (int y = 0; y < dv.ref.height; ++y)
            for (int x = 0; x < dv.ref.width; ++x) {
                if (dv.mask.at(x, y, 0) <= 0.0f) continue;
                ++depthGlassPixels;
                const glm::vec3 d = glm::abs(glm::clamp(first.rgb(x, y), 0.0f, 1.0f) - glm::clamp(last.rgb(x, y), 0.0f, 1.0f));
                if (std::max({d.x, d.y, d.z}) > 1.0f / 255.0f) {
                    changed.at(x, y, 0) = 1.0f;
                    ++depthChangedPixels;
                }
            }
        refs.push_back(dv.ref);
        changedMasks.push_back(changed);
    }
    const ray::Image refAll = sideBySide(refs), changedAll = sideBySide(changedMasks);
    std::vector<double> psnrChangedByDepth;
    for (size_t i = 0; i < depthFrames.size(); ++i) {
        double psnr = 0.0;
        if (depthChangedPixels > 0)
            psnr = ray::compareMasked(refAll, sideBySide(depthFrames[i]), changedAll, "impostors: the pixels DEPTH changes").psnr;
        psnrChangedByDepth.push_back(psnr);
        depthJ[std::to_string(S.depthSweep[i])]["changed_pixels_psnr_db"] = psnr;
    }
    // Pixel by pixel over the same pixels: where is the second DEPTH of the sweep closer to
    // the reference than the first (squared RGB error, clamped as the PSNR clamps)?
    int64_t closerAtSecond = 0;
    if (depthFrames.size() >= 2)
        for (size_t vi = 0; vi < dollyViews.size(); ++vi)
            for (int y = 0; y < refs[vi].height; ++y)
                for (int x = 0; x < refs[vi].width; ++x) {
                    if (changedMasks[vi].at(x, y, 0) <= 0.0f) continue;
                    const glm::vec3 t = glm::clamp(refs[vi].rgb(x, y), 0.0f, 1.0f);
                    auto err = [&](const ray::Image& im) {
                        const glm::vec3 d = glm::clamp(im.rgb(x, y), 0.0f, 1.0f) - t;
                        return glm::dot(d, d);
                    };
                    closerAtSecond += err(depthFrames[1][vi]) < err(depthFrames[0][vi]);
                }
    const double closerFraction = double(closerAtSecond) / double(std::max<int64_t>(depthChangedPixels, 1));
    depthJ["changed_pixels"] = depthChangedPixels;
    depthJ["changed_pixels_closer_at_second_depth"] = closerFraction;
    depthJ["changed_pixels_views"] = int(dollyViews.size());
    depthJ["changed_pixels_of_glass_pixels"] = depthGlassPixels;
    r["depth_sweep"] = depthJ;
    std::vector<double> psnrByIterations;
    nlohmann::json iterJ;
    for (int it : S.iterationSweep) {
        ImpostorSettings s = base;
        s.mode = Mode::Static;
        s.moverU = uImage;
        s.iterations = it;
        renderer.render(scene.camera, s);
        const Scores sc = scoreAgainst(refWhole, renderer.frame(), maskWhole);
        psnrByIterations.push_back(sc.psnrGlass);
        iterJ[std::to_string(it)] = scoresJson(sc);
    }
    r["iteration_sweep"] = iterJ;
    progress.advance();

    // ---- more glass pixels → slower ----------------------------------------------------------
    // Views (camera and settings) timed side by side: they take turns, a frame each per round,
    // so a change in the machine's load falls on all of them alike; per view the median of
    // the rounds, its glass fragments, frame and glass-pass times.
    struct SweepPoint {
        double fragments = 0, frameMs = 0, glassMs = 0;
    };
    auto timeViews = [&](const std::vector<std::pair<ray::Camera, ImpostorSettings>>& views, int rounds) {
        for (const auto& [cam, s] : views) renderer.render(cam, s);  // warm-up
        std::vector<std::vector<double>> ms(views.size()), glassMs(views.size());
        std::vector<SweepPoint> out(views.size());
        for (int round = 0; round < rounds; ++round)
            for (size_t i = 0; i < views.size(); ++i) {
                const ImpostorFrame f = renderer.render(views[i].first, views[i].second);
                ms[i].push_back(f.totalMs);
                for (const PassTiming& p : f.passes)
                    if (p.name.rfind("frame: glass", 0) == 0) glassMs[i].push_back(p.ms);
                out[i].fragments = double(f.glassFragments);
            }
        for (size_t i = 0; i < views.size(); ++i) {
            out[i].frameMs = median(ms[i]);
            out[i].glassMs = glassMs[i].empty() ? 0.0 : median(glassMs[i]);
        }
        return out;
    };
    const int sweepRounds = std::max(5, S.timedFrames);
    // A view's entry in results.json, named by the swept quantity; a sweep's fits.
    auto pointJson = [&](const char* key, const nlohmann::json& value, const SweepPoint& p) {
        return nlohmann::json{{key, value},
                              {"glass_fragments", int64_t(p.fragments)},
                              {"frame_ms", p.frameMs},
                              {"glass_pass_ms", p.glassMs},
                              {"frames", sweepRounds}};
    };
    auto sweepJson = [](const nlohmann::json& frames, const Fit& glass, const Fit& frame) {
        return nlohmann::json{{"frames", frames},
                              {"ms_per_million_glass_fragments", glass.slope * 1e6},
                              {"intercept_ms", glass.intercept},
                              {"r2", glass.r2},
                              {"whole_frame", {{"ms_per_million_glass_fragments", frame.slope * 1e6},
                                               {"intercept_ms", frame.intercept},
                                               {"r2", frame.r2}}}};
    };
    ImpostorSettings staticSettings = base;
    staticSettings.mode = Mode::Static;

    // The camera dollied in.
    std::vector<double> glassPx, frameMs, glassPassMs;
    nlohmann::json dollyJ = nlohmann::json::array();
    {
        std::vector<std::pair<ray::Camera, ImpostorSettings>> views;
        for (float k : S.dollies) {
            ray::Camera cam = scene.camera;
            cam.eye = cam.target + (scene.camera.eye - scene.camera.target) * k;
            views.emplace_back(cam, staticSettings);
        }
        const std::vector<SweepPoint> pts = timeViews(views, sweepRounds);
        for (size_t i = 0; i < pts.size(); ++i) {
            glassPx.push_back(pts[i].fragments);
            frameMs.push_back(pts[i].frameMs);
            glassPassMs.push_back(pts[i].glassMs);
            dollyJ.push_back(pointJson("distance_factor", S.dollies[i], pts[i]));
        }
    }
    // The claim is the pixel shader's ("this technique is pixel shader sensitive", §8): the
    // glass pass's time against its fragments. The whole frame's time is reported beside it;
    // its other passes change with the view in their own ways (pieces leaving the frustum
    // are culled as the camera moves in, the board covers more pixels).
    const Fit dollyFit = fitLine(glassPx, glassPassMs);
    const Fit dollyFrameFit = fitLine(glassPx, frameMs);
    r["glass_pixels_sweep"] = sweepJson(dollyJ, dollyFit, dollyFrameFit);

    // More glass pixels, the same geometry: the image sized at Figure 10's view. The dolly
    // also changes what the vertex stage and set-up see (pieces leave the frustum as the
    // camera moves in), a share of the glass pass that outweighs the fragments' at the quick
    // size now that a fragment costs under a microsecond: at 300² the pass fell from the
    // third dolly to the fourth while its fragments grew. Sizing the image at one view
    // changes the glass fragments and nothing the geometry stages do, which is what "pixel
    // shader sensitive" asks about; the claim is decided on this sweep.
    std::vector<double> sizePx, sizeFrameMs, sizeGlassMs;
    nlohmann::json sizeJ = nlohmann::json::array();
    {
        std::vector<std::pair<ray::Camera, ImpostorSettings>> views;
        for (float f : S.sizeSweep) {
            ImpostorSettings s = staticSettings;
            s.width = s.height = std::max(8, int(std::lround(double(f) * double(S.imageSize))));
            views.emplace_back(scene.camera, s);
        }
        const std::vector<SweepPoint> pts = timeViews(views, sweepRounds);
        for (size_t i = 0; i < pts.size(); ++i) {
            sizePx.push_back(pts[i].fragments);
            sizeFrameMs.push_back(pts[i].frameMs);
            sizeGlassMs.push_back(pts[i].glassMs);
            sizeJ.push_back(pointJson("image_size", views[i].second.width, pts[i]));
        }
    }
    const Fit sizeFit = fitLine(sizePx, sizeGlassMs);
    const Fit sizeFrameFit = fitLine(sizePx, sizeFrameMs);
    r["glass_pixels_sweep"]["image_sizes"] = sweepJson(sizeJ, sizeFit, sizeFrameFit);
    progress.advance();

    // ---- Figures 5 and 9: the mirror pawn seen through the sphere -----------------------------
    nlohmann::json fig9;
    {
        ImpostorRenderer mr(mirrorScene, threads, rasterPath);
        ImpostorSettings s = base;
        s.mode = Mode::Separated;
        s.moverU = uImage;
        s.diagnostics = true;
        mr.render(mirrorScene.closeUp, s);
        const ray::Image ours = mr.frame();
        const ImpostorRenderer::Diagnostics dg = mr.readDiagnostics();
        s.mode = Mode::Classical;
        s.diagnostics = false;
        mr.render(mirrorScene.closeUp, s);
        const ray::Image oursClassical = mr.frame();
        const ray::Image ref = reference(mirrorScene, mirrorScene.closeUp, uImage, S.referenceDepth);
        std::vector<int> obj;
        const ray::Image mask = glassMaskOf(mirrorScene, mirrorScene.closeUp, uImage, &obj);
        const Scores sep = scoreAgainst(ref, ours, mask), cls = scoreAgainst(ref, oursClassical, mask);
        fig9["separated"] = scoresJson(sep);
        fig9["classical"] = scoresJson(cls);
        // The class map (Figure 9's labels): 1 the environment impostor could not represent
        // the hit (the search's distance disagrees with Embree's along the same ray); 2 a
        // ray met the mover, whose own reflections ignore it; 3 the board, sampled
        // differently (our texture filtered and light-mapped); the rest unlabelled.
        const ray::Scene at = mirrorScene.at(uImage);
        ray::Accel accel(at);
        const int n = S.imageSize;
        ray::Image classes(n, n, 3);
        double share[4] = {0, 0, 0, 0}, total = 0;
        int64_t count[4] = {0, 0, 0, 0};
        const int board = at.findObject("board");
        auto disagrees = [&](glm::vec3 o, glm::vec3 d, float dOurs) {
            ray::Ray ray;
            ray.dir = glm::normalize(d);
            ray.origin = o + ray.dir * (4.0f * accel.epsilon());
            const ray::Hit h = accel.intersect(ray);
            const bool skyOurs = dOurs > 0.5f * kSkyDistance;
            if (!h.valid()) return !skyOurs;
            if (skyOurs) return true;
            return std::fabs(dOurs - h.t) > 0.1f + 0.05f * h.t;
        };
        ray::Image searches(n, n, 3);
        double searchSum = 0;
        int64_t searchPixels = 0, moverPixels = 0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const double err = (std::fabs(ours.at(x, y, 0) - ref.at(x, y, 0)) + std::fabs(ours.at(x, y, 1) - ref.at(x, y, 1)) +
                                    std::fabs(ours.at(x, y, 2) - ref.at(x, y, 2))) / 3.0;
                const int o = obj[size_t(y) * size_t(n) + size_t(x)];
                const float flags = dg.flags.at(x, y, 0), nSearch = dg.searches.at(x, y, 0);
                if (nSearch > 0) {
                    searchSum += nSearch;
                    ++searchPixels;
                    moverPixels += flags > 0;
                }
                const float sv = std::min(1.0f, nSearch / 12.0f);
                searches.setRgb(x, y, flags > 0 ? glm::vec3(1.0f, 0.6f * (1 - sv), 0.2f) : glm::vec3(sv));
                int cls3 = 0;
                if (o == board) {
                    cls3 = 3;
                } else if (o == mirrorScene.mover || flags > 0) {
                    cls3 = 2;
                } else if (nSearch > 0) {
                    const glm::vec3 P = glm::vec3(dg.exitOrigin.rgb(x, y));
                    const ray::Ray pr = ray::primaryRay(mirrorScene.closeUp, n, n, float(x) + 0.5f, float(y) + 0.5f);
                    const ray::Hit ph = accel.intersect(pr);
                    const glm::vec3 hitP = ph.valid() ? pr.origin + pr.dir * ph.t : P;
                    if (disagrees(hitP, glm::vec3(dg.reflDir.rgb(x, y)), dg.reflD.at(x, y, 0)) ||
                        disagrees(P, glm::vec3(dg.exitDir.rgb(x, y)), dg.exitD.at(x, y, 0)))
                        cls3 = 1;
                }
                share[cls3] += err;
                total += err;
                if (err > 0.05) ++count[cls3];
                const glm::vec3 colours[4] = {{0.35f, 0.35f, 0.35f}, {0.9f, 0.15f, 0.15f}, {0.15f, 0.75f, 0.2f}, {0.2f, 0.35f, 0.95f}};
                classes.setRgb(x, y, err > 0.05 ? colours[cls3] : glm::vec3(std::min(1.0, err * 10.0)));
            }
        for (int k = 0; k < 4; ++k) share[k] = total > 0 ? share[k] / total : 0.0;
        fig9["error_share"] = {{"1_concave_environment", share[1]},
                               {"2_mover_ignored_after_hit", share[2]},
                               {"3_board_sampling", share[3]},
                               {"unlabelled", share[0]}};
        fig9["pixels_over_0.05"] = {{"1", count[1]}, {"2", count[2]}, {"3", count[3]}, {"unlabelled", count[0]}};
        fig9["searches_per_glass_pixel"] = searchPixels ? searchSum / double(searchPixels) : 0.0;
        fig9["glass_pixels_meeting_the_mover"] = moverPixels;
        fig9["glass_pixels"] = searchPixels;
        ray::writeImage(out / "figure9_comparison.png",
                        demos::labelledGrid({{ref, "classic ray tracing (Whitted, depth " + std::to_string(S.referenceDepth) + ")"},
                                             {ours, "ours (separated)"},
                                             {ray::errorHeatMap(ref, ours, 0.25f), "difference, 0 to 0.25"},
                                             {classes, "error kinds: 1 red, 2 green, 3 blue, other grey"}},
                                            2));
        ray::writeImage(out / "figure5_searches.png",
                        demos::labelledGrid({{ours, "ours"}, {searches, "searches per pixel (white 12); orange: a ray met the mover"}}, 2));
    }
    r["figure9"] = fig9;
    progress.advance();

    // ---- the maps: Figure 3's refractor maps and an environment impostor ---------------------
    {
        ImpostorSettings s = base;
        s.mode = Mode::Static;
        renderer.render(scene.camera, s);
        std::vector<demos::Cell> cells;
        for (int m = 0; m < renderer.refractorMaps(); ++m)
            cells.push_back({renderer.refractorImage(m), "refractor map: " + scene.scene.meshes[renderer.refractorMesh(m)].name});
        ray::writeImage(out / "refractor_maps.png", demos::labelledGrid(cells, 2));
        const int sphere = int(std::find(scene.glass.begin(), scene.glass.end(),
                                         uint32_t(std::max(0, scene.scene.findObject("glass_sphere")))) -
                               scene.glass.begin());
        const int show = sphere < int(scene.glass.size()) ? sphere : 0;
        ray::writeImage(out / "environment_impostor.png",
                        demos::labelledGrid({{renderer.impostorImage(show, false), "radiance"},
                                             {renderer.impostorImage(show, true, 8.0f), "distance (white ≥ 8)"}},
                                            1));
    }
    progress.advance();

    // ---- Figures 3 and 4: the refractor maps searched on the CPU twin -------------------------
    // The device-rendered maps read back through the device's own point-sampled cube fetch
    // (NearestFloat2D): the sphere's exit points against the analytic sphere (Figure 3),
    // and the search from outside in the pawn's map against Embree on the pawn's mesh,
    // hits and misses over ε (Figure 4).
    nlohmann::json fig3, fig4;
    double sphereOutsideAccuracy = -1.0;
    {
        tex::SamplerState point;
        point.magFilter = point.minFilter = tex::FilterMode::Nearest;
        auto fetcher = [&](int map) {
            const raster::detail::NearestFloat2D n = raster::detail::nearestFloat2D(&renderer.refractorTexture(map), point);
            return [n](const Vec3L<float>& d, bool live) {
                if (!live) return Vec4L<float>(0.0f, 0.0f, 0.0f, 0.0f);
                const glm::vec4 t = n.fetchCube(glm::vec3(d.x, d.y, d.z));
                return Vec4L<float>(t.x, t.y, t.z, t.w);
            };
        };
        std::mt19937 rng(11);
        std::normal_distribution<float> g;
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        const int sphereObject = scene.scene.findObject("glass_sphere");
        const auto sphereIt = std::find(scene.glass.begin(), scene.glass.end(), uint32_t(std::max(sphereObject, 0)));
        if (sphereObject >= 0 && sphereIt != scene.glass.end()) {
            const int map = renderer.refractorOf(int(sphereIt - scene.glass.begin()));
            const auto fetch = fetcher(map);
            const ray::Mesh& mesh = scene.scene.meshes[renderer.refractorMesh(map)];
            const ray::Bounds b = ray::computeBounds(mesh);
            const float radius = 0.5f * (b.hi.x - b.lo.x);  // the map's centre is the sphere's
            const double texel = 2.0 * radius / double(S.refractorSize);  // a texel's width at the surface, at a face centre
            std::vector<double> errs;
            for (int i = 0; i < S.analyticRays; ++i) {
                const glm::vec3 n = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
                glm::vec3 dir = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
                if (glm::dot(dir, n) > -0.1f) dir = glm::normalize(dir - n * (glm::dot(dir, n) + 0.5f));
                const glm::vec3 x = n * radius;  // relative to the centre
                const float truth = -2.0f * glm::dot(x, dir);
                const SearchResult<float, bool> s =
                    secantSearch(Vec3L<float>(x.x, x.y, x.z), Vec3L<float>(dir.x, dir.y, dir.z), S.iterations, true, fetch,
                                 /*seeded=*/true);
                const glm::vec3 exit = x + dir * s.d, want = x + dir * truth;
                errs.push_back(double(glm::length(exit - want)) / texel);
            }
            std::sort(errs.begin(), errs.end());
            fig3 = {{"rays", S.analyticRays},
                    {"map_size", S.refractorSize},
                    {"median_exit_error_texels", errs[errs.size() / 2]},
                    {"p95_exit_error_texels", errs[errs.size() * 95 / 100]}};
        }
        // Figure 4: the white pawn's map (the mover's kind).
        const int pawnGlass = renderer.moverIndex() >= 0 ? renderer.moverIndex() : 0;
        const int map = renderer.refractorOf(pawnGlass);
        const ray::Mesh& mesh = scene.scene.meshes[renderer.refractorMesh(map)];
        ray::Scene one;
        one.name = "refractor";
        ray::Material glassM;
        glassM.type = ray::MaterialType::Glass;
        one.addObject("piece", one.addMesh(mesh), one.addMaterial(glassM));
        ray::Accel accel(one);
        const ray::Bounds b = ray::computeBounds(mesh);
        const glm::vec3 c = b.center();
        const float halfDiagonal = 0.5f * glm::length(b.hi - b.lo);
        const float lo[3] = {b.lo.x - c.x, b.lo.y - c.y, b.lo.z - c.z}, hi[3] = {b.hi.x - c.x, b.hi.y - c.y, b.hi.z - c.z};
        const auto fetch = fetcher(map);
        const std::vector<float> epsilons = {0.005f, 0.01f, 0.02f, 0.03f, 0.05f, 0.1f};
        std::vector<int64_t> tp(epsilons.size()), fp(epsilons.size()), fn(epsilons.size()), tn(epsilons.size());
        std::vector<double> hitErr(epsilons.size());
        // Where the misses come from, at the frame's ε: each of Embree's hits is sorted by
        // whether the search's undershoot seed (the ray's point nearest the map's centre) lies
        // inside the object, and by whether the map holds any of the ray's crossings (one
        // seen first from the centre: a concave part hidden from it is not in the map); and
        // the same rays searched with four times the iterations.
        struct MissClass {
            int64_t hits = 0, missed = 0;
        };
        MissClass seedInside, seedOutside, inMap, notInMap;
        // Of the rays the map holds, found and missed: how many searches bracketed a crossing
        // (saw an undershoot and an overshoot), and the mean |a − 1| of the point they end on
        // (0 on the stored surface) — outsideSearch's own search, rerun for its result.
        struct Settle {
            int64_t n = 0, bracketed = 0;
            double ratioOff = 0;
        };
        Settle settleFound, settleMissed;
        int64_t missedLongSearch = 0;
        // [6]'s linear search first, for comparison (outsideSearchLinearFirst): agreement
        // with Embree at the frame's ε, per sample count.
        const std::vector<int> linearSamples = {4, 8, 16};
        std::vector<int64_t> linearAgree(linearSamples.size(), 0), linearMissed(linearSamples.size(), 0),
            linearFalse(linearSamples.size(), 0), linearHits(linearSamples.size(), 0);
        std::vector<double> linearHitErr(linearSamples.size(), 0.0);
        const float tolerance = 1e-3f * halfDiagonal;
        auto seenFromCentre = [&](const glm::vec3& p) {
            ray::Ray fc;
            fc.origin = c;
            fc.dir = glm::normalize(p - c);
            const ray::Hit hc = accel.intersect(fc);
            return hc.valid() && std::fabs(hc.t - glm::length(p - c)) < tolerance;
        };
        for (int i = 0; i < S.outsideRays; ++i) {
            const glm::vec3 o = c + glm::normalize(glm::vec3(g(rng), g(rng), g(rng))) * (2.5f * halfDiagonal);
            const glm::vec3 aim = c + glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 1.3f * (b.hi - b.lo);
            const glm::vec3 dir = glm::normalize(aim - o);
            ray::Ray ray;
            ray.origin = o;
            ray.dir = dir;
            const ray::Hit truth = accel.intersect(ray);
            for (size_t k = 0; k < linearSamples.size(); ++k) {
                const OutsideHit<float, bool> lh =
                    outsideSearchLinearFirst(Vec3L<float>(o.x - c.x, o.y - c.y, o.z - c.z), Vec3L<float>(dir.x, dir.y, dir.z),
                                             lo, hi, base.epsilon * halfDiagonal, linearSamples[k], S.iterations, fetch);
                const bool found = lh.valid;
                if (found && truth.valid()) ++linearHits[k], linearHitErr[k] += std::fabs(double(lh.t) - double(truth.t));
                linearAgree[k] += found == truth.valid();
                linearMissed[k] += truth.valid() && !found;
                linearFalse[k] += found && !truth.valid();
            }
            if (truth.valid()) {
                const Vec3L<float> yl(o.x - c.x, o.y - c.y, o.z - c.z), Rl(dir.x, dir.y, dir.z);
                const float eps = base.epsilon * halfDiagonal;
                const bool found = outsideSearch(yl, Rl, lo, hi, eps, S.iterations, true, fetch).valid;
                if (!outsideSearch(yl, Rl, lo, hi, eps, 4 * S.iterations, true, fetch).valid) ++missedLongSearch;
                const glm::vec3 nearest = o + dir * -glm::dot(o - c, dir);
                ray::Ray fc;
                fc.origin = c;
                fc.dir = glm::normalize(nearest - c);
                const ray::Hit hc = accel.intersect(fc);
                MissClass& bySeed = hc.valid() && hc.t > glm::length(nearest - c) ? seedInside : seedOutside;
                bool held = false;
                ray::Ray along = ray;
                for (int k = 0; k < 16 && !held; ++k) {  // every crossing of the ray, nearest first
                    const ray::Hit h = accel.intersect(along);
                    if (!h.valid()) break;
                    held = seenFromCentre(along.origin + along.dir * h.t);
                    along.tnear = h.t + tolerance;
                }
                MissClass& byMap = held ? inMap : notInMap;
                if (held) {
                    const BoxSpan<float, bool> box = rayBox<float, bool>(yl, Rl, lo, hi);
                    const SearchResult<float, bool> sr =
                        secantSearch(yl + Rl * box.tFar, Rl * -1.0f, S.iterations, box.hit, fetch, true);
                    Settle& st = found ? settleFound : settleMissed;
                    ++st.n;
                    st.bracketed += sr.bracketed ? 1 : 0;
                    st.ratioOff += std::fabs(double(length3(sr.point)) / std::max(double(sr.texel.w), 1e-9) - 1.0);
                }
                ++bySeed.hits;
                ++byMap.hits;
                if (!found) ++bySeed.missed, ++byMap.missed;
            }
            for (size_t e = 0; e < epsilons.size(); ++e) {
                const OutsideHit<float, bool> h =
                    outsideSearch(Vec3L<float>(o.x - c.x, o.y - c.y, o.z - c.z), Vec3L<float>(dir.x, dir.y, dir.z), lo, hi,
                                  epsilons[e] * halfDiagonal, S.iterations, true, fetch);
                if (truth.valid() && h.valid) {
                    ++tp[e];
                    hitErr[e] += std::fabs(double(h.t) - double(truth.t));
                } else if (h.valid) {
                    ++fp[e];
                } else if (truth.valid()) {
                    ++fn[e];
                } else {
                    ++tn[e];
                }
            }
        }
        nlohmann::json rows = nlohmann::json::array();
        for (size_t e = 0; e < epsilons.size(); ++e)
            rows.push_back({{"epsilon_half_diagonal", epsilons[e]},
                            {"true_hits", tp[e]},
                            {"false_hits", fp[e]},
                            {"missed_hits", fn[e]},
                            {"true_misses", tn[e]},
                            {"accuracy", double(tp[e] + tn[e]) / double(S.outsideRays)},
                            {"mean_hit_error", tp[e] ? hitErr[e] / double(tp[e]) : 0.0}});
        // The same rays' recipe on the glass sphere's map and mesh (convex, so its map holds
        // every crossing): the search's agreement where the map is not the limit.
        if (sphereObject >= 0 && sphereIt != scene.glass.end()) {
            const int smap = renderer.refractorOf(int(sphereIt - scene.glass.begin()));
            const ray::Mesh& smesh = scene.scene.meshes[renderer.refractorMesh(smap)];
            ray::Scene sone;
            sone.name = "sphere";
            sone.addObject("sphere", sone.addMesh(smesh), sone.addMaterial(glassM));
            ray::Accel saccel(sone);
            const ray::Bounds sb = ray::computeBounds(smesh);
            const glm::vec3 sc = sb.center();
            const float shalf = 0.5f * glm::length(sb.hi - sb.lo);
            const float slo[3] = {sb.lo.x - sc.x, sb.lo.y - sc.y, sb.lo.z - sc.z};
            const float shi[3] = {sb.hi.x - sc.x, sb.hi.y - sc.y, sb.hi.z - sc.z};
            const auto sfetch = fetcher(smap);
            int64_t agree = 0;
            for (int i = 0; i < S.outsideRays; ++i) {
                const glm::vec3 o = sc + glm::normalize(glm::vec3(g(rng), g(rng), g(rng))) * (2.5f * shalf);
                const glm::vec3 aim = sc + glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) * 1.3f * (sb.hi - sb.lo);
                ray::Ray sr;
                sr.origin = o;
                sr.dir = glm::normalize(aim - o);
                const bool hit = saccel.intersect(sr).valid();
                const bool found = outsideSearch(Vec3L<float>(o.x - sc.x, o.y - sc.y, o.z - sc.z),
                                                 Vec3L<float>(sr.dir.x, sr.dir.y, sr.dir.z), slo, shi,
                                                 base.epsilon * shalf, S.iterations, true, sfetch)
                                       .valid;
                agree += hit == found;
            }
            sphereOutsideAccuracy = double(agree) / double(S.outsideRays);
        }
        auto cls = [](const MissClass& m) { return nlohmann::json{{"hits", m.hits}, {"missed", m.missed}}; };
        fig4 = {{"object", mesh.name},
                {"rays", S.outsideRays},
                {"by_epsilon", rows},
                {"missed_hits_at_epsilon",
                 {{"epsilon_half_diagonal", base.epsilon},
                  {"seed_inside", cls(seedInside)},
                  {"seed_outside", cls(seedOutside)},
                  {"a_crossing_in_the_map", cls(inMap)},
                  {"no_crossing_in_the_map", cls(notInMap)},
                  {"iterations", S.iterations},
                  {"missed_with_4x_iterations", missedLongSearch},
                  {"held_found", {{"rays", settleFound.n},
                                  {"bracketed", settleFound.n ? double(settleFound.bracketed) / double(settleFound.n) : 0.0},
                                  {"mean_ratio_off", settleFound.n ? settleFound.ratioOff / double(settleFound.n) : 0.0}}},
                  {"held_missed", {{"rays", settleMissed.n},
                                   {"bracketed", settleMissed.n ? double(settleMissed.bracketed) / double(settleMissed.n) : 0.0},
                                   {"mean_ratio_off", settleMissed.n ? settleMissed.ratioOff / double(settleMissed.n) : 0.0}}}}}};
        if (sphereOutsideAccuracy >= 0) fig4["sphere_accuracy_at_epsilon"] = sphereOutsideAccuracy;
        nlohmann::json lin = nlohmann::json::array();
        for (size_t k = 0; k < linearSamples.size(); ++k)
            lin.push_back({{"samples", linearSamples[k]},
                           {"accuracy", double(linearAgree[k]) / double(S.outsideRays)},
                           {"missed_hits", linearMissed[k]},
                           {"false_hits", linearFalse[k]},
                           {"mean_hit_error", linearHits[k] ? linearHitErr[k] / double(linearHits[k]) : 0.0}});
        fig4["linear_search_first_at_epsilon"] = lin;
    }
    r["figure3_refractor_exit"] = fig3;
    r["figure4_outside_search"] = fig4;
    progress.advance();

    // ---- claims --------------------------------------------------------------------------------
    // Margins (docs/reports.md, "Margins"), from spreads measured at quick quality:
    // - Glass PSNR, 0.5 dB. From 8 to 16 secant iterations, where the analytic room's search
    //   has converged (its mean error changes by 0.2 %), the glass PSNR still moves by 0.11 dB:
    //   the spread of the measurement under a change that should not matter. The margin is
    //   over four times that (and the one every paper's PSNR orderings use); "as close as"
    //   is within it.
    // - Figure 2's analytic searches: refining must remove at least half the first guesses'
    //   error; the first four iterations must gain more than iterations 8 to 16 by the error
    //   no iteration removes (the converged error e16, the map's sampling: 0.0012 at quick
    //   quality, some 500 times the 0.000002 that iterations past 8 still move it).
    // - The refractor map's exit within one texel, the map's resolution (a search that stops
    //   at the entry misses by the whole chord, many texels).
    // - The outside search: 95 % agreement with Embree, one ray in twenty wrong.
    // - The frame-rate ratios and the glass-pixel fit are timings on this machine (its load
    //   decides them; the tests report them and do not assert them).
    constexpr double kMarginDb = 0.5;
    auto ratioClaim = [&](const std::string& id, const std::string& section, const std::string& statement,
                          const std::string& what, double ours, double paper, double atLeast) {
        demos::Claim c;
        c.id = id;
        c.section = section;
        c.statement = statement;
        c.test = what + " ≥ " + num(atLeast, 2);
        c.measured = {{"ours", ours}, {"paper", paper}};
        c.holds = ours >= atLeast;
        rep.claim(c);
    };
    ratioClaim("static_faster_than_separated", "§8", "Only static pieces (no map updates) run faster than a moving piece with separation",
               "fps static / fps separated", fpsStatic / fpsSep, kPaperStaticFps / kPaperSeparatedFps, 1.2);
    ratioClaim("separated_faster_than_classical", "§8, §5.2",
               "Separating the static environment from the moving piece is several times faster than rebuilding "
               "every environment map (\"approximately 6 times\")",
               "fps separated / fps classical", fpsSep / fpsClassical, kPaperSeparatedFps / kPaperClassicalFps, 2.0);
    ratioClaim("smaller_maps_faster", "§8",
               "Environment maps of " + std::to_string(S.envSize) + "² run faster than " + std::to_string(S.envSizeLarge) +
                   "² (paper: 256² against 512²)",
               "fps small / fps large", fpsSep / fpsLarge, kPaperSeparatedFps / kPaperSeparated512Fps, 1.1);
    {
        demos::Claim c;
        c.id = "glass_pixels_cost_linearly";
        c.section = "§8";
        c.statement = "The technique is pixel shader sensitive: the more pixels shaded with the glassy effect, the lower "
                      "the frame rate, near-linearly";
        c.test = "slope of the glass pass's time against its fragments > 0 and R² ≥ 0.9 over the image sized ×0.5 "
                 "to ×1.25 at one view (the geometry unchanged); the whole frame's fit and the camera dolly's "
                 "reported beside it";
        c.measured = {{"ms_per_million_glass_fragments", sizeFit.slope * 1e6},
                      {"r2", sizeFit.r2},
                      {"whole_frame_r2", sizeFrameFit.r2},
                      {"dolly_r2", dollyFit.r2}};
        c.holds = sizeFit.slope > 0 && sizeFit.r2 >= 0.9;
        rep.claim(c);
    }
    {
        const auto& e = analytic.meanError;
        demos::Claim c = demos::claimAtLeast("iterations_reduce_error", "§3, Figure 2",
                                             "Refining the first guesses by secant iterations brings the hit closer",
                                             "error_0_iterations", e[0], "error_8_iterations", e[8], 0.5 * e[0], "");
        c.test = "mean error after p and l − after 8 iterations ≥ half the former (analytic box room)";
        rep.claim(c);
        demos::Claim d = demos::claimAtLeast("iterations_diminishing_returns", "§3, Figure 2",
                                             "Each further iteration gains less (the secant search converges)",
                                             "gain_0_to_4", e[0] - e[4], "gain_8_to_16", e[8] - e[16], e[16], "");
        d.measured["converged_error_16"] = e[16];
        d.test = "gain_0_to_4 − gain_8_to_16 ≥ converged_error_16, the error no iteration removes (analytic box room)";
        rep.claim(d);
    }
    {
        const size_t i1 = 0, i2 = std::min<size_t>(1, psnrByDepth.size() - 1);
        demos::Claim c = demos::claimAtLeast(
            "depth_adds_bounces", "§5.1",
            "Each DEPTH iteration adds a bounce to the environment maps: DEPTH " + std::to_string(S.depthSweep[i2]) +
                " is closer to the ray tracer than DEPTH " + std::to_string(S.depthSweep[i1]) +
                " where the iterations change the frame",
            "changed_psnr_depth_" + std::to_string(S.depthSweep[i2]), psnrChangedByDepth[i2],
            "changed_psnr_depth_" + std::to_string(S.depthSweep[i1]), psnrChangedByDepth[i1], kMarginDb, "dB");
        c.test = "PSNR against the ray tracer over the glass pixels DEPTH " + std::to_string(S.depthSweep.front()) +
                 " and DEPTH " + std::to_string(S.depthSweep.back()) + " render differently (by more than one 8-bit level): DEPTH " +
                 std::to_string(S.depthSweep[i2]) + " − DEPTH " + std::to_string(S.depthSweep[i1]) + " ≥ " + num(kMarginDb, 2) + " dB";
        c.measured["changed_pixels"] = depthChangedPixels;
        c.measured["changed_pixels_of_glass_pixels"] = depthGlassPixels;
        c.measured["changed_pixels_closer_at_depth_" + std::to_string(S.depthSweep[i2])] = closerFraction;
        c.measured["glass_psnr_depth_" + std::to_string(S.depthSweep[i1])] = psnrByDepth[i1];
        c.measured["glass_psnr_depth_" + std::to_string(S.depthSweep[i2])] = psnrByDepth[i2];
        if (depthChangedPixels == 0) c.holds = false;
        rep.claim(c);
    }
    if (!fig3.empty()) {
        demos::Claim c;
        c.id = "refractor_map_finds_the_exit";
        c.section = "§3, Figure 3";
        c.statement = "Searching a refractor distance map finds where a refracted ray leaves the object (a sphere)";
        c.test = "median distance to the analytic exit ≤ 1 texel";
        c.measured = {{"median_texels", fig3["median_exit_error_texels"]}, {"p95_texels", fig3["p95_exit_error_texels"]}};
        c.holds = fig3["median_exit_error_texels"].get<double>() <= 1.0;
        rep.claim(c);
    }
    {
        double acc = 0;
        for (const auto& row : fig4["by_epsilon"])
            if (std::fabs(row["epsilon_half_diagonal"].get<double>() - double(base.epsilon)) < 1e-6) acc = row["accuracy"];
        demos::Claim c;
        c.id = "outside_search_tells_hits_from_misses";
        c.section = "§4.1, Figure 4";
        c.statement = "Searching a refractor map from outside, with points farther than ε from the ray invalid, tells the "
                      "rays that hit the object from those that miss";
        c.test = "hit/miss agreement with Embree on the " + fig4["object"].get<std::string>() + " ≥ 95 % at ε = " +
                 num(base.epsilon * 100.0, 0) + " % of its half diagonal";
        c.measured = {{"accuracy", acc}};
        // Context, not the test: the convex sphere's agreement, and the pawn's missed hits
        // whose crossing the map holds (report.md, "Where the missed hits come from").
        if (fig4.contains("sphere_accuracy_at_epsilon")) c.measured["sphere_accuracy"] = fig4["sphere_accuracy_at_epsilon"];
        {
            const auto& m = fig4["missed_hits_at_epsilon"]["a_crossing_in_the_map"];
            const int64_t h = m["hits"].get<int64_t>();
            if (h) c.measured["missed_of_hits_the_map_holds"] = double(m["missed"].get<int64_t>()) / double(h);
        }
        c.holds = acc >= 0.95;
        rep.claim(c);
    }
    // §7's caustics claims, glass and mirror: the median distance from each reference peak
    // (≥ 1/10 of its largest irradiance) to the nearest of ours against the measured margin,
    // twice the 90th percentile of how far the reference's own peaks move when it is traced
    // with half the photons (its sampling spread), ≥ 1 texel.
    auto causticsClaim = [&](const std::string& id, const std::string& statement, const std::string& test,
                             const nlohmann::json& sc) {
        demos::Claim c;
        c.id = id;
        c.section = "§7";
        c.statement = statement;
        c.test = test + num(sc["peak_margin_texels"].get<double>(), 1) + " texels";
        c.measured = {{"peak_offset_median_texels", sc["peak_offset_median_texels"]},
                      {"peak_margin_texels", sc["peak_margin_texels"]},
                      {"reference_peaks", sc["reference_peaks"]},
                      {"correlation", sc["correlation"]},
                      {"energy_ratio", sc["energy_ratio"]}};
        c.holds = sc["peak_offset_median_texels"].get<double>() <= sc["peak_margin_texels"].get<double>();
        return c;
    };
    if (!caustics.empty()) {
        const auto& sc = caustics["scores"];
        demos::Claim c = causticsClaim(
            "caustics_where_photon_tracing_puts_them",
            "Photons refracted through the pieces by searching their refractor maps light the board where photons "
            "traced through the exact geometry do: the caustics peak where the reference's peak",
            "median distance from each reference caustic peak (≥ 1/10 of its largest irradiance) to the nearest of ours "
            "≤ the margin, twice the 90th percentile of that distance for the reference traced with half the photons "
            "(≥ 1 texel): ",
            sc);
        c.measured["peaks_within_margin"] = sc["peaks_within_margin"];
        c.measured["psnr_db"] = sc["psnr_db_peak_reference_max"];
        rep.claim(c);
    }
    if (r.contains("caustics_mirror"))
        rep.claim(causticsClaim("mirror_caustics_where_photon_tracing_puts_them",
                                "Reflecting pieces focus the light too: photons reflected by the mirror pawn light the "
                                "board where photons reflected by its exact mesh do",
                                "the glass caustics' test on the board with the mirror pawn alone: median distance from "
                                "each reference peak (≥ 1/10 of its largest irradiance) to the nearest of ours ≤ ",
                                r["caustics_mirror"]["scores"]));
    rep.claim(demos::claimWithin("separation_as_good_as_classical", "§5.2, Figure 9",
                                 "With separation, paths through the moving piece are still found: the image is as close "
                                 "to ray tracing as rebuilding every map",
                                 "glass_psnr_separated", fig9["separated"]["glass_psnr_db"].get<double>(),
                                 "glass_psnr_classical", fig9["classical"]["glass_psnr_db"].get<double>(), kMarginDb, "dB"));

    // ---- report ---------------------------------------------------------------------------------
    std::ostringstream& md = rep.md();
    const int nThreads = threads > 0 ? threads : int(std::thread::hardware_concurrency());
    md << "Dancsik & Minarik's distance-normal impostors on the emulated `geforce8800` profile: C++ vertex and "
          "fragment programs, RGBA16F cube render targets (six 90° passes each), the secant search in every glass "
          "fragment.\n\n"
       << "Quality `" << demos::qualityName(options.quality) << "`: frames " << S.imageSize << "², environment impostors "
       << S.envSize << "² (and " << S.envSizeLarge << "²), refractor distance maps " << S.refractorSize << "², DEPTH "
       << S.depth << ", " << S.iterations << " secant iterations, on " << nThreads << " thread(s). Scene: "
       << scene.description << "; " << scene.vertices << " vertices and " << scene.faces
       << " faces (the paper: 30,838 and 47,404).\n\n";
    rep.heading("§8: frame rates");
    md << "Paper: an AMD Athlon 64 X2 4600+ with a GeForce 8800 GTX at 600 × 600, environment maps 256². Ours: the "
          "emulated G80 on this machine's CPU, median of the timed frames; the moving piece moves every frame.\n\n";
    {
        demos::Table t{{"configuration", "paper FPS", "ours FPS", "ours ms", "maps ms", "impostors rebuilt / frame"}, {}};
        auto row = [&](const char* name, const char* key, double paper) {
            const auto& j = timing[key];
            t.rows.push_back({name, num(paper, 1), num(j["fps"].get<double>(), 2), num(j["frame_ms"].get<double>(), 1),
                              num(j["maps_ms"].get<double>(), 1), std::to_string(j["impostors_rebuilt_per_frame"].get<int>())});
        };
        row("only static pieces", "static", kPaperStaticFps);
        row("moving piece, every map rebuilt (classical)", "classical", kPaperClassicalFps);
        row("moving piece, static/dynamic separated", "separated", kPaperSeparatedFps);
        row(("separated, " + std::to_string(S.envSizeLarge) + "² maps").c_str(), "separated_large_maps", kPaperSeparated512Fps);
        rep.table(t);
        demos::Table q{{"ratio", "paper", "ours"}, {}};
        q.rows.push_back({"static / separated", num(kPaperStaticFps / kPaperSeparatedFps, 2), num(fpsStatic / fpsSep, 2)});
        q.rows.push_back({"separated / classical", num(kPaperSeparatedFps / kPaperClassicalFps, 2), num(fpsSep / fpsClassical, 2)});
        q.rows.push_back({"small / large maps", num(kPaperSeparatedFps / kPaperSeparated512Fps, 2), num(fpsSep / fpsLarge, 2)});
        rep.table(q);
        md << "Per pass (ms), separated: ";
        for (const auto& [pass, ms] : timing["separated"]["passes_ms"].items()) md << pass << " " << num(ms.get<double>(), 1) << "; ";
        md << "\n\nGlass fragments in the frame: " << timing["static"]["glass_fragments"].get<int64_t>() << ", "
           << num(timing["static"]["fetches_per_glass_fragment"].get<double>(), 1) << " texel fetches each (static).\n\n";
    }
    if (!caustics.empty()) {
        rep.heading("Caustics (§7)");
        const auto& cs = caustics["settings"];
        const auto& sc = caustics["scores"];
        md << "After Szirmay-Kalos et al. 2005, as §7 describes: per glass piece and light a photon map of "
           << cs["photon_map_size"].get<int>() << "² (our choice; the paper gives none), the piece rendered from the light, "
              "each texel's photon refracted in (its power: the light's intensity over the texel's cross-section, times "
              "Schlick's 1 − F and the absorption inside), its exit found by the refractor-map search of the frame, "
              "refracted out and met with the board plane only (other pieces neglected, as §7 says). Then one quad per "
              "photon-map texel, placed by a vertex program that reads the photon map (vertex texture fetch, added to "
              "`geforce8800` as the G80 had it), a Gaussian of σ = "
           << num(cs["splat_sigma_texels"].get<double>(), 2) << " light-map texels to 3σ, normalised so that a splat "
              "carries its photon's power, added with ONE/ONE blending into a "
           << cs["light_map_size"].get<int>() << "² RGBA32F caustic light map (static pieces once, the mover per frame). "
              "The board adds the caustic irradiance to its shadowed direct light. The reference: raycore traces "
           << caustics["reference_photons"].get<int64_t>() << " photons (" << cs["reference_photons_per_piece_and_light"].get<int>()
           << " per piece and light, the same framing and power model) through the exact meshes with Embree, other "
              "pieces neglected too, and splats them with the same kernel in double precision.\n\n";
        demos::Table t{{"measure", "value"}, {}};
        t.rows.push_back({"PSNR against the reference (peak: its largest irradiance)",
                          num(sc["psnr_db_peak_reference_max"].get<double>()) + " dB"});
        t.rows.push_back({"relative L1 error", num(sc["relative_l1"].get<double>(), 3)});
        t.rows.push_back({"energy ours / reference", num(sc["energy_ratio"].get<double>(), 3)});
        t.rows.push_back({"correlation", num(sc["correlation"].get<double>(), 3)});
        t.rows.push_back({"reference core energy found (texels above ½ its peak lit above ¼ within 2σ)",
                          num(sc["core_energy_found"].get<double>(), 3)});
        t.rows.push_back({"caustic peaks (≥ 1/10 of the reference's largest): reference, ours",
                          std::to_string(sc["reference_peaks"].get<int>()) + ", " + std::to_string(sc["our_peaks"].get<int>())});
        t.rows.push_back({"distance from each reference peak to ours: median, 90th percentile",
                          num(sc["peak_offset_median_texels"].get<double>(), 1) + ", " +
                              num(sc["peak_offset_p90_texels"].get<double>(), 1) + " texels"});
        t.rows.push_back({"the same for the reference with half the photons, 90th percentile",
                          num(sc["half_photon_reference_peak_offset_p90_texels"].get<double>(), 1) + " texels"});
        t.rows.push_back({"brightest texel, ours to the reference's", num(sc["brightest_texel_offset_texels"].get<double>(), 1) + " texels"});
        for (const auto& [name, p] : caustics["passes"].items())
            t.rows.push_back({"pass \"" + name + "\"", num(p["ms"].get<double>(), 1) + " ms, " +
                                                          std::to_string(p["vertex_texture_fetches"].get<uint64_t>()) +
                                                          " vertex texture fetches"});
        t.rows.push_back({"reference (Embree, this machine)", num(caustics["reference_ms"].get<double>(), 0) + " ms"});
        rep.table(t);
        const auto& lost = caustics["reference_photons_lost"];
        md << "Of the reference's photons that met their object, " << caustics["reference_board_hits"].get<int64_t>()
           << " of " << lost["met_their_object"].get<int64_t>() << " reached the board; "
           << lost["leaving_upward_or_level"].get<int64_t>() << " left upward or level, "
           << lost["inside_after_max_interfaces"].get<int64_t>() << " were still inside after 8 interfaces, "
           << lost["no_exit_found"].get<int64_t>() << " found no exit, " << lost["off_the_board"].get<int64_t>()
           << " landed off the board: " << num(100.0 * double(caustics["reference_board_hits"].get<int64_t>()) /
                                                     double(caustics["reference_photons"].get<int64_t>()), 1)
           << " % of the photons shot, against about "
           << num(100.0 * caustics["ours_board_hits_estimate"].get<double>() / double(caustics["ours_photons"].get<int64_t>()), 1)
           << " % of ours (their splats' weights summed): a ratio of "
           << num((caustics["ours_board_hits_estimate"].get<double>() / double(caustics["ours_photons"].get<int64_t>())) /
                      (double(caustics["reference_board_hits"].get<int64_t>()) /
                       double(caustics["reference_photons"].get<int64_t>())),
                  2)
           << " in photons landed beside " << num(caustics["scores"]["energy_ratio"].get<double>(), 2)
           << " in energy. Ours sends each photon out after at most two total "
              "reflections (the frame's exit rule), and its 32² photons per piece and light give a noisier map than "
              "the reference's.\n\n";
        rep.figure("caustics.png", "§7: the shadows' light map (visibility of the two lights, red and green), our caustic "
                                   "light map, the photon-traced reference's, and their difference.");
        if (r.contains("caustics_mirror")) {
            const auto& mc = r["caustics_mirror"];
            const auto& ms = mc["scores"];
            md << "A mirror reflects each photon once where the photon map's rasterisation meets it, with its "
                  "reflectance as the photon's power (as the frame shades it), and the reference reflects its photons "
                  "off the exact mesh. Figure 9's mirror pawn alone on the board (the sphere's focus beside it would put "
                  "the pawn's caustic under the peaks' floor): PSNR "
               << num(ms["psnr_db_peak_reference_max"].get<double>()) << " dB, correlation "
               << num(ms["correlation"].get<double>(), 3) << ", energy ours / reference " << num(ms["energy_ratio"].get<double>(), 3)
               << ", " << ms["reference_peaks"].get<int>() << " reference peaks, the median "
                  "distance to ours " << num(ms["peak_offset_median_texels"].get<double>(), 1) << " texels (margin "
               << num(ms["peak_margin_texels"].get<double>(), 1) << "). Ours shoots "
               << mc["settings"]["photons_per_piece_and_light"].get<int>() << " photons per piece and light, as for glass, "
                  "and the convex mirror spreads them over much of the board: away from the bright ring at the pawn's foot "
                  "ours is single splats where the reference's "
               << mc["settings"]["reference_photons_per_piece_and_light"].get<int>()
               << " make a faint haze, hence the low correlation.\n\n";
            rep.figure("caustics_mirror.png", "§7 with a mirror: the mirror pawn's caustic light map, ours and the "
                                              "photon-traced reference's (each at the reference's peak as white), and "
                                              "their difference.");
        }
    }
    rep.heading("Against the ray tracer");
    md << "raycore's Whitted tracer at depth " << S.referenceDepth << ", one sample at each pixel centre, exact Fresnel, "
          "glass casting opaque shadows (as shadow maps do), no caustics on either side.\n\n";
    {
        demos::Table t{{"mode", "PSNR (dB)", "SSIM", "glass PSNR (dB)", "glass SSIM"}, {}};
        for (const auto& [m, j] : quality.items())
            t.rows.push_back({m, num(j["psnr_db"].get<double>()), num(j["ssim"].get<double>(), 3),
                              num(j["glass_psnr_db"].get<double>()), num(j["glass_ssim"].get<double>(), 3)});
        rep.table(t);
    }
    r["quality"] = quality;
    md << "Glass pixels of the whole view whose refracted ray reflects totally at its exit: "
       << num(100.0 * exitTir["ours_fraction"].get<double>(), 1) << " % in ours (the exit the refractor distance map "
       << "gives), " << num(100.0 * exitTir["ray_tracer_fraction"].get<double>(), 1) << " % at the ray tracer's first "
       << "exit, " << num(100.0 * exitTir["both_fraction"].get<double>(), 1) << " % in both ("
       << exitTir["glass_pixels"].get<int64_t>() << " pixels). Over the same pixels the mean colour is (" << num(exitTir["ours_mean_rgb"][0].get<double>(), 3) << ", "
       << num(exitTir["ours_mean_rgb"][1].get<double>(), 3) << ", " << num(exitTir["ours_mean_rgb"][2].get<double>(), 3)
       << ") in ours and (" << num(exitTir["ray_tracer_mean_rgb"][0].get<double>(), 3) << ", "
       << num(exitTir["ray_tracer_mean_rgb"][1].get<double>(), 3) << ", "
       << num(exitTir["ray_tracer_mean_rgb"][2].get<double>(), 3)
       << ") in the ray tracer's. A distance map about the centre holds one surface per direction, and the pieces' "
          "necks and collars are not star-shaped about it, so exits and normals found there can be off: the case §6's "
          "height maps are for (next section).";
    if (builtIn)
        md << " The pieces rest " << ray::kChessRestGap << " squares above the board, so their bases are glass–air faces "
              "for both sides (in the board's plane, as they stood until 2026-11-28, the ray tracer took the base or the "
              "board pixel by pixel, and its pieces came out black with speckles of sky).";
    md << "\n\n";
    rep.heading("§6: refractor height maps");
    md << "Each piece kind's refractor height map (" << S.heightMapSize << "², RGBA32F: normal and height over its "
          "plane of symmetry, taken by Embree with one orthographic ray per texel) on a billboard turned towards each "
          "ray's origin; the exit of the refracted ray by a binary search of " << S.heightSteps
       << " steps on Figure 7's segment, with the mirrored retry behind the plane. The same static frames with the exit "
          "in the refractor distance maps (" << S.refractorSize << "² a face) for comparison; environment impostors, "
          "Fresnel and absorption are the same.\n\n";
    {
        demos::Table t{{"view (× distance)", "exit", "glass PSNR (dB)", "glass SSIM", "TIR at exit: ours", "ray tracer", "both"}, {}};
        for (const auto& v : heightJ["views"])
            for (const char* e : {"distance-map", "height-map"}) {
                const auto& j = v[e];
                const auto& tir = j["exit_total_reflection"];
                t.rows.push_back({num(v["distance_factor"].get<double>(), 2), e, num(j["glass_psnr_db"].get<double>()),
                                  num(j["glass_ssim"].get<double>(), 3), num(100.0 * tir["ours_fraction"].get<double>(), 1) + " %",
                                  num(100.0 * tir["ray_tracer_fraction"].get<double>(), 1) + " %",
                                  num(100.0 * tir["both_fraction"].get<double>(), 1) + " %"});
            }
        rep.table(t);
        demos::Table f{{"exit", "static frame (ms)", "glass pass (ms)", "texel fetches / glass fragment"}, {}};
        for (const char* e : {"distance-map", "height-map"}) {
            const auto& j = heightJ["timing"][e];
            f.rows.push_back({e, num(j["frame_ms"].get<double>(), 1),
                              j["glass_pass_ms"].is_number() ? num(j["glass_pass_ms"].get<double>(), 1) : "–",
                              num(j["fetches_per_glass_fragment"].get<double>(), 1)});
        }
        rep.table(f);
        const auto& f9 = heightJ["figure9_separated"];
        md << "Figure 9's view in the separated mode (the mirror pawn moving, seen through the sphere; with the height-map "
              "exit the static objects also search the mover's height map from outside, §6's last paragraph): glass PSNR "
           << num(f9["distance-map"]["glass_psnr_db"].get<double>()) << " dB with distance maps, "
           << num(f9["height-map"]["glass_psnr_db"].get<double>()) << " dB with height maps.\n\n";
        const auto& c7 = heightJ["figure7_exit_cases"];
        md << "Figure 7's cases over the whole view's " << c7["glass_pixels"].get<int64_t>() << " refracting glass pixels "
           << "(the exit search on the scalar twin from Embree's primary hits): case 1 " << num(100.0 * c7["case_1"].get<double>(), 1)
           << " %, case 2 " << num(100.0 * c7["case_2"].get<double>(), 1) << " %, case 3 in front "
           << num(100.0 * c7["case_3"].get<double>(), 1) << " %, case 3a → 3b " << num(100.0 * c7["case_3a"].get<double>(), 1)
           << " %; the mirrored retry ran for " << num(100.0 * c7["mirrored_retry"].get<double>(), 1)
           << " %; no crossing found (the ray leaves unbent) for " << num(100.0 * c7["no_crossing_found"].get<double>(), 1)
           << " %. The billboard faces the ray's origin, which for an exit ray is its entry point, so the origin is always "
              "in front of the plane: case 3a only arises for rays that cross the plane before the box.\n\n";
        const auto& fe = heightJ["first_exit_against_embree"];
        md << "The first exit of the same refracted rays (from Embree's primary hits) against Embree's first exit, on the "
              "scalar twins: median distance " << num(fe["median_point_error_height_map"].get<double>(), 4) << " (height map) and "
           << num(fe["median_point_error_distance_map"].get<double>(), 4) << " (distance map) world units over "
           << fe["rays"].get<int64_t>() << " rays; normal more than 10° off for "
           << num(100.0 * fe["normal_off_10deg_height_map"].get<double>(), 1) << " % and "
           << num(100.0 * fe["normal_off_10deg_distance_map"].get<double>(), 1) << " %. "
           << num(100.0 * fe["exits_through_flat_faces"].get<double>(), 1) << " % of the true exits are through flat faces "
              "(bases, tops: |n_y| > 0.9), which a height map sees edge-on and so does not hold; they account for "
           << num(100.0 * fe["normal_off_10deg_height_map_flat_faces"].get<double>(), 1)
           << " points of the height map's off normals.";
        if (heightJ.contains("first_view_by_exit_face")) {
            const auto& bf = heightJ["first_view_by_exit_face"];
            md << " Over the first view's glass pixels split by the face Embree's refracted ray first leaves through:";
            for (const char* k : {"curved", "flat"})
                if (bf.contains(k))
                    md << " " << k << " (" << bf[k]["pixels"].get<int64_t>() << " pixels) "
                       << num(bf[k]["glass_psnr_height_map_db"].get<double>()) << " dB with the height map against "
                       << num(bf[k]["glass_psnr_distance_map_db"].get<double>()) << " dB with the distance map"
                       << (std::string(k) == "curved" ? ";" : ".");
        }
        md << "\n\n";
    }
    rep.figure("figure6_height_maps.png", "Figure 6 analogue: the refractor height maps, normals ½ + ½n (left) and the "
                                          "height over the plane of symmetry / the box's half depth (right); empty texels black.");
    if (heightJ.contains("first_view_by_exit_face"))
        rep.figure("figure10_exit_faces.png",
                   "§6 by the exit's face: the glass pixels of the whole view by the face Embree's refracted ray first "
                   "leaves through (the lathes' curved sides, which a height map holds, or the flat bases and tops it "
                   "sees edge-on), and each exit's |difference| from the ray tracer (0 to 0.25).");
    rep.figure("figure10_double_refraction.png", "Figure 10 (right) analogue: the closest view, the exit through the refractor "
                                                 "distance maps and through the refractor height maps, against Whitted ray tracing.");
    rep.figure("figure10_whole_scene.png", "Figure 10 (left) analogue: the whole scene, ours against Whitted ray tracing.");
    rep.figure("figure9_comparison.png",
               "Figure 9 analogue: a reflective pawn (the mover) seen through the glass sphere. Error kinds: 1 "
               "the environment impostor cannot represent the hit (concave surroundings), 2 the mover's reflection "
               "ignores the mover itself, 3 the board sampled differently (light map and texture filtering).");
    {
        demos::Table t{{"error kind", "share of the total |difference|", "pixels over 0.05"}, {}};
        t.rows.push_back({"1 concave environment", num(fig9["error_share"]["1_concave_environment"].get<double>(), 3),
                          std::to_string(fig9["pixels_over_0.05"]["1"].get<int64_t>())});
        t.rows.push_back({"2 mover ignored after the hit", num(fig9["error_share"]["2_mover_ignored_after_hit"].get<double>(), 3),
                          std::to_string(fig9["pixels_over_0.05"]["2"].get<int64_t>())});
        t.rows.push_back({"3 board sampling", num(fig9["error_share"]["3_board_sampling"].get<double>(), 3),
                          std::to_string(fig9["pixels_over_0.05"]["3"].get<int64_t>())});
        t.rows.push_back({"unlabelled", num(fig9["error_share"]["unlabelled"].get<double>(), 3),
                          std::to_string(fig9["pixels_over_0.05"]["unlabelled"].get<int64_t>())});
        rep.table(t);
    }
    rep.figure("figure5_searches.png", "Figure 5 analogue: searches per glass pixel in the Figure 9 view (3 for a glass "
                                       "piece, 4 where its exit reflects totally, 1 for a mirror; the outside searches where a ray meets the mover's box, and the mover's "
                                       "own where it is hit, in orange).");
    md << "Mean searches per glass pixel: " << num(fig9["searches_per_glass_pixel"].get<double>(), 2) << "; glass pixels "
       << "whose rays meet the mover: " << fig9["glass_pixels_meeting_the_mover"].get<int64_t>() << " of "
       << fig9["glass_pixels"].get<int64_t>() << ".\n\n";
    rep.figure("figure2_error_by_iterations.svg", "Figure 2 analogue: the hit distance's error against the secant "
                                                  "iterations after the first guesses p and l, on an analytic room.");
    rep.heading("DEPTH and iterations");
    {
        demos::Table t{{"DEPTH", "glass PSNR (dB)", "PSNR where DEPTH changes the frame (dB)"}, {}};
        for (size_t i = 0; i < S.depthSweep.size(); ++i)
            t.rows.push_back({std::to_string(S.depthSweep[i]), num(psnrByDepth[i]), num(psnrChangedByDepth[i])});
        rep.table(t);
        rep.paragraph("Each DEPTH iteration re-renders every impostor with the surrounding objects seen through the "
                      "impostors as they stand, so a piece seen in a piece seen in a third gains the third's "
                      "content (§5.1); in place, in scene order, so DEPTH 1 already carries more than one bounce for "
                      "the later objects. Those paths are few here: of the " + std::to_string(depthGlassPixels) +
                      " glass pixels of the " + std::to_string(dollyViews.size()) + " views of §6, " +
                      std::to_string(depthChangedPixels) + " change by more than one 8-bit level between DEPTH " +
                      std::to_string(S.depthSweep.front()) + " and DEPTH " + std::to_string(S.depthSweep.back()) +
                      "; over all glass pixels the exit search's error, which DEPTH does not touch, hides them. "
                      "Over the changed pixels the second DEPTH of the sweep is the closer one at " +
                      num(100.0 * closerFraction, 1) + " % of them.");
        demos::Table u{{"secant iterations", "glass PSNR (dB)", "analytic mean error"}, {}};
        for (size_t i = 0; i < S.iterationSweep.size(); ++i)
            u.rows.push_back({std::to_string(S.iterationSweep[i]), num(psnrByIterations[i]),
                              num(analytic.meanError[size_t(std::min(S.iterationSweep[i], maxIt))], 4)});
        rep.table(u);
    }
    rep.heading("Figures 3 and 4: searching the refractor maps");
    if (!fig3.empty())
        md << "The sphere's refractor map (" << S.refractorSize << "²), " << S.analyticRays
           << " refracted rays from its surface: the exit found is "
           << num(fig3["median_exit_error_texels"].get<double>(), 2) << " texels from the analytic one at the median, "
           << num(fig3["p95_exit_error_texels"].get<double>(), 2) << " at the 95th percentile.\n\n";
    {
        md << "From outside (§4.1), the " << fig4["object"].get<std::string>() << "'s map against Embree on its mesh, "
           << S.outsideRays << " rays aimed at its box:\n\n";
        demos::Table t{{"ε (× half diagonal)", "agree", "false hits", "missed hits", "mean |t − t_true| of hits"}, {}};
        for (const auto& row : fig4["by_epsilon"])
            t.rows.push_back({num(row["epsilon_half_diagonal"].get<double>(), 3), num(100.0 * row["accuracy"].get<double>(), 1) + " %",
                              std::to_string(row["false_hits"].get<int64_t>()), std::to_string(row["missed_hits"].get<int64_t>()),
                              num(row["mean_hit_error"].get<double>(), 4)});
        rep.table(t);
        const auto& mh = fig4["missed_hits_at_epsilon"];
        auto share = [&](const char* k) {
            const auto& m = mh[k];
            const int64_t h = m["hits"].get<int64_t>(), n = m["missed"].get<int64_t>();
            return std::to_string(n) + " of " + std::to_string(h) + " (" + num(h ? 100.0 * double(n) / double(h) : 0.0, 1) + " %)";
        };
        md << "Where the missed hits come from at ε = " << num(100.0 * mh["epsilon_half_diagonal"].get<double>(), 0)
           << " % (Embree's hits, sorted twice). By the search's undershoot seed, the ray's point nearest the map's "
              "centre: inside the object " << share("seed_inside") << " missed, outside it " << share("seed_outside")
           << ". By what the map holds: rays with a crossing seen first from the centre " << share("a_crossing_in_the_map")
           << ", rays whose every crossing a nearer part hides from the centre " << share("no_crossing_in_the_map")
           << ". With " << 4 * mh["iterations"].get<int>() << " iterations instead of " << mh["iterations"].get<int>()
           << ", " << mh["missed_with_4x_iterations"].get<int64_t>()
           << " hits are missed. So most misses are of rays the map does hold, and more iterations do not recover "
              "them; a seed outside the piece (rays through the head or the base, far from the centre) doubles the "
              "rate. Where those searches end: of the held rays found, "
           << num(100.0 * mh["held_found"]["bracketed"].get<double>(), 1) << " % bracketed a crossing and their last point "
              "lies at a mean |a − 1| of " << num(mh["held_found"]["mean_ratio_off"].get<double>(), 4)
           << " from the stored surface; of those missed, " << num(100.0 * mh["held_missed"]["bracketed"].get<double>(), 1)
           << " % bracketed one, at a mean |a − 1| of " << num(mh["held_missed"]["mean_ratio_off"].get<double>(), 2)
           << ": the missed searches mostly never sample a point inside the piece along the ray, and end far from "
              "any surface.";
        if (fig4.contains("sphere_accuracy_at_epsilon"))
            md << " The glass sphere's map, convex and so holding every crossing, searched from outside with rays aimed "
                  "the same way at its box, agrees with Embree on "
               << num(100.0 * fig4["sphere_accuracy_at_epsilon"].get<double>(), 1) << " % of them.";
        if (fig4.contains("linear_search_first_at_epsilon")) {
            md << " For comparison, not the frame's search: [6]'s linear search before the same secant steps, which "
                  "§3 names and the paper does not use (\"We used the method described in [5], which uses only secant "
                  "search\"), points evenly along the ray's span in the box bracketing the last crossing from inside:";
            for (const auto& row : fig4["linear_search_first_at_epsilon"])
                md << " " << row["samples"].get<int>() << " points, " << num(100.0 * row["accuracy"].get<double>(), 1)
                   << " % agree (" << row["missed_hits"].get<int64_t>() << " missed, " << row["false_hits"].get<int64_t>()
                   << " false hits);";
            md << " the frame's search reads " << 4 + mh["iterations"].get<int>() << " texels a ray. A better seed recovers "
                  "some of the missed hits, but even with 16 points the agreement stays under the claim's 95 %: the "
                  "rest are not the seed's.";
        }
        md << "\n\n";
    }
    rep.figure("refractor_maps.png", "Refractor distance maps (002 §3, Figure 3): the normals of each mesh seen from its "
                                     "centre, as a cube cross (+Y top, −X +Z +X −Z, −Y bottom).");
    rep.figure("environment_impostor.png", "An environment distance impostor (the sphere's): radiance and distance.");
    rep.heading("Choices where the paper is silent");
    md << "- **Secant iterations**: " << S.iterations << " after p and l (the paper gives none). With no undershoot "
          "seen, a step uses x's own surface point (\"we can use x\"), read once; with no overshoot, r.\n"
       << "- **Formats**: RGBA16F cubes, point sampled (one fetch gives radiance and distance); the sky at distance "
       << num(kSkyDistance, 0) << ".\n"
       << "- **DEPTH** " << S.depth << ", in place (Gauss–Seidel in scene order): a map later in the order already "
          "sees this iteration's maps.\n"
       << "- **§4.1's ε**: 3 % of the object's half diagonal.\n"
       << "- **The reference**: raycore's Whitted tracer at depth " << S.referenceDepth
       << " (a path cut there is black; on the chess view depth 24 is within 1/255 of depth 32 at 99.96 % of the "
          "pixels, depth 8 at 98 %)"
       << (builtIn ? std::string("; the pieces rest ") + num(double(ray::kChessRestGap), 2) +
                         " squares above the board, their bases glass–air faces (the paper's stand on it; a base in the "
                         "board's plane leaves the tracer no defined closest hit)"
                   : std::string())
       << ".\n"
       << "- **Fresnel**: Schlick with F0 = ((η − 1)/(η + 1))² = 0.04; total internal reflection at the exit "
          "reflects and reads the environment along the reflected ray.\n"
       << "- **The mover's impostor** holds the board, the sky and the static objects through their static "
          "impostors (one pass: they already carry DEPTH bounces); static objects drawn into it do not search the "
          "mover.\n"
       << "- **Height maps** (§6): the plane of symmetry is the model's z = 0 (every piece a lathe about the model's y "
          "axis, the knight's head extruded symmetrically about it), the billboard turns about the model's y axis; the "
          "texture domain is the mesh's reach from the axis across and its height along, padded by two texels so the "
          "box's faces read empty. A texel is empty (height 0) where no surface lies above the plane. The binary search "
          "reads the segment's end, then halves towards the state wanted (inside for an entry, outside for an exit); it "
          "succeeds where its end has that state, and the crossing is the bracket's middle, its normal the texel on the "
          "inside. Total reflection at the exit: one more height-map search from the exit point. With the height-map "
          "exit, static objects in separated mode search the mover's height map from outside (an entry search from the "
          "ray's origin, §6's last paragraph) instead of §4.1's distance-map search and its ε; mode A uses distance maps "
          "only.\n"
       << "- **Shadows** (§7): one 1024² Depth32F shadow map per light, resolved into two 512² light maps over the "
          "board (static pieces, the mover), 2×2 PCF. Caustics (§7, their section above) go into two caustic light maps of their own "
          "(RGBA32F): shadows multiply the direct light, caustics add. The frames compared with Whitted tracing keep "
          "caustics off (it has none); they are compared with a photon-traced reference instead.\n"
       << "- **Claims' margins.** Glass PSNR orderings by " << num(kMarginDb, 1) << " dB and \"as close\" within it: "
          "over four times the 0.11 dB the glass PSNR moves from 8 to 16 secant iterations at quick quality, where the "
          "analytic search has converged (its error changes by 0.2 %). Figure 2: refining removes at least half the first "
          "guesses' error, and the first four iterations gain more than iterations 8–16 by the error none removes (e16). "
          "The refractor exit within one texel (the map's resolution); the outside search 95 % right. The frame-rate "
          "ratios and the glass-pixel fit are timings on this machine. Caustics: our peaks within twice the 90th "
          "percentile of how far the reference's own peaks move with half its photons (at least one texel).\n\n";
    r["settings"] = {{"quality", demos::qualityName(options.quality)},
                     {"image_size", S.imageSize},
                     {"env_size", S.envSize},
                     {"env_size_large", S.envSizeLarge},
                     {"refractor_size", S.refractorSize},
                     {"height_map_size", S.heightMapSize},
                     {"height_steps", S.heightSteps},
                     {"depth", S.depth},
                     {"iterations", S.iterations},
                     {"epsilon_half_diagonal", base.epsilon},
                     {"reference_depth", S.referenceDepth},
                     {"threads", nThreads},
                     {"sky_distance", kSkyDistance}};
    r["seconds_total"] = std::chrono::duration<double>(Clock::now() - tStart).count();
    r = rep.write(out, r);
    std::printf("impostors: %d² static %.1f FPS, separated %.2f FPS, classical %.2f FPS (paper: 75, 11.3, 1.8)\n",
                S.imageSize, fpsStatic, fpsSep, fpsClassical);
    return r;
}

// ---- the registry entry ---------------------------------------------------------------------

std::string ImpostorReproduction::paper() const {
    return "Dancsik & Minarik, \"Real-time multi-bounce many-object ray tracing with distance-normal impostors\"";
}

nlohmann::json ImpostorReproduction::settings(demos::Quality quality) const {
    const ImpostorReproduceSettings s = impostorSettingsFor(quality);
    return {{"image_size", s.imageSize}, {"env_size", s.envSize}, {"env_size_large", s.envSizeLarge},
            {"refractor_size", s.refractorSize}, {"depth", s.depth}, {"iterations", s.iterations},
            {"height_map_size", s.heightMapSize}, {"height_steps", s.heightSteps}, {"timed_frames", s.timedFrames}};
}

nlohmann::json ImpostorReproduction::reproduce(const demos::ReproduceOptions& options) const {
    ImpostorReproduceSettings s = impostorSettingsFor(options.quality);
    s.threads = options.threads;
    return runImpostors(s, options);
}

std::string ImpostorReproduction::appliesTo(const ray::Scene& scene) const {
    for (const auto& o : scene.objects) {
        const ray::MaterialType t = scene.materials.at(o.material).type;
        if (t == ray::MaterialType::Glass || t == ray::MaterialType::Mirror) return o.name;
    }
    return {};
}

std::unique_ptr<demos::Technique> ImpostorReproduction::prepare(const ray::Scene& scene, const std::vector<ray::Camera>&,
                                                                const demos::PrepareOptions& options) const {
    return makeImpostorTechnique(scene, options);
}

std::unique_ptr<viewer::Demo> ImpostorReproduction::makeDemo(const viewer::DemoOptions& options) const {
    return std::make_unique<ImpostorDemo>(options);
}

void ImpostorReproduction::registerPrograms() const {
    registerImpostorPrograms();
    registerImpostorHeightPrograms();
}

std::vector<demos::BenchCase> ImpostorReproduction::benchCases() const { return impostorBenchCases(); }

const ImpostorReproduction& impostorReproduction() {
    static const ImpostorReproduction instance;
    return instance;
}

}  // namespace rg::impostors
