// Figure 6 of Davis & Wyman 2007 as a measurement: after each binary search the method
// holds two candidates, one from the back-facing and one from the front-facing depth map,
// and keeps "the point that is more closely aligned with the ray" (004 §3). How often is
// that the map holding the surface the ray really meets? The reference answers it: raycore's
// TIR path tracer records, for every hit that ends a segment inside the glass, whether the
// triangle faces away from the eye (the back map) or towards it (the front map).
//
// The search is replayed on the CPU, per pixel, with the same code the fragment program
// runs (tir_search.h, scalar lanes) on the maps the emulated device rendered, starting from
// the front map's point and normal under the pixel's centre; the reference traces the
// pixel-centre ray. A bounce is compared while both paths are still inside the glass, so
// the figures describe the choice, not the drift of one path from the other.
#pragma once

#include <vector>

#include "raycore/camera.h"
#include "raycore/image.h"
#include "tir_renderer.h"
#include "tir_scene.h"

namespace rg::tir {

struct BounceAgreement {
    int searching = 0;     // pixels whose search is still inside the glass at this bounce
    int missed = 0;        // … of which both candidates miss ("done bouncing")
    int compared = 0;      // … with a candidate while the reference path is also still inside
    int agree = 0;         // … whose chosen map is the one holding the reference's hit
    int backIsRight = 0;   // … whose reference hit is back-facing (what back-only would pick)
    int frontChosen = 0;   // … where the front candidate was taken
    int frontCaught = 0;   // … where it was taken and the reference's hit is front-facing
    int frontIsRight() const { return compared - backIsRight; }
    // Of the hits on front-facing surfaces, the share the choice finds (back-only: none).
    double frontRecall() const { return frontIsRight() ? double(frontCaught) / frontIsRight() : 0.0; }
    double agreement() const { return compared ? double(agree) / compared : 0.0; }
    double backOnlyAgreement() const { return compared ? double(backIsRight) / compared : 0.0; }
    double missRate() const { return searching ? double(missed) / searching : 0.0; }
};

struct ChoiceAnalysis {
    int pixels = 0;                        // pixels whose centre ray meets the refractor first
    std::vector<BounceAgreement> bounces;  // one per searched bounce
    // Per pixel and bounce (one panel per bounce, side by side): green the back map chosen
    // and right, blue the front map chosen and right, red the wrong map, yellow both
    // candidates missed, grey the reference path already left the glass, black no refractor.
    ray::Image image;
};

// Renders `camera` at size² with front and back maps and `bounces` bounces (the renderer's
// last frame changes), then compares every refractor pixel's choices with the reference.
ChoiceAnalysis analyseFrontBackChoice(TirRenderer& renderer, const TirScene& scene, const ray::Camera& camera,
                                      int size, int bounces);

}  // namespace rg::tir
