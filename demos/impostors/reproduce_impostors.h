// `retroglass reproduce impostors`: Dancsik & Minarik, "Real-time multi-bounce many-object
// ray tracing with distance-normal impostors", end to end on the geforce8800 profile.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "impostor_renderer.h"
#include "impostor_scene.h"
#include "reproduction.h"

namespace rg::impostors {

// The Whitted reference's interfaces after the primary hit (the reproduction's and the
// technique's ground truth). A path cut there returns black; rays caught by total internal
// reflection in the pieces' stems need many: on raycore's chess view at 300², the image at
// depth 8 differs from depth 32's by more than 1/255 at 1,847 pixels (2.1 %), at depth 16
// at 196, at depth 24 at 39 (0.04 %).
constexpr int kReferenceDepth = 24;

struct ImpostorReproduceSettings {
    int imageSize = 300;              // §8: 600 × 600
    int envSize = 64, envSizeLarge = 128;  // §8: 256² and 512²
    int refractorSize = 128;
    int heightMapSize = 256;          // §8: refractor height maps 512 × 512
    int heightSteps = 8;              // §6's binary-search steps per segment
    std::vector<float> heightViews = {1.0f, 0.65f, 0.5f};  // §6's comparison: camera distance, × Figure 10's
    int depth = 2;                    // §5.1's DEPTH
    int iterations = 8;               // secant steps after p and l
    int timedFrames = 2;              // per configuration, after a warm-up frame
    int classicalFrames = 1;
    int referenceDepth = kReferenceDepth;
    int segments = 56;                // the pieces' lathe segments (the paper's face count)
    int sphereSlices = 64;
    std::vector<float> dollies = {1.0f, 0.8f, 0.65f, 0.5f};  // camera distance, × Figure 10's
    std::vector<float> sizeSweep = {0.5f, 0.75f, 1.0f, 1.25f};  // image side, × imageSize, at Figure 10's view
    std::vector<int> iterationSweep = {0, 1, 2, 4, 8, 16};
    std::vector<int> depthSweep = {1, 2, 3};
    int analyticRays = 4000;          // Figure 2's rays
    int outsideRays = 4000;           // Figure 4's rays
    bool caustics = true;             // §7's caustics against the photon-traced reference
    int causticReferencePhotons = 128;  // the reference's photons per piece and light, per axis (ours: 32)
    int threads = 0;
};
ImpostorReproduceSettings impostorSettingsFor(demos::Quality quality);

// The reproduction at explicit settings (tests run it small); writes options.outDir.
nlohmann::json runImpostors(const ImpostorReproduceSettings& settings, const demos::ReproduceOptions& options);

// Figure 2's experiment on an analytic distance map: the mean |d − d_true| of the secant
// search's hit over random rays from points near the reference point of a box room,
// against the number of iterations (0 … maxIterations), and classical environment
// mapping's error (the texel along R) for scale. The map: `size`² per face, point sampled.
struct AnalyticErrors {
    std::vector<double> meanError;  // by iterations
    double classicalError = 0;
    double bracketed = 0;           // fraction of rays whose search saw both sides
};
AnalyticErrors analyticSearchErrors(int size, int maxIterations, int rays, uint32_t seed = 7);

class ImpostorReproduction final : public demos::Reproduction {
  public:
    std::string name() const override { return "impostors"; }
    std::string paper() const override;
    std::string profile() const override { return "geforce8800"; }
    nlohmann::json settings(demos::Quality quality) const override;
    nlohmann::json reproduce(const demos::ReproduceOptions& options) const override;
    std::string appliesTo(const ray::Scene& scene) const override;
    std::unique_ptr<demos::Technique> prepare(const ray::Scene& scene, const std::vector<ray::Camera>& views,
                                              const demos::PrepareOptions& options) const override;
    std::unique_ptr<viewer::Demo> makeDemo(const viewer::DemoOptions& options) const override;
    void registerPrograms() const override;
    std::vector<demos::BenchCase> benchCases() const override;
};

const ImpostorReproduction& impostorReproduction();

// impostor_technique.cpp: the technique `retroglass compare` runs (every glass and mirror
// object gets impostors, static mode) and §8's frames for `retroglass bench`.
std::unique_ptr<demos::Technique> makeImpostorTechnique(const ray::Scene& scene, const demos::PrepareOptions& options);
std::vector<demos::BenchCase> impostorBenchCases();

}  // namespace rg::impostors
