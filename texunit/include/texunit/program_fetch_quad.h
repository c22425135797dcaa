// A fragment program's implicit-λ fetch (Sample, GLSL texture) of an 8-bit 2D texture
// with LINEAR filtering, for the four pixels of a quad at once (geforce8800): what
// programFetch's fast path computes lane by lane, bit for bit, with the four lanes' taps
// summed side by side. The board of the impostors' chess scene reads its mipmapped RGBA8
// albedo this way in every board fragment, and the per-lane fetch was a quarter of its
// frame (docs/performance.md, "The board's trilinear fetch").
//
// Kept out of program_fetch.h, which the programmable device's public headers include:
// only the device's quad context calls it (rasterizer/programmable.cpp).
#pragma once

#include <array>
#include <cstdint>

#include <glm/vec4.hpp>

#include "texunit/sampler.h"
#include "texunit/texture.h"

namespace rg::tex {

// Whether programFetchQuad8 computes this texture and sampler's fetch: an 8-bit (not float)
// 2D texture, LINEAR min and mag filters with any mip filter, and on each axis
// CLAMP_TO_EDGE, or WRAP at a power-of-two base size (so every level's wrap is a mask).
// Those never read the border colour, and their footprint is the same 2×2 at every level.
bool quadFetch8Applies(const Texture& t, const SamplerState& s);

// The fetch of the lanes set in `lanes` (bit i: pixel i) at coordinates c[i].xy, all at
// the quad's one λ: the levels of chooseLevels, each level's 2×2 footprint of
// axisFootprint, Σ weight·(texel/255) in double in the tap list's order (level 0's taps,
// then level 1's; y outer, x inner), rounded to float — the bits programFetch gives each
// lane on either path. Lanes outside `lanes` get zero and no fetches; the others add their
// taps to fetches[i]. Needs AVX2 (avx2Enabled()); the caller checks quadFetch8Applies.
void programFetchQuad8(const Texture& t, const SamplerState& s, const std::array<glm::vec4, 4>& c,
                       int32_t lambda, uint32_t lanes, std::array<glm::vec4, 4>& out,
                       std::array<uint32_t, 4>& fetches);

}  // namespace rg::tex
