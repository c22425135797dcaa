#include "pem_assets.h"

#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "shards.h"

namespace fs = std::filesystem;

namespace rg::pem {

namespace {

int imageHeight(const TexelLayout& L) {
    int h = 0;
    for (int l = 0; l < L.levels(); ++l) h += L.faces * L.levelSize(l);
    return h;
}

nlohmann::json vec(const glm::vec3& v) { return {v.x, v.y, v.z}; }

nlohmann::json geometryJson(const EmGeometry& g) {
    nlohmann::json j;
    j["description"] = g.describe();
    j["origin"] = vec(g.origin);
    j["center"] = vec(g.center);
    j["radii"] = vec(g.radii);
    j["box_min"] = vec(g.boxMin);
    j["box_max"] = vec(g.boxMax);
    j["kind"] = int(g.kind);
    return j;
}

}  // namespace

void saveMap(const fs::path& path, const MapTexels& map) {
    const TexelLayout& L = map.layout;
    ray::Image img(L.baseSize, imageHeight(L), 4);
    int row = 0;
    for (int l = 0; l < L.levels(); ++l) {
        int s = L.levelSize(l);
        for (int f = 0; f < L.faces; ++f)
            for (int y = 0; y < s; ++y, ++row)
                for (int x = 0; x < s; ++x) {
                    const Rgba8 t = map.texels[size_t(L.index(l, f, x, y))];
                    img.at(x, row, 0) = t.r / 255.0f;
                    img.at(x, row, 1) = t.g / 255.0f;
                    img.at(x, row, 2) = t.b / 255.0f;
                    img.at(x, row, 3) = t.a / 255.0f;
                }
    }
    ray::writeImage(path, img);
}

MapTexels loadMap(const fs::path& path, const TexelLayout& layout) {
    ray::Image img = ray::readImage(path);
    if (img.width != layout.baseSize || img.height != imageHeight(layout) || img.channels != 4)
        throw Error(path.string() + ": expected a " + std::to_string(layout.baseSize) + "x" +
                    std::to_string(imageHeight(layout)) + " RGBA map, found " +
                    std::to_string(img.width) + "x" + std::to_string(img.height) + "x" +
                    std::to_string(img.channels));
    MapTexels map;
    map.layout = layout;
    map.texels.resize(size_t(layout.count()));
    int row = 0;
    for (int l = 0; l < layout.levels(); ++l) {
        int s = layout.levelSize(l);
        for (int f = 0; f < layout.faces; ++f)
            for (int y = 0; y < s; ++y, ++row)
                for (int x = 0; x < s; ++x)
                    map.texels[size_t(layout.index(l, f, x, y))] = {
                        ray::quantize8(img.at(x, row, 0)), ray::quantize8(img.at(x, row, 1)),
                        ray::quantize8(img.at(x, row, 2)), ray::quantize8(img.at(x, row, 3))};
    }
    return map;
}

nlohmann::json manifestFor(const PemScene& scene, const PemSettings& s, int emSize) {
    nlohmann::json j;
    j["format"] = "retroglass-pem";
    j["version"] = 1;
    j["scene"] = scene.scene.name;
    j["object"] = scene.scene.objects.at(size_t(scene.object)).name;
    j["triangles"] = scene.triangles;
    j["em_size"] = emSize;
    j["ptm_size"] = s.ptmSize;
    j["image"] = {s.width, s.height};
    j["spp"] = s.spp;
    j["views"] = s.views;
    j["step_degrees"] = s.stepDegrees;
    j["teapot_level"] = s.teapotLevel;
    j["inference"] = {{"smoothness", s.inference.smoothness},
                      {"level_coupling", s.inference.levelCoupling},
                      {"prior", s.inference.prior},
                      {"max_iterations", s.inference.maxIterations},
                      {"tolerance", s.inference.tolerance},
                      {"bound_rounds", s.inference.boundRounds}};
    for (const PemPart& p : scene.parts)
        j["parts"].push_back({{"name", p.name},
                              {"triangles", p.indices.size() / 3},
                              {"local", geometryJson(p.local)},
                              {"distant", geometryJson(p.distant)}});
    return j;
}

void writeManifest(const fs::path& dir, const nlohmann::json& manifest) {
    fs::create_directories(dir);
    std::ofstream f(dir / "manifest.json");
    if (!f) throw Error((dir / "manifest.json").string() + ": cannot write");
    f << manifest.dump(2) << "\n";
}

bool manifestMatches(const fs::path& dir, const nlohmann::json& manifest) {
    std::ifstream f(dir / "manifest.json");
    if (!f) return false;
    try {
        return nlohmann::json::parse(f) == manifest;
    } catch (const nlohmann::json::exception&) {
        return false;
    }
}

void saveView(const fs::path& vd, const PemScene& scene, const ViewSample& v,
              const ray::Camera& camera) {
    fs::create_directories(vd);
    nlohmann::json j;
    j["view"] = v.view;
    j["camera"] = {{"eye", vec(camera.eye)},
                   {"target", vec(camera.target)},
                   {"up", vec(camera.up)},
                   {"fov_y_degrees", camera.fovYDegrees}};
    j["baselines"] = v.hasBaselines();
    for (size_t p = 0; p < scene.parts.size(); ++p) {
        const std::string& n = scene.parts[p].name;
        const PartMaps& m = v.parts[p];
        saveMap(vd / (n + "_local.exr"), m.local);
        saveMap(vd / (n + "_distant.exr"), m.distant);
        if (v.hasBaselines()) {
            saveMap(vd / (n + "_infinite.exr"), m.infinite);
            saveMap(vd / (n + "_ptm.exr"), m.ptm);
        }
    }
    ray::writeImage(vd / "ground_truth.exr", v.groundTruth);
    ray::writeImage(vd / "coverage.exr", v.coverage);
    // Timings apart from the rest: they differ run to run, everything else is the same
    // bytes for the same inputs (a merged precompute is compared file by file).
    auto writeJson = [&vd](const char* name, const nlohmann::json& json) {
        std::ofstream f(vd / name);
        f << json.dump(2) << "\n";
        f.flush();
        if (!f) throw Error((vd / name).string() + ": cannot write (disk full?)");
    };
    writeJson("view.json", j);
    writeJson("timing.json", {{"raytrace_s", v.raytraceSeconds},
                              {"inference_s", v.inferenceSeconds},
                              {"inference_cpu_s", v.inferenceCpuSeconds},
                              {"baseline_s", v.baselineSeconds}});
}

std::optional<ViewSample> loadView(const fs::path& dir, const PemScene& scene, int view,
                                   int emSize, int ptmSize) {
    fs::path vd = dir / demos::viewFolderName(view);
    if (!fs::exists(vd / "view.json")) return std::nullopt;
    std::ifstream f(vd / "view.json");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(f);
    } catch (const nlohmann::json::exception& e) {
        throw Error((vd / "view.json").string() + ": " + e.what());
    }
    ViewSample v;
    v.view = view;
    if (std::ifstream tf(vd / "timing.json"); tf) {
        try {
            const nlohmann::json t = nlohmann::json::parse(tf);
            v.raytraceSeconds = t.value("raytrace_s", 0.0);
            v.inferenceSeconds = t.value("inference_s", 0.0);
            v.inferenceCpuSeconds = t.value("inference_cpu_s", 0.0);
            v.baselineSeconds = t.value("baseline_s", 0.0);
        } catch (const nlohmann::json::exception& e) {
            throw Error((vd / "timing.json").string() + ": " + e.what());
        }
    }
    TexelLayout cube{emSize, 6}, atlas{ptmSize, 1};
    for (const PemPart& p : scene.parts) {
        PartMaps m;
        m.local = loadMap(vd / (p.name + "_local.exr"), cube);
        m.distant = loadMap(vd / (p.name + "_distant.exr"), cube);
        if (j.value("baselines", false)) {
            m.infinite = loadMap(vd / (p.name + "_infinite.exr"), cube);
            m.ptm = loadMap(vd / (p.name + "_ptm.exr"), atlas);
        }
        v.parts.push_back(std::move(m));
    }
    v.groundTruth = ray::readImage(vd / "ground_truth.exr");
    v.coverage = ray::readImage(vd / "coverage.exr");
    return v;
}

}  // namespace rg::pem
