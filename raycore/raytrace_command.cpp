// `retroglass raytrace`: render a scene with the reference tracers from the command line.
#include "raycore/raytrace_command.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "core/error.h"
#include "core/progress.h"
#include "raycore/accel.h"
#include "raycore/layers_pem.h"
#include "raycore/scene_json.h"
#include "raycore/tracer_two_term.h"
#include "raycore/tracer_whitted.h"

namespace rg::ray {

Camera chooseCamera(const Scene& scene, const std::string& spec) {
    if (spec.empty()) {
        if (!scene.cameras.empty()) return scene.cameras[0];
        if (!scene.viewpointPaths.empty()) return scene.viewpointPaths[0].at(0);
        throw Error("scene '" + scene.name + "' has no cameras");
    }
    if (auto colon = spec.rfind(':'); colon != std::string::npos) {
        int p = scene.findViewpointPath(spec.substr(0, colon));
        if (p < 0) throw Error("no viewpoint path named '" + spec.substr(0, colon) + "'");
        const ViewpointPath& path = scene.viewpointPaths[size_t(p)];
        char* end = nullptr;
        const std::string index = spec.substr(colon + 1);
        double i = std::strtod(index.c_str(), &end);
        if (index.empty() || !end || *end != '\0' || !std::isfinite(i))
            throw Error("'" + spec + "': expected PATH:I with a viewpoint number I");
        if (i < 0 || i > double(path.count - 1))
            throw Error("viewpoint " + index + " is outside path '" + path.name + "' (0.." +
                        std::to_string(path.count - 1) + ")");
        if (i == std::floor(i)) return path.at(uint32_t(i));
        Camera c = cameraOnCircle(path.center, path.radius, path.height,
                                  path.startDegrees + float(i) * path.stepDegrees, path.fovYDegrees);
        c.name = spec;
        return c;
    }
    if (int c = scene.findCamera(spec); c >= 0) return scene.cameras[size_t(c)];
    char* end = nullptr;
    long i = std::strtol(spec.c_str(), &end, 10);
    if (end && *end == '\0' && i >= 0 && i < long(scene.cameras.size()))
        return scene.cameras[size_t(i)];
    throw Error("no camera '" + spec + "' in scene '" + scene.name + "'");
}

namespace {

std::filesystem::path withSuffix(const std::filesystem::path& p, const std::string& suffix) {
    return p.parent_path() / (p.stem().string() + "_" + suffix + p.extension().string());
}

}  // namespace

int runRaytraceCommand(const RaytraceArgs& args) {
    try {
        if (args.out.empty()) throw Error("raytrace: --out IMG is required");
        if (args.spp < 1 || args.spp > 64) throw Error("raytrace: --spp must be in 1..64");
        if (args.width < 1 || args.height < 1) throw Error("raytrace: image size must be positive");
        if (args.mode != "whitted" && args.mode != "two-term" && args.mode != "pem-layers")
            throw Error("raytrace: unknown --mode '" + args.mode + "' (whitted, two-term, pem-layers)");
        std::vector<std::string> warnings;
        Scene scene = loadSceneByName(args.scene, &warnings);
        for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
        Camera camera = chooseCamera(scene, args.camera);
        Accel accel(scene);
        RenderCounters counters;
        RenderOptions o;
        o.width = args.width;
        o.height = args.height;
        o.spp = args.spp;
        o.maxDepth = args.depth;
        o.threads = args.threads;
        o.counters = &counters;
        std::unique_ptr<Progress> progress;
        if (!args.quiet) {
            progress = std::make_unique<Progress>("raytrace " + args.mode, uint64_t(args.height));
            o.progress = progress.get();
        }
        const std::filesystem::path out(args.out);
        if (args.mode == "whitted") {
            writeImage(out, renderWhitted(accel, camera, o));
        } else if (args.mode == "two-term") {
            TwoTermImages im = renderTwoTerm(accel, camera, o);
            writeImage(out, im.sum);
            writeImage(withSuffix(out, "reflect"), im.reflectTerm);
            writeImage(withSuffix(out, "refract"), im.refractTerm);
            writeImage(withSuffix(out, "reflect_fg"), im.reflectFG);
            writeImage(withSuffix(out, "refract_fg"), im.refractFG);
            writeImage(withSuffix(out, "reflect_confidence"), im.reflectConfidence);
            writeImage(withSuffix(out, "refract_confidence"), im.refractConfidence);
        } else if (args.mode == "pem-layers") {
            std::vector<Segment> segments;
            for (uint32_t i = 0; i < scene.objects.size(); ++i)
                if (scene.materials[scene.objects[i].material].type != MaterialType::Diffuse)
                    segments.push_back({i, -1});
            PemLayerImages im = renderPemLayers(accel, camera, o, segments);
            Image all = im.background;
            for (const PemLayers& l : im.segments) {
                std::string n = segmentName(scene, l.segment);
                writeImage(withSuffix(out, n + "_diffuse"), l.diffuse);
                writeImage(withSuffix(out, n + "_fresnel"), l.fresnel);
                writeImage(withSuffix(out, n + "_local"), l.localColor);
                writeImage(withSuffix(out, n + "_local_alpha"), l.localAlpha);
                writeImage(withSuffix(out, n + "_distant"), l.distant);
                Image c = l.composite();
                for (size_t i = 0; i < all.pixels.size(); ++i) all.pixels[i] += c.pixels[i];
            }
            writeImage(out, all);
        } else {
            throw Error("raytrace: unknown --mode '" + args.mode + "' (whitted, two-term, pem-layers)");
        }
        if (progress) progress->finish();
        if (!args.quiet) std::fprintf(stderr, "%s: %s\n", args.out.c_str(), counters.summary().c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}

}  // namespace rg::ray
