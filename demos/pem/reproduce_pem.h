// `retroglass reproduce pem`: Hakura, Snyder & Lengyel, "Parameterized Environment Maps",
// I3D 2001, end to end on the geforce256 profile.
#pragma once

#include <nlohmann/json.hpp>

#include "pem_precompute.h"
#include "reproductions.h"

namespace rg::pem {

int reproducePem(const demos::ReproduceOptions& options);

// The reproduction at explicit settings (tests run it small). Writes the figures,
// report.md and results.json into options.outDir and returns the results; returns an empty
// object after a partial precompute (--views A:B).
nlohmann::json runPem(PemSettings settings, const demos::ReproduceOptions& options);

}  // namespace rg::pem
