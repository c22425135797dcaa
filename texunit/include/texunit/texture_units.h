// The seam between the rasterizer and the texture units.
//
// The rasterizer owns one TextureUnits value per device. It calls it at two points of the
// pipeline and nowhere else:
//   - per vertex, processVertexTexCoord(): texture-coordinate generation (D3D7 TCI_*, the
//     OpenGL texgen modes) and the texture transform matrix;
//   - per 2×2 pixel quad, shadeQuad(): for each enabled stage, projective divide, LOD from
//     the quad's derivatives, mapping, filtering, colour table, and the stage's colour and
//     alpha operations; the result is the fragment colour before the specular add, fog,
//     alpha test and blending (Direct3D 7 pixel pipeline order, docs/hardware.md).
// and, for pixel transfers (draw/copy pixels), applyPixelTransfer() (SGIX_pixel_texture).
#pragma once

#include <emmintrin.h>

#include <array>
#include <cstdint>
#include <memory>
#include <span>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/color.h"
#include "core/path.h"
#include "core/profile.h"
#include "texunit/color_table.h"
#include "texunit/pixel_texture.h"
#include "texunit/sampler.h"
#include "texunit/stages.h"
#include "texunit/texgen.h"
#include "texunit/texture.h"

namespace rg::tex {

namespace detail {
struct FetchCounter;    // texunit/fetch_counter.h
struct CompiledStages;  // texunit/filter_quad.h
struct PixelTransferLut;  // texunit/pixel_texture.cpp
}

constexpr int kMaxTexCoordSets = 8;
constexpr int kMaxStages = 16;

// A vertex as texture-coordinate generation sees it.
struct VertexEye {
    glm::vec4 objectPosition;  // as submitted (object space, w = 1)
    glm::vec4 eyePosition;     // camera space: view · world · objectPosition
    glm::vec3 eyeNormal;       // camera space, normalized (inverse transpose of view · world)
    glm::vec3 objectNormal;    // as submitted
};

// A 2×2 pixel quad as the rasterizer hands it to the texture units. Pixel i sits at
// window (x + (i & 1), y + (i >> 1)). Pixels outside the primitive (coverage bit clear)
// still carry attributes extrapolated from the plane equations, so that screen-space
// derivatives — and hence LOD — are defined for every quad, as on the hardware.
struct FragmentQuad {
    int x = 0, y = 0;
    uint8_t coverage = 0;
    std::array<Rgba8, 4> diffuse{};
    std::array<Rgba8, 4> specular{};
    // [set][pixel] = (s, t, r, q), interpolated perspective-correctly; no divide by q yet.
    std::array<std::array<glm::vec4, 4>, kMaxTexCoordSets> texCoord{};
};

// Two quads side by side as the AVX2 rasterizer computes them, one component per
// 8-lane row: lanes 0–3 are quad 0's pixels 0–3, lanes 4–7 quad 1's (at x + 2). The
// same values as two FragmentQuads, without the transposes to and from per-pixel vectors.
struct FragmentQuadPair {
    int x = 0, y = 0;
    std::array<uint8_t, 2> coverage{};  // a quad without coverage is not shaded
    alignas(32) std::array<Rgba8, 8> diffuse{};
    alignas(32) std::array<Rgba8, 8> specular{};
    // [set][component][lane]: s, t, r, q, interpolated perspective-correctly; no divide.
    alignas(32) float texCoord[kMaxTexCoordSets][4][8];
};

// Per-frame texture counters (reset by the device with its own counters).
struct TextureCounters {
    uint64_t texelFetches = 0;
    uint64_t uploadBytes = 0;
};

// The fast path's compiled samplers use AVX2 where the CPU has it (the same bytes as
// their SSE2 twins); tests lower this to check the SSE2 kernels too. Applies to samplers
// compiled afterwards (the TextureUnits setters compile them).
void allowAvx2Kernels(bool allowed);

class TextureUnits {
  public:
    // ---- called by the rasterizer ----------------------------------------------------
    // Throws rg::UnsupportedFeature / rg::InvalidState for a state `profile` cannot draw
    // (more stages than it has, a cube map on a profile without cube maps, ...).
    void validate(const Profile& profile) const;
    // True when no stage reads a texture or changes the colour: out = diffuse.
    bool passThrough() const;
    // Bit i set: coordinate set i is read by some stage and must be interpolated.
    uint32_t texCoordSetsUsed() const;
    // Per vertex: coordinate set `set` after generation and the texture matrix.
    glm::vec4 processVertexTexCoord(int set, const VertexEye& v, const glm::vec4& in) const;
    // Per quad: the stage cascade. `out` receives the RGBA8 colour of all 4 pixels.
    void shadeQuad(const FragmentQuad& quad, std::array<Rgba8, 4>& out, Path path) const;
    // Whether shadeQuadPair serves the current state (a compiled whole-quad cascade).
    bool shadesPairs() const;
    // The fast path's shadeQuad of both quads of `pair` (only when shadesPairs()): the same
    // bytes; out[4h..4h+3] quad h's colours (zeros when it has no coverage). Returns the
    // texel fetches, which the caller hands to addFetches (once per run of pairs: the
    // counter's per-thread shard is a thread_local lookup).
    uint64_t shadeQuadPair(const FragmentQuadPair& pair, std::array<Rgba8, 8>& out) const;
    // shadeQuadPair as a callable a rasterizer run keeps (only when shadesPairs(); valid
    // until the next setter): the compiled cascade called directly, without the call
    // through TextureUnits per pair. The same function, so the same bytes and fetches.
    struct PairShader {
        using Fn = uint64_t (*)(const detail::CompiledStages&, const FragmentQuadPair&, __m128i,
                                Rgba8*);
        Fn fn = nullptr;
        const detail::CompiledStages* stages = nullptr;
        __m128i tfactor = _mm_setzero_si128();
        uint64_t operator()(const FragmentQuadPair& pair, std::array<Rgba8, 8>& out) const {
            return fn(*stages, pair, tfactor, out.data());
        }
    };
    PairShader pairShader() const;
    void addFetches(uint64_t n) const;
    // Pixel transfer of one row (SGIX_pixel_texture when enabled; identity otherwise).
    // The reference path builds each pixel's tap list; the fast path reads per-axis
    // footprint tables compiled with the state: the same bytes and fetch counts. Rows are
    // independent, so a caller may transfer several rows at once from many threads.
    void applyPixelTransfer(std::span<Rgba8> pixels, Path path) const;
    void applyPixelTransfer(std::span<Rgba8> pixels) const;  // the reference path
    // The pixel-texture part of validate(): Feature::PixelTexture (rg::UnsupportedFeature
    // naming the profile), a complete, non-cube texture, 4D and colour-table features.
    // Device::drawPixels and copyPixels call it when pixel texture is enabled.
    void validatePixelTexture(const Profile& profile) const;

    // ---- configured by applications -------------------------------------------------
    TextureUnits();
    // Stage i of the cascade (D3D7 SetTextureStageState; GL: texEnvStage/combineStage).
    // Stages past the first disabled colour op are ignored, as in Direct3D 7.
    void setStage(int stage, const StageState& state);
    const StageState& stage(int stage) const;
    // The texture a stage reads (D3D7 SetTexture; GL: the unit's bound texture). nullptr
    // unbinds: TEXTURE then reads opaque white.
    void setTexture(int stage, std::shared_ptr<const Texture> texture);
    const std::shared_ptr<const Texture>& texture(int stage) const;
    void setSampler(int stage, const SamplerState& sampler);
    const SamplerState& sampler(int stage) const;
    // SGI_texture_color_table of a unit (nullptr disables it).
    void setColorTable(int stage, std::shared_ptr<const ColorTable> table);
    const std::shared_ptr<const ColorTable>& colorTable(int stage) const {
        return units_[size_t(stage)].colorTable;
    }
    // D3DRENDERSTATE_TEXTUREFACTOR; on the OpenGL profiles the TEXTURE_ENV_COLOR.
    void setTextureFactor(Rgba8 factor);
    Rgba8 textureFactor() const { return tfactor_; }
    // Coordinate generation and texture matrix of coordinate set `set`.
    void setTexGen(int set, const TexGenState& state);
    const TexGenState& texGen(int set) const;
    void setPixelTexture(const PixelTextureState& state);
    const PixelTextureState& pixelTexture() const { return pixelTexture_; }
    // Optional: the memory whose upload bytes counters() reports.
    void setTextureMemory(std::shared_ptr<TextureMemory> memory);

    // Texel fetches since resetCounters() and the memory's upload bytes this frame.
    TextureCounters counters() const;
    void resetCounters();

    // ---- instrumented query (PEM rendering matrix) ------------------------------------
    // The texel taps stage `stage` reads for pixel `pixel` of `quad`: the same projection,
    // LOD, mapping and tap generation as shadeQuad's reference path (before the colour
    // table). Empty when the stage has no texture.
    TapList queryTaps(int stage, const FragmentQuad& quad, int pixel) const;
    // The texel colour per pixel of a stage (after the colour table), as shadeQuad sees it.
    std::array<Rgba8, 4> sampleStage(int stage, const FragmentQuad& quad, Path path) const;

  private:
    struct Unit {
        StageState stage;
        SamplerState sampler;
        std::shared_ptr<const Texture> texture;
        std::shared_ptr<const ColorTable> colorTable;
    };
    int activeStages() const;  // stages before the first colorOp == Disable
    bool readsTexture(int stage) const;
    // Re-derives active_, sampling_ and the compiled per-quad samplers after every setter
    // that changes what a stage samples, so the per-quad path reads them instead of
    // re-deriving them from the stage states.
    void refresh();
    int active_ = 0;         // activeStages()
    uint32_t sampling_ = 0;  // bit i: readsTexture(i), for i < active_
    void projectQuad(int stage, const FragmentQuad& quad, std::array<glm::vec4, 4>& coords,
                     int32_t& lambda) const;

    std::array<Unit, kMaxStages> units_{};
    std::array<TexGenState, kMaxTexCoordSets> texGen_{};
    Rgba8 tfactor_{255, 255, 255, 255};
    PixelTextureState pixelTexture_{};
    std::shared_ptr<TextureMemory> memory_;
    // Shared by copies; per-thread shards, added once per quad and stage / per row.
    std::shared_ptr<detail::FetchCounter> fetches_;
    // Immutable once built; copies share it (it points at textures units_ keeps alive).
    std::shared_ptr<const detail::CompiledStages> compiled_;
    // The pixel-transfer fast path's tables (null: the reference per pixel), rebuilt with
    // the state like compiled_.
    std::shared_ptr<const detail::PixelTransferLut> compilePixelTransfer() const;
    std::shared_ptr<const detail::PixelTransferLut> pixelLut_;
};

}  // namespace rg::tex
