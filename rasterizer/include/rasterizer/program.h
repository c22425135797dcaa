// What the programmable profile (geforce8800) runs: vertex and fragment programs written
// in C++, and the state of the output merger they write through (docs/hardware.md,
// "Programmable profile").
//
// A program is a plain C++ type, so that the pipeline instantiates its inner loop for it
// and the compiler inlines the program there — no call through a pointer per fragment:
//
//   struct MyVertexProgram {
//       static constexpr int kVaryings = 1;            // vec4 varyings written
//       glm::vec4 operator()(const MyVertex& v, Varyings& out) const {
//           out[0] = glm::vec4(v.uv, 0, 1);
//           return mvp * v.position;                   // clip-space position
//       }
//   };
//   struct MyFragmentProgram {
//       static constexpr int kVaryings = 1;            // must match the vertex program
//       static constexpr uint32_t kTargets = 0b1;      // render targets written
//       static constexpr uint32_t kUnits = 0b1;        // texture units read
//       static constexpr bool kWritesDepth = false;    // true: disables the early depth test
//       void operator()(FragmentContext& f) const {
//           f.output(0, f.sample(0, 0));               // unit 0 at varying 0, implicit LOD
//       }
//   };
//
// The declarations are checked at draw time (targets attached, units bound) so that a
// mistake is an error naming it before any pixel is written; a program that reads a unit
// or writes a target it did not declare is an error too (rg::InvalidState).
//
// A vertex program may read textures too (vertex texture fetch, as the G80 did under
// Direct3D 10 and GL_NV_gpu_program4 / GLSL 1.30): it declares the units it reads in
// kVertexUnits and takes a VertexContext, which offers only the reads without derivatives
// (texelFetch / Load, textureLod / SampleLevel):
//
//   struct SplatVertexProgram {
//       static constexpr int kVaryings = 1;
//       static constexpr uint32_t kVertexUnits = 0b1;  // texture units the vertex stage reads
//       glm::vec4 operator()(const MyVertex& v, Varyings& out, VertexContext& t) const {
//           const glm::vec4 hit = t.texelFetch(0, v.texel);   // level 0, no filtering
//           ...
//       }
//   };
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <string>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/path.h"
#include "rasterizer/state.h"
#include "texunit/cube_mapping.h"
#include "texunit/sampler.h"
#include "texunit/texture.h"

namespace rg::raster {

constexpr int kMaxVaryings = 8;      // vec4 varyings (Direct3D 9 SM3 had 10, GL on G80 15)
constexpr int kMaxColorTargets = 4;  // simultaneous render targets a program writes
constexpr int kMaxProgramUnits = 16; // G80: 16 texture image units per fragment program
constexpr int kMaxVertexUnits = 16;  // G80: MAX_VERTEX_TEXTURE_IMAGE_UNITS 16 (D3D10: 16 slots per stage)

using Varyings = std::array<glm::vec4, kMaxVaryings>;

// One colour attachment: a level (and cube face) of a texture made by
// tex::TextureMemory::createRenderTarget(). Formats: RGBA8, R16F, RGBA16F, R32F, RGBA32F.
struct ColorTarget {
    std::shared_ptr<tex::Texture> texture;
    int level = 0;
    int face = 0;
};

// The depth attachment: a Depth24 or Depth32F render-target texture, sampled later as a
// shadow map (depth compare) or as plain float depth.
struct DepthTarget {
    std::shared_ptr<tex::Texture> texture;
    int level = 0;
    int face = 0;
};

// Per-target blending (Direct3D 10 D3D10_BLEND_DESC with independent blend, as the G80
// supported through its OpenGL drivers). Float targets blend in single precision; RGBA8
// targets use the fixed-function 8-bit blend (fragment_ops.h).
struct TargetBlend {
    uint8_t enable = 0;
    BlendFactor src = BlendFactor::One;
    BlendFactor dst = BlendFactor::Zero;
    BlendOp op = BlendOp::Add;
    uint8_t writeMask = kWriteRGBA;
    friend bool operator==(const TargetBlend&, const TargetBlend&) = default;
};

struct ProgramState {
    CullMode cull = CullMode::None;  // Direct3D 10 rasterizer default is BACK; GL's is off
    uint8_t depthTest = 0;
    uint8_t depthWrite = 0;
    CompareFunc depthFunc = CompareFunc::Less;  // D3D10 default D3D10_COMPARISON_LESS
    uint8_t pad = 0;
    float pointSize = 1.0f;  // edge of a point's square, pixels (photon splats)
    std::array<TargetBlend, kMaxColorTargets> blend{};
};

enum class ProgramPrimitive : uint8_t { TriangleList, TriangleStrip, TriangleFan, PointList };

// Per-frame counters of the programmable pipeline (reset by beginFrame).
struct ProgramCounters {
    uint64_t drawCalls = 0;
    uint64_t vertexInvocations = 0;
    uint64_t primitivesSubmitted = 0;   // triangles, or points
    uint64_t trianglesDrawn = 0;        // reached rasterization (points count as two)
    uint64_t trianglesCulled = 0;
    uint64_t trianglesClipped = 0;
    uint64_t primitivesInvalid = 0;     // dropped for NaN/Inf clip positions
    uint64_t fragmentsGenerated = 0;    // covered pixels
    uint64_t fragmentsDepthFailed = 0;  // failed the (early or late) depth test
    uint64_t fragmentInvocations = 0;   // fragment-program runs
    uint64_t fragmentsDiscarded = 0;
    uint64_t fragmentsWritten = 0;      // reached the targets
    uint64_t textureFetches = 0;        // texels read by fragment programs
    uint64_t vertexTextureFetches = 0;  // texels read by vertex programs (vertex texture fetch)
    uint64_t maxFetchesPerFragment = 0;
    double meanFetchesPerFragment() const {
        return fragmentInvocations ? double(textureFetches) / double(fragmentInvocations) : 0.0;
    }
    void add(const ProgramCounters& o);
    std::string toString() const;  // one "name value" line per counter
};

namespace detail {

// The values of every varying at the four pixels of a 2×2 quad (pixel i at x + (i & 1),
// y + (i >> 1)); uncovered pixels are extrapolated from the planes so derivatives exist.
struct QuadVaryings {
    std::array<std::array<glm::vec4, 4>, kMaxVaryings + 1> v;  // + the point coordinate
};

inline int nearestTexel(float c, int n, bool wrap) {
    // ⌊c·n⌋ as the sampler computes it (texunit/addressing.h: toSubTexel, NaN → 0,
    // clamped to ±2^22), then the address mode.
    float u = c * float(n);
    if (!(u == u)) u = 0.0f;
    u = std::clamp(u, -4194304.0f, 4194304.0f);
    int i = int(u);
    if (float(i) > u) --i;
    if (!wrap) return std::clamp(i, 0, n - 1);
    if ((n & (n - 1)) == 0) return i & (n - 1);
    const int r = i % n;
    return r < 0 ? r + n : r;
}

// Point sampling of a float 1D/2D texture whose sampler has NEAREST min and mag filters and
// no mipmaps, with WRAP or CLAMP_TO_EDGE addressing: every λ selects the nearest texel of
// the base level, so the fetch needs no level of detail. The depth and normal maps of the
// image-space searches (tir, impostors) are read this way, many times per fragment; the
// result is the tap-list reference's bit for bit (tests/programmable/).
//
// Cube maps point-sampled the same way (`cube`): the face and (s, t) of
// tex::selectCubeFace, then ⌊s·n⌋ and ⌊t·n⌋ clamped to the face (cube maps clamp to their
// edges whatever the address mode); the faces of the base level lie one after another
// (faceTexels apart). The distance impostors of Dancsik & Minarik are read this way.
struct NearestFloat2D {
    const glm::vec4* data4 = nullptr;  // base level, row-major (RGBA16F, RGBA32F), or
    const float* data1 = nullptr;      // (R16F, R32F, depth); both null: not this case
    bool depth = false;                // data1 expands to (d, d, d, 1), else (r, 0, 0, 1)
    int width = 0, height = 0;
    bool wrapS = false, wrapT = false;  // else clamp to edge
    // Set where the four-lane fetch (quad_program.h: detail::nearestIndices) applies: WRAP axes
    // have power-of-two sizes. widthShift: log2(width) for a power of two, else −1.
    bool lanes4 = false;
    int widthShift = -1;
    // Where lanes4 is set, one axis of the wide fetch (quad_program_wide.h) without a branch
    // on the address mode: texel (t + (float(t) > u)) & mask, t = trunc(u), u =
    // min(max(c·scale, lo), hi). WRAP: lo, hi = ∓2^22, mask = size − 1; CLAMP_TO_EDGE:
    // lo = 0, hi = size − 1, mask = −1 (u is then a non-negative float, so t ≤ u and the
    // step down never fires); a 1D texture's t axis: size 1, texel 0 either way.
    struct Axis {
        float scale = 0.0f, lo = 0.0f, hi = 0.0f;
        int32_t mask = 0;
    };
    Axis axisS, axisT;
    bool cube = false;
    size_t faceTexels = 0;  // cube: texels per face (the next face's offset)
    bool valid() const { return data4 || data1; }
    // The tap list's Σ 1·texel in double is the texel itself, with −0 turned into +0.
    glm::vec4 fetchCube(const glm::vec3& dir) const {
        const tex::CubeCoord cc = tex::selectCubeFace(dir);
        const int x = nearestTexel(cc.s, width, false), y = nearestTexel(cc.t, height, false);
        const size_t i = size_t(int(cc.face)) * faceTexels + size_t(y) * size_t(width) + size_t(x);
        if (data4) return data4[i] + glm::vec4(0.0f);
        const float v = data1[i] + 0.0f;
        return depth ? glm::vec4(v, v, v, 1.0f) : glm::vec4(v, 0.0f, 0.0f, 1.0f);
    }
    glm::vec4 fetch(float s, float t) const {
        const int x = nearestTexel(s, width, wrapS);
        const int y = height == 1 ? 0 : nearestTexel(t, height, wrapT);
        const size_t i = size_t(y) * size_t(width) + size_t(x);
        if (data4) return data4[i] + glm::vec4(0.0f);
        const float v = data1[i] + 0.0f;
        return depth ? glm::vec4(v, v, v, 1.0f) : glm::vec4(v, 0.0f, 0.0f, 1.0f);
    }
};


// Bilinear filtering of a four-channel float cube map (RGBA16F, RGBA32F) whose sampler has
// LINEAR min and mag filters and no mipmaps: every λ selects the base level and its 2×2
// footprint on the face the direction selects (clamped to the face's edges), so the fetch
// needs no level of detail. The tir demo's exit rays read their environment this way, once
// per fragment; the AVX2 kernel's fetch (quad_program_wide.h: detail::linearCubeFetchAvx2)
// gives the tap-list reference's sum bit for bit (tests/programmable/).
struct LinearFloatCube {
    const glm::vec4* data = nullptr;  // base level, face 0; null: not this case
    int size = 0;                     // the base level's edge
    int32_t faceTexels = 0;           // from one face's texels to the next's
    bool valid() const { return data != nullptr; }
};

// The same for a four-channel float 2D texture whose sampler also has CLAMP_TO_EDGE in s
// and t: the base level's 2×2 footprint at (s, t) whatever λ, so an implicit-derivative
// fetch (`sample`) needs no λ either. The impostors' light and caustic maps are read this
// way, several times per board fragment; the AVX2 kernel's fetch
// (quad_program_wide.h: detail::linear2DFetchAvx2) gives the tap-list reference's sum bit
// for bit (tests/programmable/test_cube_lanes.cpp).
struct LinearFloat2D {
    const glm::vec4* data = nullptr;  // base level; null: not this case
    int width = 0, height = 0;
    bool valid() const { return data != nullptr; }
};

struct BoundUnit {
    const tex::Texture* texture = nullptr;
    tex::SamplerState sampler;
    NearestFloat2D nearest;
    LinearFloatCube cube;
    LinearFloat2D linear2D;
};

}  // namespace detail

// What a fragment program sees of its fragment. Derivatives and implicit level of detail
// come from the quad: ddx is the difference along the pixel's row of the quad, ddy along
// its column ("fine" derivatives). Only varyings have derivatives — for a computed
// coordinate, give the gradients (sampleGrad) or a level (sampleLevel).
class FragmentContext {
  public:
    const glm::vec4& varying(int k) const { return quad_->v[size_t(k)][size_t(pixel_)]; }
    glm::vec4 ddx(int k) const {
        const auto& q = quad_->v[size_t(k)];
        return q[size_t(pixel_ | 1)] - q[size_t(pixel_ & 2)];
    }
    glm::vec4 ddy(int k) const {
        const auto& q = quad_->v[size_t(k)];
        return q[size_t(pixel_ | 2)] - q[size_t(pixel_ & 1)];
    }
    // Window position of the pixel centre, window z and 1/w (gl_FragCoord, SV_Position).
    const glm::vec4& fragCoord() const { return fragCoord_; }
    // Point primitives: (0, 0) at the top-left corner of the square to (1, 1)
    // (gl_PointCoord); (0, 0) for triangles.
    glm::vec2 pointCoord() const {
        const glm::vec4& p = quad_->v[kMaxVaryings][size_t(pixel_)];
        return {p.x, p.y};
    }

    // ---- texture instructions (texunit/program_fetch.h) ----------------------------------
    // Unit `unit` at varying `k`, λ from that varying over the quad (texture2D, Sample).
    glm::vec4 sample(int unit, int k);
    // The same with the projective divide by the varying's w (texture2DProj).
    glm::vec4 sampleProj(int unit, int k);
    // At a computed coordinate with explicit gradients (textureGrad, SampleGrad).
    glm::vec4 sampleGrad(int unit, const glm::vec4& c, const glm::vec4& ddx, const glm::vec4& ddy);
    // At a computed coordinate on an explicit level of detail (textureLod, SampleLevel).
    glm::vec4 sampleLevel(int unit, const glm::vec4& c, float lod) {
        const detail::BoundUnit& b = this->unit(unit);
        if (b.nearest.valid() && setup_->path == Path::Fast) {
            ++fetches_;
            return b.nearest.cube ? b.nearest.fetchCube(glm::vec3(c)) : b.nearest.fetch(c.x, c.y);
        }
        return sampleLevelFiltered(b, c, lod);
    }
    // Depth compare on level 0: the filtered fraction of taps with ref ≤ depth (shadow2D).
    float sampleCompare(int unit, const glm::vec4& c, float ref);

    // ---- outputs -------------------------------------------------------------------------
    void discard() { discarded_ = true; }
    void output(int target, const glm::vec4& color) {
        if (target < 0 || target >= kMaxColorTargets || !((declaredTargets_ >> target) & 1u))
            undeclaredTarget(target);
        out_[size_t(target)] = color;
        written_ |= 1u << target;
    }
    void depth(float z) {
        depth_ = z;
        depthWritten_ = true;
    }

    // ---- used by the pipeline -------------------------------------------------------------
    struct Setup {
        const std::array<detail::BoundUnit, kMaxProgramUnits>* units = nullptr;
        uint32_t declaredUnits = 0;
        uint32_t declaredTargets = 0;
        Path path = Path::Fast;
    };
    void begin(const Setup& s, const detail::QuadVaryings* quad, int pixel, const glm::vec4& fragCoord) {
        setup_ = &s;
        declaredTargets_ = s.declaredTargets;
        quad_ = quad;
        pixel_ = pixel;
        fragCoord_ = fragCoord;
        discarded_ = false;
        depthWritten_ = false;
        written_ = 0;
        fetches_ = 0;
        depth_ = fragCoord.z;
    }
    bool discarded() const { return discarded_; }
    uint32_t written() const { return written_; }
    const glm::vec4& out(int target) const { return out_[size_t(target)]; }
    const std::array<glm::vec4, kMaxColorTargets>& outputs() const { return out_; }
    bool depthWritten() const { return depthWritten_; }
    float depthValue() const { return depth_; }
    uint32_t fetches() const { return fetches_; }

  private:
    const detail::BoundUnit& unit(int u) const {
        if (u < 0 || u >= kMaxProgramUnits || !((setup_->declaredUnits >> u) & 1u)) undeclaredUnit(u);
        return (*setup_->units)[size_t(u)];  // declared units are checked bound at draw time
    }
    [[noreturn]] void undeclaredUnit(int u) const;
    glm::vec4 sampleLevelFiltered(const detail::BoundUnit& b, const glm::vec4& c, float lod);
    [[noreturn]] void undeclaredTarget(int target) const;

    const Setup* setup_ = nullptr;
    uint32_t declaredTargets_ = 0;
    const detail::QuadVaryings* quad_ = nullptr;
    int pixel_ = 0;
    glm::vec4 fragCoord_{0.0f};
    bool discarded_ = false;
    bool depthWritten_ = false;
    uint32_t written_ = 0;
    uint32_t fetches_ = 0;
    float depth_ = 0.0f;
    std::array<glm::vec4, kMaxColorTargets> out_{};
};

// What a vertex program sees of the texture units (vertex texture fetch, docs/hardware.md
// "Programmable profile: vertex texture fetch"). A vertex has no neighbours, so there are
// no derivatives and no implicit level of detail: the G80's vertex stage offered the
// explicit-level reads only (GLSL 1.30 texelFetch and textureLod, Direct3D 10 Load and
// SampleLevel). The units are the ones setTexture binds for the fragment stage (GL's
// shared texture image units); the vertex program declares which it reads in kVertexUnits.
class VertexContext {
  public:
    // The texel (x, y) of `level` (and cube `face`) as stored, no sampler: no filtering,
    // addressing, bias or LOD clamp (GLSL texelFetch, D3D10 Load). 8-bit texels read as
    // v/255, float texels as stored, R formats as (r, 0, 0, 1), depth as (d, d, d, 1). A
    // texel outside the level, or a level or face the texture lacks, reads (0, 0, 0, 0)
    // (D3D10's out-of-bounds Load; GL leaves it undefined).
    glm::vec4 texelFetch(int unit, glm::ivec2 texel, int level = 0, int face = 0);
    // The sampler's filtered texel at `c` on the explicit level `lod` (textureLod,
    // SampleLevel): λ = lod in 8 fraction bits with the sampler's bias and MIN_LOD/MAX_LOD
    // clamp, then the fragment stage's level choice, addressing and filter.
    glm::vec4 sampleLevel(int unit, const glm::vec4& c, float lod);

    // ---- used by the pipeline -------------------------------------------------------------
    struct Setup {
        const std::array<detail::BoundUnit, kMaxProgramUnits>* units = nullptr;
        uint32_t declaredUnits = 0;
        Path path = Path::Fast;
    };
    explicit VertexContext(const Setup& s) : setup_(&s) {}
    uint64_t fetches() const { return fetches_; }

  private:
    const detail::BoundUnit& unit(int u) const;
    const Setup* setup_;
    uint64_t fetches_ = 0;
};

namespace detail {
// The texture units a vertex program declares (kVertexUnits), 0 for one that reads none.
template <class VP>
constexpr uint32_t vertexUnitsOf() {
    if constexpr (requires { VP::kVertexUnits; })
        return uint32_t(VP::kVertexUnits);
    else
        return 0u;
}
}  // namespace detail

}  // namespace rg::raster
