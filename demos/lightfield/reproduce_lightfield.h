// `retroglass reproduce lightfield`: Heidrich, Lensch, Cohen & Seidel, "Light Field
// Techniques for Reflections and Refractions", EGWR 1999, end to end on sgi-octane-mxe (pixel
// texture, 16-bit colour tables, 4D textures) and sgi-o2 (the software lookup).
#pragma once

#include <nlohmann/json.hpp>

#include <string>

#include "reproduction.h"

namespace rg::lightfield {

struct LightfieldSettings {
    int imageSize = 256;        // the evaluation images (square)
    int truthSpp = 2;           // n×n samples per pixel of the ray-traced references
    int timingSize = 400;       // §4: "images are of size 400×400 pixels"
    int timingFrames = 5;       // timed frames per route (median), after a warm-up
    int geoS = 16, geoU = 64;   // the geometry light field of §4 (S = T, U = V)
    int radS = 32, radU = 64;   // the radiance light field of §5 / colour plate 3
    int vqK = 1024;             // codebook entries of the all-halved variant (paper: 2^16)
    int vqKOther = 1024;        // of the (s, t)- and (u, v)-halved variants
    int vqTraining = 32768;     // blocks the codebook is trained on
    int vqIterations = 6;
    int lightGeoS = 8, lightGeoU = 64;  // §4.1: the geometry light field (RGBA8)
    int lightS = 16, lightU = 32;       // §4.1: the lighting light field (a 4D texture)
    int envSize = 256;          // dual-paraboloid maps, per side
    int glossySize = 64;        // the prefiltered map of §4.2
    float glossyExponent = 48.0f;
    int threads = 0;
};
LightfieldSettings lightfieldSettingsFor(demos::Quality quality);

// The reproduction at explicit settings (tests run it small); writes options.outDir.
nlohmann::json runLightfield(const LightfieldSettings& settings, const demos::ReproduceOptions& options);

class LightfieldReproduction final : public demos::Reproduction {
  public:
    std::string name() const override { return "lightfield"; }
    std::string paper() const override;
    std::string profile() const override { return "sgi-octane-mxe"; }
    nlohmann::json settings(demos::Quality quality) const override;
    nlohmann::json reproduce(const demos::ReproduceOptions& options) const override;
    // `retroglass compare`: the first glass or mirror object (lightfield_technique.cpp).
    std::string appliesTo(const ray::Scene& scene) const override;
    std::unique_ptr<demos::Technique> prepare(const ray::Scene& scene, const std::vector<ray::Camera>& views,
                                              const demos::PrepareOptions& options) const override;
    std::unique_ptr<viewer::Demo> makeDemo(const viewer::DemoOptions& options) const override;
    std::vector<demos::BenchCase> benchCases() const override;
};

const LightfieldReproduction& lightfieldReproduction();

}  // namespace rg::lightfield
