// Sampling: level of detail, addressing and filtering of one texture
// (docs/hardware.md, "Level of detail", "Filtering").
//
// Every sample is expressed as a list of texel taps with integer weights that sum to
// 2^weightBits; the filtered colour is round(Σ weight·texel / 2^weightBits). The reference
// path literally builds that list (gatherTaps) and resolves it; the fast path computes the
// same sum without the list. The PEM demo's instrumented query returns the same list.
#pragma once

#include <array>
#include <cstdint>

#include <glm/vec4.hpp>

#include "core/color.h"
#include "texunit/texture.h"

namespace rg::tex {

// D3DTEXTUREADDRESS / GL wrap modes. Clamp is OpenGL 1.2's CLAMP (coordinate clamped to
// [0, 1], linear filtering then reaches the border colour at the edges); ClampToEdge is
// GL_CLAMP_TO_EDGE and D3DTADDRESS_CLAMP; Border is D3DTADDRESS_BORDER /
// CLAMP_TO_BORDER (texels outside the level are the border colour).
enum class AddressMode : uint8_t { Wrap, Mirror, Clamp, ClampToEdge, Border };
enum class FilterMode : uint8_t { Nearest, Linear };
// D3DTFP_NONE/POINT/LINEAR; with FilterMode they make the four GL mipmap min filters:
// NEAREST_MIPMAP_NEAREST = (Nearest, Nearest), LINEAR_MIPMAP_NEAREST = (Linear, Nearest),
// NEAREST_MIPMAP_LINEAR = (Nearest, Linear), LINEAR_MIPMAP_LINEAR = (Linear, Linear).
enum class MipMode : uint8_t { None, Nearest, Linear };

struct SamplerState {
    std::array<AddressMode, 4> address{AddressMode::Wrap, AddressMode::Wrap, AddressMode::Wrap,
                                       AddressMode::Wrap};  // s, t, r, q (4D)
    FilterMode magFilter = FilterMode::Linear;
    FilterMode minFilter = FilterMode::Linear;
    MipMode mipFilter = MipMode::None;
    uint8_t pad0 = 0;
    float lodBias = 0.0f;     // D3DTSS_MIPMAPLODBIAS / EXT_texture_lod_bias
    float minLod = -1000.0f;  // GL 1.2 TEXTURE_MIN_LOD
    float maxLod = 1000.0f;   // GL 1.2 TEXTURE_MAX_LOD
    int32_t baseLevel = 0;    // GL 1.2 TEXTURE_BASE_LEVEL / D3DTSS_MAXMIPLEVEL
    int32_t maxLevel = 1000;  // GL 1.2 TEXTURE_MAX_LEVEL
    Rgba8 borderColor{};      // D3DTSS_BORDERCOLOR / TEXTURE_BORDER_COLOR
    friend bool operator==(const SamplerState&, const SamplerState&) = default;
};

// ---- precision (docs/hardware.md, "Pinned choices") ------------------------------------
constexpr int kSubTexelBits = 8;   // fraction bits of a texel coordinate (bilinear weights)
constexpr int kLodFracBits = 8;    // fraction bits of λ (mip blend weight)
constexpr int32_t kLodOne = 1 << kLodFracBits;

// λ in fixed point (kLodFracBits) for the whole 2×2 quad, before bias and clamps:
// ½·log2(ρ²) with log2 taken piecewise-linearly from the float bits of ρ², where
// ρ² = max(|∂u/∂x|², |∂u/∂y|²) over the texture's dimensions in level-`baseLevel` texels.
// `coords` are the four pixels' coordinates after projection (and for cube maps after
// face mapping: see cubeQuadCoords()).
int32_t log2Fixed(float x);  // ⌊log2approx(x)·2^kLodFracBits⌋
int32_t quadLambda(const std::array<glm::vec4, 4>& coords, const std::array<int, 4>& size,
                   int dims);
// Bias and the MIN_LOD/MAX_LOD clamp (GL 1.2 §3.8.7): λ' = clamp(λ + bias).
int32_t biasAndClampLambda(int32_t lambda, const SamplerState& s);

// One texel contributing to a sample.
struct TexelTap {
    uint8_t level = 0;
    uint8_t face = 0;
    uint8_t border = 0;        // 1: outside the level under Clamp/Border: the border colour
    uint8_t pad = 0;
    std::array<int32_t, 4> xyzw{};  // texel coordinates inside the level (unused dims 0)
    uint64_t weight = 0;       // out of 2^weightBits
};

struct TapList {
    static constexpr int kMax = 32;  // 4D quadrilinear × 2 levels
    std::array<TexelTap, kMax> taps{};
    int count = 0;
    int weightBits = 0;
    double weightOf(int i) const { return double(taps[i].weight) / double(uint64_t(1) << weightBits); }
};

// Which levels a λ selects and with which weights (GL 1.2 §3.8.8).
struct LevelChoice {
    FilterMode filter;       // min or mag filter
    int level0, level1;      // level1 == level0 unless blending
    int32_t frac;            // weight of level1 in [0, kLodOne)
    bool blend;              // MipMode::Linear between two distinct levels
};
LevelChoice chooseLevels(const Texture& t, const SamplerState& s, int32_t lambda);

// Texel taps for one sample. `coord` is (s, t, r, q) after projection for 1D/2D/3D, the
// 4D coordinate for 4D textures; for cube maps it must be (s, t, face, 0) from
// selectCubeFace(), and addressing is forced to ClampToEdge (no seamless filtering on
// the period hardware). `lambda` is the biased, clamped λ.
void gatherTaps(const Texture& t, const SamplerState& s, const glm::vec4& coord,
                int32_t lambda, TapList& out);
// round(Σ weight·texel / 2^weightBits) (8-bit formats); float formats blend in float in
// tap order and convert with floatToRgba8().
Rgba8 resolveTaps(const Texture& t, const SamplerState& s, const TapList& taps);
// I16 textures: the 16-bit filtered intensity, round(Σ weight·v / 2^weightBits) with
// v the stored 16-bit values (a border tap reads the border colour's red as 257·r).
uint16_t resolveTaps16(const Texture& t, const SamplerState& s, const TapList& taps);
// The filtered colour in float, for every format (8-bit texels as v/255): for the
// geforce8800 programmable profile, whose shaders see unclamped float texels.
glm::vec4 resolveTapsFloat(const Texture& t, const SamplerState& s, const TapList& taps);
// The same result as resolveTaps(gatherTaps(...)) for 1D/2D/cube 8-bit textures without
// building the list (falls back to it otherwise).
Rgba8 sampleFast(const Texture& t, const SamplerState& s, const glm::vec4& coord,
                 int32_t lambda);
// sampleFast for the four pixels of a quad sharing one λ (the level choice is made once).
// Returns the texel fetches the reference would count.
uint64_t sampleQuadFast(const Texture& t, const SamplerState& s,
                        const std::array<glm::vec4, 4>& coords, int32_t lambda,
                        std::array<Rgba8, 4>& out);

}  // namespace rg::tex
