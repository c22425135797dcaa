// Per-frame counters, reset by Device::beginFrame(); printed by --stats.
#pragma once

#include <cstdint>
#include <string>

#include "texunit/texture_units.h"

namespace rg::raster {

struct Counters {
    uint64_t passes = 0;              // Device::beginPass() calls
    uint64_t drawCalls = 0;
    uint64_t trianglesSubmitted = 0;
    uint64_t trianglesCulled = 0;     // back-face, zero-area or entirely outside the frustum
    uint64_t trianglesClipped = 0;    // crossed the near/far plane or the guard band
    uint64_t trianglesDrawn = 0;      // reached rasterization
    uint64_t trianglesInvalid = 0;    // dropped for NaN/Inf coordinates
    uint64_t fragmentsGenerated = 0;  // covered pixels after scissor
    uint64_t fragmentsWritten = 0;    // passed alpha and depth tests
    uint64_t blendOps = 0;
    uint64_t bytesReadBack = 0;
    tex::TextureCounters texture;

    std::string toString() const;     // one "name value" line per counter
};

}  // namespace rg::raster
