// `retroglass reproduce hybrid`: Hakura & Snyder, "Realistic Reflections and Refractions on
// Graphics Hardware With Hybrid Rendering and Layered Environment Maps", EGWR 2001, end to
// end on the geforce256 profile.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "hybrid_precompute.h"
#include "reproduction.h"

namespace rg::hybrid {

struct HybridSettings {
    PrecomputeSettings pre;        // display size, subsamples, EM size, τ of the samples' A
    int teapotLevel = 10;          // 32·level²·2 triangles (25 → 40,000)
    int views = 45;                // viewpoint samples on the circle (000 §6: 8° apart)
    float stepDegrees = 8.0f;
    int sample = 40;               // the evaluated sample k (and k + 1)
    float tauFast = 5.0f;          // Figure 10's faster setting (pre.tau is the slower one)
    int glassLayers = 3, mirrorLayers = 2;
    int neighbourViews = 3;        // disocclusion prevention: views stacked per sample,
    float neighbourSpanDegrees = 8.0f;  // spread evenly over this azimuth span around it
    float aboveHeight = 2.0f;      // Figure 8b: this much above the circle
    // 000 §4.3's direct images (the with_direct_images and direct_images_only variants):
    // Auto follows the paper's advice (viewpoint for glass, centre for a mirror).
    DirectSource directSource = DirectSource::Auto;
    int tableFrames = 3;           // timed repetitions of each §6 table row (median)
    bool countTests = true;        // the §6 table's triangle tests (counting twins)
    std::vector<ShellKind> teapotShells = {ShellKind::Quad, ShellKind::Cylinder,
                                           ShellKind::Sphere};  // 000 §6, by hand
    int threads = 0;
};
HybridSettings settingsFor(demos::Quality quality);

// The reproduction at explicit settings (tests run it small): figures, report.md,
// index.html and results.json in options.outDir; returns the results.
nlohmann::json runHybrid(HybridSettings settings, const demos::ReproduceOptions& options);

class HybridReproduction final : public demos::Reproduction {
  public:
    std::string name() const override { return "hybrid"; }
    std::string paper() const override;
    std::string profile() const override { return "geforce256"; }
    nlohmann::json settings(demos::Quality quality) const override;
    nlohmann::json reproduce(const demos::ReproduceOptions& options) const override;
    // `retroglass compare`: the scene's first glass or mirror object names the technique's
    // row; every glass and mirror object is a lens object (LensScene).
    std::string appliesTo(const ray::Scene& scene) const override;
    std::unique_ptr<demos::Technique> prepare(const ray::Scene& scene,
                                              const std::vector<ray::Camera>& views,
                                              const demos::PrepareOptions& options) const override;
    std::vector<demos::BenchCase> benchCases() const override;
    std::string capturedFrame() const override {
        return "the frame the §6 table times (between two samples: 4n layer passes and the alpha clears)";
    }
    std::unique_ptr<viewer::Demo> makeDemo(const viewer::DemoOptions& options) const override;
};

const HybridReproduction& hybridReproduction();

}  // namespace rg::hybrid
