// Figure 6 of Heidrich et al. 1999 (§5, "4D VQ"): "The textures that comprise the basis
// functions for a 2D 'light field', and the rays that each basis function corresponds to."
//
// The 2D light field has one eye-point axis s and one window axis u; VQ halves both, so a
// block holds 2×2 samples and the basis textures are 2×2 (the 2D analogue of the 2^4 4D
// textures). Two readings of "exactly two pixels are one":
//   one-hot     — one texel set, shifted once per parity class (4 in 2D, 16 in 4D): Σ = 1;
//   two pixels  — texel 0 and the opposite corner, shifted once per parity class: Σ = 2;
//                 only 2 (2D) or 8 (4D) of those shifts differ, and those alone sum to one,
//                 but then each basis covers two parity classes, whose samples one colour
//                 table cannot both return.
// Every basis value is a LINEAR (bilinear / quadrilinear) sample of the emulated texture
// unit (texunit gatherTaps / resolveTaps), as the basis passes compute it.
#pragma once

#include <nlohmann/json.hpp>

#include "core/profile.h"
#include "raycore/image.h"

namespace rg::lightfield {

struct Figure6 {
    ray::Image image;
    nlohmann::json sums;  // per dimension (2D, 4D) and reading: textures, Σ min / max, expected
};

// `profile` must have 4D textures (for the 4D sums); `points4D` random 4D coordinates.
Figure6 makeFigure6(const Profile& profile, int points4D = 20000);

}  // namespace rg::lightfield
