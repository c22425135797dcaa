// `retroglass reproduce pem`: Hakura, Snyder & Lengyel, "Parameterized Environment Maps",
// I3D 2001, end to end on the geforce256 profile.
#pragma once

#include <nlohmann/json.hpp>

#include "pem_precompute.h"
#include "reproduction.h"

namespace rg::pem {

// The settings of each quality (001 §6 for paper).
PemSettings settingsFor(demos::Quality quality);

// The EM resolution of a PEM (001 §4 "EM Resolution"): the finest MIPMAP level a probe map
// of S.emProbeSize² is read at from `camera`, capped at S.emSize.
int emResolutionFor(PemRenderer& renderer, const ray::Camera& camera, const PemSettings& S,
                    int* finestAccessed = nullptr);

// The reproduction at explicit settings (tests run it small). Writes the figures,
// report.md, index.html and results.json into options.outDir and returns the results;
// returns an empty object after a partial precompute (--views A:B).
nlohmann::json runPem(PemSettings settings, const demos::ReproduceOptions& options);

class PemReproduction final : public demos::Reproduction {
  public:
    std::string name() const override { return "pem"; }
    std::string paper() const override;
    std::string profile() const override { return "geforce256"; }
    nlohmann::json settings(demos::Quality quality) const override;
    nlohmann::json reproduce(const demos::ReproduceOptions& options) const override;
    std::string appliesTo(const ray::Scene& scene) const override;
    std::unique_ptr<demos::Technique> prepare(const ray::Scene& scene,
                                              const std::vector<ray::Camera>& views,
                                              const demos::PrepareOptions& options) const override;
    std::unique_ptr<viewer::Demo> makeDemo(const viewer::DemoOptions& options) const override;
    std::vector<demos::BenchCase> benchCases() const override;
    std::string capturedFrame() const override {
        return "the frame the PEM viewer times (001 §6), on a viewpoint sample";
    }
};

const PemReproduction& pemReproduction();

}  // namespace rg::pem
