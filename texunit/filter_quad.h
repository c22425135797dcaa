// Internal: the per-quad sampling kernels of the fast path, compiled once per state
// change (TextureUnits::refresh) instead of re-derived per quad (SwiftShader's compiled
// pixel routines, in miniature: a function pointer chosen from the hashed-down stage
// state).
//
// A kernel does for one stage and one 2×2 quad what TextureUnits::sampleStage does on the
// fast path — projection or cube-face selection, one λ, the level choice, filtering — for
// the states that dominate real frames: 8-bit 1D, 2D and cube textures, no colour table,
// and per used axis CLAMP_TO_EDGE or WRAP on power-of-two extents (cube faces always
// clamp to edge). Every other state keeps the generic path (sampleStage). The arithmetic
// is the reference's (docs/hardware.md, "Level of detail", "Filtering"): same float
// operations in the same order for the coordinates and λ, and the integer weighted sum
// evaluated exactly (filter_quad.cpp explains the SSE2 form); TextureUnits tests compare
// the paths.
#pragma once

#include <emmintrin.h>

#include <array>
#include <cstdint>
#include <glm/vec4.hpp>

#include "addressing.h"
#include "core/color.h"
#include "texunit/sampler.h"
#include "texunit/stages.h"
#include "texunit/texture.h"
#include "texunit/texture_units.h"

namespace rg::tex::detail {

struct QuadSampler;
// What a kernel derives from the coordinates and the texture's shape alone: the level
// choice, and per level used and pixel the tap indices (from the level's data; face
// included) and packed weight pairs ((256 − α) | α << 16).
struct QuadFootprint {
    LevelChoice ch;
    uint64_t fetches;
    alignas(16) int32_t i00[2][4], i01[2][4], i10[2][4], i11[2][4];
    alignas(16) int32_t wx[2][4], wy[2][4];
    // Per level (AVX2 LINEAR kernels only): every pixel's second x tap is the texel after
    // its first (i01 = i00 + 1, i11 = i10 + 1), so each row pair is one 8-byte load.
    bool adjacent[2] = {false, false};
};
// Samples one stage for the four pixels of a quad from its coordinate set `in` (s, t, r,
// q per pixel, before any divide) into `out` (pixel p in bytes 4p..4p+3, the layout of
// std::array<Rgba8, 4>); returns the texel fetches the reference would count.
using QuadSampleFn = uint64_t (*)(const QuadSampler&, const std::array<glm::vec4, 4>& in,
                                  __m128i& out);
// The kernel in two phases, for stages that share a footprint (sameFootprint).
using QuadPrepareFn = uint64_t (*)(const QuadSampler&, const std::array<glm::vec4, 4>& in,
                                   QuadFootprint& fp);
using QuadGatherFn = __m128i (*)(const QuadSampler&, const QuadFootprint& fp);

// One mipmap level as the kernels address it: face f starts at data + f·faceStride.
struct LevelView {
    const Rgba8* data = nullptr;
    uint32_t faceStride = 0;
    int32_t width = 1, height = 1;
};

struct QuadSampler {
    static constexpr int kMaxLevels = 16;
    QuadSampleFn fn = nullptr;  // null: the generic path
    QuadPrepareFn prepare = nullptr;
    QuadGatherFn gather = nullptr;
    const Texture* texture = nullptr;
    SamplerState sampler{};
    bool projected = false;  // divide by q (1D/2D)
    // Fixed point (kLodFracBits): λ' = clamp(λ + lodBias, lodMin, lodMax).
    int32_t lodBias = 0, lodMin = 0, lodMax = 0;
    std::array<int, 4> baseSize{1, 1, 1, 1};  // level-base extent (λ is measured in it)
    float baseSizeF[2] = {1.0f, 1.0f};        // the same as floats
    LevelParams levels{};                     // chooseLevels' inputs
    bool constantChoice = false;  // MAG = MIN, no mipmaps or q = base: `choice` whatever λ is
    LevelChoice choice{};
    std::array<LevelView, kMaxLevels> level{};
};

// True when b, fed the same coordinate set, has a's footprint: same kernel, λ parameters,
// level choice parameters and level extents (the texels may differ). The PEM viewer's
// two cube maps blended by BLENDFACTORALPHA are the case this is for.
bool sameFootprint(const QuadSampler& a, const QuadSampler& b);

struct CompiledStages;
// The whole fast-path cascade of a quad in one function, for the commonest states
// (compileCascade): the stages' samplers and arithmetic inlined into one body. Returns the
// texel fetches; `out` as QuadSampleFn's.
using CascadeFn = uint64_t (*)(const CompiledStages&, const FragmentQuad& quad,
                               __m128i tfactor, __m128i& out);

// The same cascade for both quads of a FragmentQuadPair; out[4h..4h+3] quad h's colours
// (zero without coverage), each quad one 16-byte store. Returns the fetches of the covered
// quads.
using CascadePairFn = uint64_t (*)(const CompiledStages&, const FragmentQuadPair& pair,
                                   __m128i tfactor, Rgba8* out);

// The compiled samplers of all stages (TextureUnits holds one, rebuilt by its setters).
struct CompiledStages {
    std::array<QuadSampler, 16> stage{};
    std::array<uint8_t, 16>
        stageKernel{};  // quad::StageKernel of each stage (stage_arith.h)
    // Bit i: stage i reuses stage i − 1's footprint (same coordinate set, sameFootprint);
    // stage i − 1 then runs its kernel in two phases and keeps the footprint.
    uint32_t sharesFootprint = 0;
    std::array<StageState, 16> state{};  // the stages' states (for `cascade`)
    CascadeFn cascade = nullptr;         // null: TextureUnits::shadeQuad's general loop
    CascadePairFn cascadePair = nullptr;  // set with `cascade`
};

// Sets c.cascade when the `active` stages (c.state, c.stage, c.stageKernel filled) are
// one of the specialised combinations, with no premodulation or shared footprint: every
// stage sampling through an AVX2 kernel with MODULATE colour and alpha — one 2D or cube
// stage (GL MODULATE), or a cube stage then a 1D stage (the PEM pass) — or the hybrid
// layer pass: a cube stage MODULATE(TEXTURE, DIFFUSE) with alpha SELECTARG1(TEXTURE),
// alone or followed by a stage that samples nothing, MODULATE(CURRENT, TFACTOR) with
// alpha SELECTARG1(CURRENT).
void compileCascade(CompiledStages& c, int active, uint32_t sampling);

// Chooses the kernel for a stage's texture and sampler, or leaves fn null when the state
// needs the generic path (float formats, 3D/4D, colour tables, other address modes).
QuadSampler compileQuadSampler(const Texture& t, const SamplerState& s, bool projected,
                               bool hasColorTable);

}  // namespace rg::tex::detail
