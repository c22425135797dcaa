#include "compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "core/error.h"
#include "figures.h"
#include "raycore/metrics.h"
#include "raycore/raytrace_command.h"
#include "raycore/scene_json.h"
#include "report.h"

namespace fs = std::filesystem;

namespace rg::demos {

namespace {

struct NamedView {
    std::string name;
    ray::Camera camera;
};

std::vector<NamedView> resolveViews(const ray::Scene& scene, std::vector<std::string> specs) {
    const ray::ViewpointPath* path = nullptr;
    if (int p = scene.findViewpointPath("circle"); p >= 0) path = &scene.viewpointPaths[size_t(p)];
    else if (!scene.viewpointPaths.empty()) path = &scene.viewpointPaths[0];
    if (specs.empty()) {
        if (path) specs = {"on", "between", "above"};
        for (const auto& c : scene.cameras)
            if (!path) specs.push_back(c.name);
        if (specs.empty()) throw Error("compare: scene '" + scene.name + "' has no camera or viewpoint path");
    }
    std::vector<NamedView> views;
    for (const std::string& s : specs) {
        if (s == "on" || s == "between" || s == "above") {
            if (!path)
                throw Error("compare: view '" + s + "' needs a viewpoint path, and scene '" +
                            scene.name + "' has none");
            const float mid = float(path->count / 2);
            const float index = s == "on" ? mid : mid + 0.5f;
            const float height = path->height + (s == "above" ? 0.25f * path->radius : 0.0f);
            ray::Camera c = ray::cameraOnCircle(path->center, path->radius, height,
                                                path->startDegrees + index * path->stepDegrees,
                                                path->fovYDegrees);
            c.name = s;
            views.push_back({s, c});
        } else {
            views.push_back({s, ray::chooseCamera(scene, s)});
        }
    }
    return views;
}

// A file-name-safe form of a view's name.
std::string slug(const std::string& s) {
    std::string out;
    for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return out;
}

// PSNR per (view, technique variant) as horizontal bars, a group per view.
void writePlot(const fs::path& file, const nlohmann::json& rows) {
    const int rowHeight = 18, labelWidth = 330, plotWidth = 420, top = 40;
    // Identical images score +∞ (JSON null): drawn as a full bar labelled ∞, and kept out
    // of the axis, which spans the finite scores (at most 100 dB).
    auto finite = [](const nlohmann::json& v) { return v.is_number() && std::isfinite(v.get<double>()); };
    double maxPsnr = 10.0;
    for (const auto& r : rows)
        if (finite(r["psnr_db"])) maxPsnr = std::max(maxPsnr, std::min(100.0, r["psnr_db"].get<double>()));
    const double axisMax = std::ceil(maxPsnr / 10.0) * 10.0;
    const int height = top + rowHeight * int(rows.size()) + 30;
    std::ofstream f(file);
    if (!f) throw Error(file.string() + ": cannot write");
    char buf[512];
    auto put = [&](const char* fmt, auto... args) {
        std::snprintf(buf, sizeof buf, fmt, args...);
        f << buf;
    };
    auto x = [&](double v) { return labelWidth + plotWidth * std::clamp(v, 0.0, axisMax) / axisMax; };
    put("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
        "font-family=\"sans-serif\" font-size=\"11\">\n",
        labelWidth + plotWidth + 60, height);
    put("<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n");
    put("<text x=\"10\" y=\"18\" font-size=\"13\">PSNR (dB) against the ray tracer, over "
        "the object's pixels</text>\n");
    for (double t = 0.0; t <= axisMax + 1e-9; t += 10.0) {
        put("<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"#ddd\"/>\n", x(t), top - 6,
            x(t), height - 24);
        put("<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%.0f</text>\n", x(t), height - 10, t);
    }
    int row = 0;
    for (const auto& r : rows) {
        const int y = top + rowHeight * row++;
        const bool inf = !finite(r["psnr_db"]);
        const double v = inf ? axisMax : std::min(axisMax, r["psnr_db"].get<double>());
        const bool main = r["main"].get<bool>();
        put("<text x=\"%d\" y=\"%d\" text-anchor=\"end\">", labelWidth - 6, y + 12);
        f << htmlEscape(r["view"].get<std::string>() + " · " + r["technique"].get<std::string>() +
                        " " + r["variant"].get<std::string>())
          << "</text>\n";
        put("<rect class=\"psnr\" data-psnr=\"%.2f\" x=\"%d\" y=\"%d\" width=\"%.1f\" height=\"%d\" "
            "fill=\"%s\"/>\n",
            v, labelWidth, y + 2, x(v) - labelWidth, rowHeight - 4, main ? "#2f6db3" : "#9bb7d8");
        if (inf) put("<text x=\"%.1f\" y=\"%d\">∞</text>\n", x(v) + 4, y + 12);
        else put("<text x=\"%.1f\" y=\"%d\">%.2f</text>\n", x(v) + 4, y + 12, v);
    }
    f << "</svg>\n";
    if (!f) throw Error(file.string() + ": cannot write");
}

}  // namespace

nlohmann::json runCompare(const CompareOptions& o) {
    const fs::path out = o.outDir;
    fs::create_directories(out);
    ray::Scene scene = ray::loadSceneByName(o.scene);
    const std::vector<NamedView> views = resolveViews(scene, o.views);
    std::vector<ray::Camera> cameras;
    for (const auto& v : views) cameras.push_back(v.camera);

    // ---- the techniques that apply ----------------------------------------------------------
    struct Prepared {
        const Reproduction* paper;
        std::string object;
        std::unique_ptr<Technique> technique;
    };
    std::vector<Prepared> prepared;
    std::string considered;
    for (const Reproduction* r : reproductions()) {
        if (!o.techniques.empty() &&
            std::find(o.techniques.begin(), o.techniques.end(), r->name()) == o.techniques.end())
            continue;
        if (!r->built()) continue;
        considered += (considered.empty() ? "" : ", ") + r->name();
        const std::string object = r->appliesTo(scene);
        if (object.empty()) {
            std::printf("compare: %s does not apply to scene '%s' (no object of its kind, or no "
                        "viewpoint path where it needs one)\n",
                        r->name().c_str(), scene.name.c_str());
            continue;
        }
        std::printf("compare: %s on object '%s' (profile %s): precompute\n", r->name().c_str(),
                    object.c_str(), r->profile().c_str());
        std::fflush(stdout);
        PrepareOptions po;
        po.quality = o.quality;
        po.workDir = out / r->name();
        po.threads = o.threads;
        po.width = o.width;
        po.height = o.height;
        prepared.push_back({r, object, r->prepare(scene, cameras, po)});
        if (!prepared.back().technique)
            throw Error("compare: " + r->name() + " applies to the scene but cannot prepare it");
    }
    if (prepared.empty())
        throw Error("compare: no technique (" + (considered.empty() ? std::string("none selected") : considered) +
                    ") applies to scene '" + scene.name + "': it needs a mirror or glass object");

    // ---- every view, every technique and variant --------------------------------------------
    nlohmann::json results;
    results["scene"] = scene.name;
    results["image_size"] = {o.width, o.height};
    results["quality"] = qualityName(o.quality);
    results["rows"] = nlohmann::json::array();
    std::ostringstream md;
    md << "# retroglass compare: scene `" << scene.name << "`\n\n"
       << "Every registered technique that applies to the scene's objects, each on its own "
          "emulated profile, against the ray tracer at the same views. PSNR and SSIM are "
          "measured over the pixels the ray tracer fully covers with the object and the "
          "technique draws. Precompute is the technique's total for these views; frame time "
          "is one frame on the emulated device on this machine; texture memory is what one "
          "frame reads.\n\n"
       << "![PSNR per view and technique](psnr.svg)\n\n";
    std::map<std::string, std::string> tracerOf;
    for (const NamedView& view : views) {
        md << "## View `" << view.name << "`\n\n";
        Table table{{"technique", "variant", "profile", "PSNR (dB)", "SSIM", "precompute (s)",
                     "frame (ms)", "texture memory (KiB)", "passes"},
                    {}};
        std::vector<Cell> cells;
        for (Prepared& p : prepared) {
            GroundTruth truth = p.technique->groundTruth(view.camera);
            tracerOf[p.paper->name()] = truth.tracer;
            cells.push_back({masked(truth.image, truth.coverage), p.paper->name() + ": ray traced"});
            for (const std::string& variant : p.technique->variants()) {
                RenderedView rv = p.technique->render(variant, view.camera);
                ray::Image mask(rv.image.width, rv.image.height, 1);
                for (int y = 0; y < mask.height; ++y)
                    for (int x = 0; x < mask.width; ++x)
                        mask.at(x, y, 0) = truth.coverage.at(x, y, 0) >= 0.999f &&
                                                   rv.drawn.at(x, y, 0) != 0.0f
                                               ? 1.0f
                                               : 0.0f;
                ray::MaskedScore s = ray::compareMasked(
                    truth.image, rv.image, mask,
                    "compare: object '" + p.object + "' in view '" + view.name + "' (" +
                        p.paper->name() + " " + variant + ")");
                const uint64_t bytes = p.technique->textureBytes(variant);
                nlohmann::json row = {{"view", view.name},
                                      {"technique", p.paper->name()},
                                      {"variant", variant},
                                      {"main", variant == p.technique->mainVariant()},
                                      {"object", p.object},
                                      {"profile", p.paper->profile()},
                                      {"psnr_db", s.psnr},
                                      {"ssim", s.ssim},
                                      {"pixels", s.pixels},
                                      {"precompute_s", p.technique->precomputeSeconds()},
                                      {"frame_ms", rv.frameMs},
                                      {"texture_bytes", bytes},
                                      {"passes", rv.passes},
                                      {"counters", rv.counters},
                                      {"reference", truth.tracer}};
                results["rows"].push_back(row);
                table.rows.push_back({p.paper->name(), variant, p.paper->profile(), num(s.psnr),
                                      num(s.ssim, 3), num(p.technique->precomputeSeconds(), 1),
                                      num(rv.frameMs, 1), num(double(bytes) / 1024.0, 0),
                                      std::to_string(rv.passes)});
                cells.push_back({rv.image, p.paper->name() + " " + variant + ", " + num(s.psnr) + " dB"});
            }
        }
        const std::string grid = "view_" + slug(view.name) + ".png";
        ray::writeImage(out / grid, labelledGrid(cells, 5));
        md << table.markdown() << "![view " << view.name << "](" << grid << ")\n\n";
    }
    md << "References: ";
    for (const auto& [name, tracer] : tracerOf) md << name << " against " << tracer << "; ";
    md << "the techniques run at quality `" << qualityName(o.quality) << "`.\n";

    writePlot(out / "psnr.svg", results["rows"]);
    {
        std::ofstream f(out / "report.md");
        f << md.str();
    }
    {
        std::ofstream f(out / "index.html");
        f << htmlPage("retroglass compare: " + scene.name,
                      "<p class=\"nav\"><a href=\"../index.html\">← all papers</a> · <a "
                      "href=\"report.md\">report.md</a> · <a href=\"results.json\">results.json</a></p>\n" +
                          markdownToHtml(md.str()));
    }
    {
        std::ofstream f(out / "results.json");
        f << results.dump(2) << "\n";
        if (!f) throw Error((out / "results.json").string() + ": cannot write");
    }
    std::printf("compare: wrote %s (%zu rows)\n", (out / "report.md").string().c_str(),
                results["rows"].size());
    return results;
}

}  // namespace rg::demos
