// Texture fetches of the programmable profile (geforce8800): what a fragment program's
// texture instructions compute (Direct3D 10 Sample, SampleLevel, SampleGrad, SampleCmp;
// GLSL texture, textureLod, textureGrad, shadow2D), on the same level choice, addressing
// and filter weights as the fixed-function units (docs/hardware.md, "Programmable
// profile: texture fetches").
//
// A fetch is split in two steps, as on the hardware: the level of detail λ (from the
// coordinates of the 2×2 quad, from explicit gradients, or given), then the filtered
// texel. The result is float RGBA: 8-bit texels as v/255, float texels as stored, the
// weighted sum in double in tap order (resolveTapsFloat). The reference path builds the
// tap list; the fast path computes the same sum without it, bit for bit
// (tests/programmable/test_program_fetch.cpp).
#pragma once

#include <array>
#include <cstdint>

#include <glm/vec4.hpp>

#include "core/path.h"
#include "texunit/sampler.h"
#include "texunit/texture.h"

namespace rg::tex {

// λ (biased and clamped, kLodFracBits fixed point) from one coordinate at the quad's
// pixels 0, 1 (x + 1) and 2 (y + 1) — pixel 3 is not read (quadLambda). Cube-map
// coordinates are directions, measured on pixel 0's face as the fixed-function units do.
int32_t programLambdaQuad(const Texture& t, const SamplerState& s,
                          const std::array<glm::vec4, 4>& quad);
// λ from explicit screen-space gradients (SampleGrad): the quad (c, c + ddx, c + ddy).
int32_t programLambdaGrad(const Texture& t, const SamplerState& s, const glm::vec4& c,
                          const glm::vec4& ddx, const glm::vec4& ddy);
// λ from an explicit level of detail (SampleLevel / textureLod), with the sampler's bias
// and MIN_LOD/MAX_LOD clamp applied as for any λ (GL 3.0 §3.8.8).
int32_t programLambdaLod(const SamplerState& s, float lod);

// The filtered texel at `c` ((s, t, r) or a cube direction) for a λ from above. Adds the
// texels read to `fetches`.
glm::vec4 programFetch(const Texture& t, const SamplerState& s, const glm::vec4& c,
                       int32_t lambda, Path path, uint32_t& fetches);

// Depth compare (shadow maps, SampleCmp / shadow2D): each tap passes when
// ref ≤ texel depth (GL_LEQUAL, the GL 1.4 default) and the filter weights sum the
// passing taps, so LINEAR filtering gives 2×2 percentage-closer filtering as on the G80.
// Depth textures only; returns a value in [0, 1].
float programFetchCompare(const Texture& t, const SamplerState& s, const glm::vec4& c,
                          float ref, int32_t lambda, Path path, uint32_t& fetches);

}  // namespace rg::tex
