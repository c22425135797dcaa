// `retroglass reproduce tir`: Davis & Wyman, "Interactive Refractions with Total Internal
// Reflection", Graphics Interface 2007, end to end on the geforce8800 profile.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "reproduction.h"
#include "tir_renderer.h"
#include "tir_scene.h"

namespace rg::tir {

struct TirReproduceSettings {
    int imageSize = 256;          // the evaluation images (square)
    int supersample = 2;          // raster images at n× and box-filtered (004 §4: 4×)
    int referenceSpp = 2;         // n×n samples per pixel of the ray-traced reference
    int referenceDepth = 10;      // 004 §4: "a ray depth of 10"
    std::vector<int> tableSizes = {512, 1024};
    int tableFrames = 3;          // timed frames per Table 1 cell (median), after a warm-up
    std::vector<std::string> tableScenes = {"kitchen", "statue", "dragon"};
    std::vector<float> mapScales = {0.125f, 0.25f, 0.5f, 1.0f};  // Figure 7's columns
    int envSize = 128;
    int textureSize = 512;
    bool paperMeshes = false;
    int threads = 0;
    // > 0: the frames draw the glass with this index of refraction instead of the scene's
    // (the ray-traced reference keeps the scene's): the claims test's deliberately wrong
    // setting (tests/tir/test_tir_claims.cpp).
    float frameIor = 0.0f;
};
TirReproduceSettings tirSettingsFor(demos::Quality quality);

// The reproduction at explicit settings (tests run it small); writes out/tir.
nlohmann::json runTir(const TirReproduceSettings& settings, const demos::ReproduceOptions& options);

// The ray-traced reference of a view (004 §4): refraction and TIR only, `depth` segments
// inside the glass, n×n samples; colour, the refractor's coverage and where paths reflect
// totally.
struct Reference {
    ray::Image color, refractor, tir;
};
Reference traceReference(const TirScene& scene, const ray::Camera& camera, int size, int spp,
                         int depth, int threads);

class TirReproduction final : public demos::Reproduction {
  public:
    std::string name() const override { return "tir"; }
    std::string paper() const override;
    std::string profile() const override { return "geforce8800"; }
    nlohmann::json settings(demos::Quality quality) const override;
    nlohmann::json reproduce(const demos::ReproduceOptions& options) const override;
    std::string appliesTo(const ray::Scene& scene) const override;
    std::unique_ptr<demos::Technique> prepare(const ray::Scene& scene,
                                              const std::vector<ray::Camera>& views,
                                              const demos::PrepareOptions& options) const override;
    std::unique_ptr<viewer::Demo> makeDemo(const viewer::DemoOptions& options) const override;
    void registerPrograms() const override;
    std::vector<demos::BenchCase> benchCases() const override;
};

const TirReproduction& tirReproduction();

}  // namespace rg::tir
