// 002 §7's caustics in `retroglass reproduce impostors`: the emulated caustic light maps
// (impostor_caustics.h) against raycore's photon-traced reference (raycore/tracer_caustics.h).
#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "core/path.h"
#include "impostor_renderer.h"
#include "impostor_scene.h"
#include "raycore/tracer_caustics.h"

namespace rg::impostors {

struct CausticsComparison {
    nlohmann::json json;      // settings, pass timings and counters, the scores
    ray::Image ours, reference, shadows;
};

// The photon-traced reference's options for what `r` draws: its board plane, texture space
// and extent, the light map's size and the splat σ of `s`, `photonsPerAxis`² photons per
// glass object and light, through the scene's glass objects.
ray::CausticTraceOptions causticTraceOptions(const ImpostorRenderer& r, const ImpostorScene& scene,
                                             const ImpostorSettings& s, int photonsPerAxis);

// Renders the scene (static mode, the mover at u) with caustics on, times the caustics
// passes (all pieces, then the mover alone in separated mode), traces the reference with
// `referencePhotonsPerAxis`² photons per piece and light, and scores ours against it:
// PSNR with the reference's largest irradiance as the peak, the relative L1 error, the
// ratio of the energies, the Pearson correlation, and where the brightest caustics lie.
CausticsComparison compareCaustics(const ImpostorScene& scene, const ImpostorSettings& base, float u,
                                   int referencePhotonsPerAxis, int threads, Path path);

}  // namespace rg::impostors
