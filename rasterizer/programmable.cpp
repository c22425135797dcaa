// The programmable device (geforce8800): state, validation, primitive assembly, the
// fixed-function clip and setup, binning into tiles, and the output merger
// (docs/hardware.md, "Programmable profile").
#include "rasterizer/programmable_device.h"

#include <Imath/half.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cstdlib>
#include <cstring>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/cpu.h"
#include "core/error.h"
#include "pipeline.h"
#include "rasterizer/fragment_ops.h"
#include "rasterizer/trace.h"
#include "raster_tiles.h"
#include "core/tsan_annotations.h"
#include "texunit/format.h"
#include "texunit/program_fetch.h"
#include "texunit/program_fetch_quad.h"

namespace rg::raster {

static_assert(sizeof(detail::Plane) == 3 * sizeof(float), "planes are read as float triples");

// ---- counters ---------------------------------------------------------------------------

void ProgramCounters::add(const ProgramCounters& o) {
    drawCalls += o.drawCalls;
    vertexInvocations += o.vertexInvocations;
    primitivesSubmitted += o.primitivesSubmitted;
    trianglesDrawn += o.trianglesDrawn;
    trianglesCulled += o.trianglesCulled;
    trianglesClipped += o.trianglesClipped;
    primitivesInvalid += o.primitivesInvalid;
    fragmentsGenerated += o.fragmentsGenerated;
    fragmentsDepthFailed += o.fragmentsDepthFailed;
    fragmentInvocations += o.fragmentInvocations;
    fragmentsDiscarded += o.fragmentsDiscarded;
    fragmentsWritten += o.fragmentsWritten;
    textureFetches += o.textureFetches;
    vertexTextureFetches += o.vertexTextureFetches;
    maxFetchesPerFragment = std::max(maxFetchesPerFragment, o.maxFetchesPerFragment);
}

std::string ProgramCounters::toString() const {
    std::string s;
    auto line = [&](const char* name, uint64_t v) {
        s += name;
        s += ' ';
        s += std::to_string(v);
        s += '\n';
    };
    line("draw_calls", drawCalls);
    line("vertex_invocations", vertexInvocations);
    line("primitives_submitted", primitivesSubmitted);
    line("triangles_drawn", trianglesDrawn);
    line("triangles_culled", trianglesCulled);
    line("triangles_clipped", trianglesClipped);
    line("primitives_invalid", primitivesInvalid);
    line("fragments_generated", fragmentsGenerated);
    line("fragments_depth_failed", fragmentsDepthFailed);
    line("fragment_invocations", fragmentInvocations);
    line("fragments_discarded", fragmentsDiscarded);
    line("fragments_written", fragmentsWritten);
    line("texture_fetches", textureFetches);
    char mean[64];
    std::snprintf(mean, sizeof mean, "%.3f", meanFetchesPerFragment());
    s += "texture_fetches_per_fragment_mean ";
    s += mean;
    s += '\n';
    line("texture_fetches_per_fragment_max", maxFetchesPerFragment);
    line("vertex_texture_fetches", vertexTextureFetches);
    return s;
}

// ---- fragment context: texture instructions ---------------------------------------------

namespace {
// A program used a unit or target its type does not declare (kUnits, kTargets).
[[noreturn]] void undeclared(const char* program, bool unit, int index) {
    throw InvalidState(std::string(program) + (unit ? " reads texture unit " : " writes render target ") +
                       std::to_string(index) + ", which it does not declare in " +
                       (unit ? "kUnits" : "kTargets"));
}
}  // namespace

void FragmentContext::undeclaredUnit(int u) const { undeclared("fragment program", true, u); }
void FragmentContext::undeclaredTarget(int target) const { undeclared("fragment program", false, target); }

glm::vec4 FragmentContext::sample(int u, int k) {
    const detail::BoundUnit& b = unit(u);
    const auto& q = quad_->v[size_t(k)];
    const int32_t lambda = tex::programLambdaQuad(*b.texture, b.sampler, q);
    return tex::programFetch(*b.texture, b.sampler, q[size_t(pixel_)], lambda, setup_->path, fetches_);
}

glm::vec4 FragmentContext::sampleProj(int u, int k) {
    const detail::BoundUnit& b = unit(u);
    std::array<glm::vec4, 4> q;
    for (int p = 0; p < 4; ++p) {
        const glm::vec4& v = quad_->v[size_t(k)][size_t(p)];
        q[size_t(p)] = glm::vec4(v.x / v.w, v.y / v.w, v.z / v.w, 0.0f);
    }
    const int32_t lambda = tex::programLambdaQuad(*b.texture, b.sampler, q);
    return tex::programFetch(*b.texture, b.sampler, q[size_t(pixel_)], lambda, setup_->path, fetches_);
}

glm::vec4 FragmentContext::sampleGrad(int u, const glm::vec4& c, const glm::vec4& dx,
                                      const glm::vec4& dy) {
    const detail::BoundUnit& b = unit(u);
    const int32_t lambda = tex::programLambdaGrad(*b.texture, b.sampler, c, dx, dy);
    return tex::programFetch(*b.texture, b.sampler, c, lambda, setup_->path, fetches_);
}

glm::vec4 FragmentContext::sampleLevelFiltered(const detail::BoundUnit& b, const glm::vec4& c,
                                               float lod) {
    const int32_t lambda = tex::programLambdaLod(b.sampler, lod);
    return tex::programFetch(*b.texture, b.sampler, c, lambda, setup_->path, fetches_);
}

float FragmentContext::sampleCompare(int u, const glm::vec4& c, float ref) {
    const detail::BoundUnit& b = unit(u);
    const int32_t lambda = tex::programLambdaLod(b.sampler, 0.0f);
    return tex::programFetchCompare(*b.texture, b.sampler, c, ref, lambda, setup_->path, fetches_);
}

// ---- vertex context: vertex texture fetch ------------------------------------------------

const detail::BoundUnit& VertexContext::unit(int u) const {
    if (u < 0 || u >= kMaxVertexUnits || !((setup_->declaredUnits >> u) & 1u))
        throw InvalidState("vertex program reads texture unit " + std::to_string(u) +
                           ", which it does not declare in kVertexUnits");
    return (*setup_->units)[size_t(u)];  // declared units are checked bound at draw time
}

glm::vec4 VertexContext::texelFetch(int u, glm::ivec2 texel, int level, int face) {
    const detail::BoundUnit& b = unit(u);
    const tex::Texture& t = *b.texture;
    ++fetches_;
    // D3D10 Load: out of range reads zero (texel, level or face).
    if (level < 0 || level >= t.levels() || face < 0 || face >= t.faces()) return glm::vec4(0.0f);
    const std::array<int, 4>& size = t.levelSize(level);
    const int h = t.dims() == 1 ? 1 : size[1];
    if (texel.x < 0 || texel.x >= size[0] || texel.y < 0 || texel.y >= h) return glm::vec4(0.0f);
    const int y = t.dims() == 1 ? 0 : texel.y;
    if (t.isFloat()) return t.texelFloat(level, face, texel.x, y, 0, 0);
    const Rgba8 v = t.texel8(level, face, texel.x, y, 0, 0);
    return glm::vec4(v.r, v.g, v.b, v.a) / 255.0f;
}

glm::vec4 VertexContext::sampleLevel(int u, const glm::vec4& c, float lod) {
    const detail::BoundUnit& b = unit(u);
    const int32_t lambda = tex::programLambdaLod(b.sampler, lod);
    uint32_t n = 0;
    const glm::vec4 r = tex::programFetch(*b.texture, b.sampler, c, lambda, setup_->path, n);
    fetches_ += n;
    return r;
}

// ---- quad context -------------------------------------------------------------------------

bool detail::programAvx2() {
    return avx2Enabled();
}

void QuadContext::undeclaredTarget(int target) const { undeclared("quad program", false, target); }
void QuadContext::undeclaredUnit(int u) const { undeclared("quad program", true, u); }

Vec4x4 QuadContext::sample(int u, int k, Mask4 m) {
    const detail::BoundUnit& b = unit(u);
    const uint32_t lanes = active_ & ~discarded_ & m.bits();
    const auto& q = quad_->v[size_t(k)];
    const int32_t lambda = tex::programLambdaQuad(*b.texture, b.sampler, q);  // one per quad
    std::array<glm::vec4, 4> t{};
    if (setup_->path == Path::Fast && detail::programAvx2() && tex::quadFetch8Applies(*b.texture, b.sampler)) {
        // An 8-bit 2D texture, LINEAR (the impostors' board albedo, mipmapped): the quad's
        // four fetches side by side, the lanes' bits as below.
        tex::programFetchQuad8(*b.texture, b.sampler, q, lambda, lanes, t, fetches_);
        return Vec4x4::fromLanes(t);
    }
    for (int i = 0; i < 4; ++i)
        if ((lanes >> i) & 1u)
            t[size_t(i)] = tex::programFetch(*b.texture, b.sampler, q[size_t(i)], lambda, setup_->path,
                                             fetches_[size_t(i)]);
    return Vec4x4::fromLanes(t);
}

Float4 QuadContext::sampleCompare(int u, const Vec4x4& c, Float4 ref, Mask4 m) {
    const detail::BoundUnit& b = unit(u);
    const uint32_t lanes = active_ & ~discarded_ & m.bits();
    const int32_t lambda = tex::programLambdaLod(b.sampler, 0.0f);
    float r[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4; ++i)
        if ((lanes >> i) & 1u)
            r[i] = tex::programFetchCompare(*b.texture, b.sampler, c.lane(i), ref[i], lambda, setup_->path,
                                            fetches_[size_t(i)]);
    return Float4::lanes(r[0], r[1], r[2], r[3]);
}

// Lane by lane through the scalar fetch: filtered samplers, non-power-of-two WRAP, and the
// reference path.
Vec4x4 QuadContext::sampleLevelLanes(const detail::BoundUnit& b, const Vec4x4& c, Float4 lod, uint32_t lanes) {
    alignas(16) float cx[4], cy[4], cz[4], cw[4], l[4];
    _mm_store_ps(cx, c.x.v);
    _mm_store_ps(cy, c.y.v);
    _mm_store_ps(cz, c.z.v);
    _mm_store_ps(cw, c.w.v);
    _mm_store_ps(l, lod.v);
    std::array<glm::vec4, 4> t{};
    for (int i = 0; i < 4; ++i) {
        if (!((lanes >> i) & 1u)) continue;
        if (b.nearest.valid() && setup_->path == Path::Fast) {
            t[size_t(i)] = b.nearest.cube ? b.nearest.fetchCube(glm::vec3(cx[i], cy[i], cz[i]))
                                          : b.nearest.fetch(cx[i], cy[i]);
            ++fetches_[size_t(i)];
            continue;
        }
        const int32_t lambda = tex::programLambdaLod(b.sampler, l[i]);
        t[size_t(i)] = tex::programFetch(*b.texture, b.sampler, glm::vec4(cx[i], cy[i], cz[i], cw[i]), lambda,
                                         setup_->path, fetches_[size_t(i)]);
    }
    return Vec4x4::fromLanes(t);
}

// ---- point-sampled float textures ------------------------------------------------------

detail::NearestFloat2D detail::nearestFloat2D(const tex::Texture* texture, const tex::SamplerState& sampler) {
    NearestFloat2D n;
    using tex::AddressMode;
    auto simple = [](AddressMode m) { return m == AddressMode::Wrap || m == AddressMode::ClampToEdge; };
    if (texture && texture->isFloat() && texture->desc().target == tex::TextureTarget::CubeMap &&
        sampler.magFilter == tex::FilterMode::Nearest && sampler.minFilter == tex::FilterMode::Nearest &&
        sampler.mipFilter == tex::MipMode::None) {
        // Cube maps clamp to their face edges whatever the address mode (fetchOneLevel).
        const int base = std::clamp(sampler.baseLevel, 0, texture->levels() - 1);
        if (texture->singleChannel())
            n.data1 = texture->dataR(base, 0);
        else
            n.data4 = texture->dataF(base, 0);
        n.depth = texture->format().isDepth;
        n.width = texture->levelSize(base)[0];
        n.height = texture->levelSize(base)[1];
        n.cube = true;
        n.faceTexels = size_t(n.width) * size_t(n.height);
        if ((n.width & (n.width - 1)) == 0) n.widthShift = std::countr_zero(unsigned(n.width));
        return n;  // lanes4 stays false: the groups fetch cube maps through nearestCubeIndices
    }
    if (!(texture && texture->isFloat() && texture->dims() <= 2 &&
          texture->desc().target != tex::TextureTarget::CubeMap &&
          sampler.magFilter == tex::FilterMode::Nearest && sampler.minFilter == tex::FilterMode::Nearest &&
          sampler.mipFilter == tex::MipMode::None && simple(sampler.address[0]) &&
          (texture->dims() == 1 || simple(sampler.address[1]))))
        return n;
    const int base = std::clamp(sampler.baseLevel, 0, texture->levels() - 1);
    if (texture->singleChannel())
        n.data1 = texture->dataR(base, 0);
    else
        n.data4 = texture->dataF(base, 0);
    n.depth = texture->format().isDepth;
    n.width = texture->levelSize(base)[0];
    n.height = texture->levelSize(base)[1];
    n.wrapS = sampler.address[0] == AddressMode::Wrap;
    n.wrapT = sampler.address[1] == AddressMode::Wrap;
    auto pow2 = [](int v) { return (v & (v - 1)) == 0; };
    n.lanes4 = (!n.wrapS || pow2(n.width)) && (n.height == 1 || !n.wrapT || pow2(n.height));
    if (pow2(n.width)) n.widthShift = std::countr_zero(unsigned(n.width));
    auto axis = [](int size, bool wrap) {
        if (wrap) return NearestFloat2D::Axis{float(size), -4194304.0f, 4194304.0f, size - 1};
        return NearestFloat2D::Axis{float(size), 0.0f, float(size - 1), -1};
    };
    n.axisS = axis(n.width, n.wrapS);
    n.axisT = axis(n.height, n.wrapT);
    return n;
}

detail::LinearFloatCube detail::linearFloatCube(const tex::Texture* texture, const tex::SamplerState& sampler) {
    LinearFloatCube c;
    if (!(texture && texture->isFloat() && !texture->singleChannel() &&
          texture->desc().target == tex::TextureTarget::CubeMap && sampler.magFilter == tex::FilterMode::Linear &&
          sampler.minFilter == tex::FilterMode::Linear && sampler.mipFilter == tex::MipMode::None))
        return c;
    const int base = std::clamp(sampler.baseLevel, 0, texture->levels() - 1);
    c.data = texture->dataF(base, 0);
    c.size = texture->levelSize(base)[0];
    c.faceTexels = int32_t(texture->dataF(base, 1) - texture->dataF(base, 0));
    return c;
}

detail::LinearFloat2D detail::linearFloat2D(const tex::Texture* texture, const tex::SamplerState& sampler) {
    LinearFloat2D c;
    if (!(texture && texture->isFloat() && !texture->singleChannel() && texture->dims() == 2 &&
          texture->desc().target != tex::TextureTarget::CubeMap && sampler.magFilter == tex::FilterMode::Linear &&
          sampler.minFilter == tex::FilterMode::Linear && sampler.mipFilter == tex::MipMode::None &&
          sampler.address[0] == tex::AddressMode::ClampToEdge && sampler.address[1] == tex::AddressMode::ClampToEdge))
        return c;
    const int base = std::clamp(sampler.baseLevel, 0, texture->levels() - 1);
    c.data = texture->dataF(base, 0);
    c.width = texture->levelSize(base)[0];
    c.height = texture->levelSize(base)[1];
    return c;
}

// ---- output merger ------------------------------------------------------------------------

namespace detail {

float storedDepth(bool depthD24, double z) {
    if (depthD24) {
        const uint32_t q = quantizeDepth(z, (1u << 24) - 1u);
        return float(double(q) / double((1u << 24) - 1u));
    }
    if (!(z > 0.0)) return 0.0f;  // NaN → 0, as the fixed-function quantizer
    return z >= 1.0 ? 1.0f : float(z);
}

namespace {

// IEEE binary16, round to nearest even (Imath's conversion); overflow → ±infinity; every
// NaN → the canonical quiet NaN 0x7E00, so the bytes do not depend on whether the
// compiler used the F16C instruction or Imath's portable code (their NaN payloads differ).
float roundToHalf(float v) {
    if (v != v) return tex::halfToFloat(0x7E00);
    return tex::halfToFloat(imath_float_to_half(v));
}

// What a target stores for a colour: R formats keep red (and read back as (r, 0, 0, 1)).
glm::vec4 toStored(tex::TexelFormat f, const glm::vec4& v) {
    switch (f) {
        case tex::TexelFormat::R16F: return {roundToHalf(v.x), 0.0f, 0.0f, 1.0f};
        case tex::TexelFormat::RGBA16F:
            return {roundToHalf(v.x), roundToHalf(v.y), roundToHalf(v.z), roundToHalf(v.w)};
        case tex::TexelFormat::R32F: return {v.x, 0.0f, 0.0f, 1.0f};
        default: return v;
    }
}

float factorValue(BlendFactor f, int c, const glm::vec4& s, const glm::vec4& d) {
    switch (f) {
        case BlendFactor::Zero: return 0.0f;
        case BlendFactor::One: return 1.0f;
        case BlendFactor::SrcColor: return s[c];
        case BlendFactor::InvSrcColor: return 1.0f - s[c];
        case BlendFactor::SrcAlpha: return s.w;
        case BlendFactor::InvSrcAlpha: return 1.0f - s.w;
        case BlendFactor::DestAlpha: return d.w;
        case BlendFactor::InvDestAlpha: return 1.0f - d.w;
        case BlendFactor::DestColor: return d[c];
        case BlendFactor::InvDestColor: return 1.0f - d[c];
        case BlendFactor::SrcAlphaSat: return c == 3 ? 1.0f : std::min(s.w, 1.0f - d.w);
        case BlendFactor::BothSrcAlpha: return s.w;
        case BlendFactor::BothInvSrcAlpha: return 1.0f - s.w;
    }
    return 0.0f;
}

// Float blending (Direct3D 10 on float targets: unclamped, single precision here; the
// products and the sum rounded separately — no fused multiply-add).
glm::vec4 blendFloat(const TargetBlend& b, const glm::vec4& s, const glm::vec4& d) {
    const BlendFactor df = effectiveDestFactor(b.src, b.dst);
    glm::vec4 r(0.0f);
    for (int c = 0; c < 4; ++c) {
        const float sf = s[c] * factorValue(b.src, c, s, d);
        const float dfv = d[c] * factorValue(df, c, s, d);
        switch (b.op) {
            case BlendOp::Add: r[c] = sf + dfv; break;
            case BlendOp::Subtract: r[c] = sf - dfv; break;
            case BlendOp::RevSubtract: r[c] = dfv - sf; break;
            case BlendOp::Min: r[c] = std::min(s[c], d[c]); break;
            case BlendOp::Max: r[c] = std::max(s[c], d[c]); break;
        }
    }
    return r;
}

}  // namespace

void mergeFragment(const ProgramDraw& d, int x, int y,
                   const std::array<glm::vec4, kMaxColorTargets>& out, uint32_t written) {
    for (int k = 0; k < d.numTargets; ++k) {
        if (!((written >> k) & 1u)) continue;  // not written by this fragment: unchanged
        const TargetView& t = d.targets[size_t(k)];
        const size_t i = size_t(y) * size_t(t.width) + size_t(x);
        if (t.data8) {
            const Rgba8 dst = t.data8[i];
            Rgba8 src = tex::floatToRgba8(out[size_t(k)]);
            if (t.blend.enable) src = blendPixel(t.blend.src, t.blend.dst, t.blend.op, src, dst);
            t.data8[i] = applyWriteMask(t.blend.writeMask, src, dst);
        } else {
            const glm::vec4 dst = t.data1 ? glm::vec4(t.data1[i], 0.0f, 0.0f, 1.0f) : t.dataF[i];
            glm::vec4 src = out[size_t(k)];
            if (t.blend.enable) src = blendFloat(t.blend, src, dst);
            const uint8_t m = t.blend.writeMask;
            const glm::vec4 merged((m & kWriteR) ? src.x : dst.x, (m & kWriteG) ? src.y : dst.y,
                                   (m & kWriteB) ? src.z : dst.z, (m & kWriteA) ? src.w : dst.w);
            if (t.data1)
                t.data1[i] = toStored(t.format, merged).x;
            else
                t.dataF[i] = toStored(t.format, merged);
        }
    }
}

void mergeQuad(const ProgramDraw& d, int qx, int qy, const QuadContext& f, uint32_t alive) {
    for (int k = 0; k < d.numTargets; ++k) {
        const uint32_t lanes = f.writtenLanes(k) & alive;
        if (!lanes) continue;
        const TargetView& t = d.targets[size_t(k)];
        if (t.data8 && !t.blend.enable && t.blend.writeMask == kWriteRGBA) {
            // tex::floatToRgba8 on four lanes: max(x, 0) also maps NaN to 0 (MAXPS returns
            // its second operand), then min(x, 1), x·255 + ½ and truncation (= floor here).
            const Vec4x4& o = f.outQuad(k);
            auto unorm = [](__m128 x) {
                x = _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), _mm_set1_ps(1.0f));
                return _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(x, _mm_set1_ps(255.0f)), _mm_set1_ps(0.5f)));
            };
            const __m128i px = _mm_or_si128(
                _mm_or_si128(unorm(o.x.v), _mm_slli_epi32(unorm(o.y.v), 8)),
                _mm_or_si128(_mm_slli_epi32(unorm(o.z.v), 16), _mm_slli_epi32(unorm(o.w.v), 24)));
            alignas(16) uint32_t v[4];
            _mm_store_si128(reinterpret_cast<__m128i*>(v), px);
            for (int p = 0; p < 4; ++p) {
                if (!((lanes >> p) & 1u)) continue;
                const size_t i = size_t(qy + (p >> 1)) * size_t(t.width) + size_t(qx + (p & 1));
                std::memcpy(static_cast<void*>(&t.data8[i]), &v[p], 4);  // Rgba8 is r, g, b, a in memory
            }
            continue;
        }
        for (int p = 0; p < 4; ++p)
            if ((lanes >> p) & 1u) mergeFragment(d, qx + (p & 1), qy + (p >> 1), f.out(p), 1u << k);
    }
}

// One draw between its checks and its pixels: the state it was issued with, its programs,
// and what the vertex stage and setup made of it. A draw run at once uses the device's
// bindings; a batched one keeps its own copy (`units`), since later draws may rebind.
struct DrawJob {
    ProgramDraw d;
    std::array<BoundUnit, kMaxProgramUnits> units{};
    ProgramState state;
    Viewport viewport;
    bool scissorOn = false;
    Rect scissor;
    ProgramPrimitive primitive = ProgramPrimitive::TriangleList;
    std::span<const uint32_t> indices;
    size_t vertexCount = 0;
    uint32_t vertexUnits = 0;
    VertexStageFn runVertices = nullptr;
    const void* stage = nullptr;
    TrianglesKernelFn fast = nullptr;
    TriangleKernelFn reference = nullptr;
    void* kernel = nullptr;
    std::unique_ptr<HeldPrograms> held;
    // The setup's output.
    std::vector<ProgramVertex> vertices;
    std::vector<ProcessedVertex> processed;
    TriangleChunk chunk;
    std::vector<ProgramTriangle> tris;
    ProgramCounters counters;  // the draw, its vertices and its triangles
};

}  // namespace detail

// ---- the device ---------------------------------------------------------------------------

struct ProgrammableDevice::Impl {
    const Profile& profile;
    DeviceOptions options;
    std::unique_ptr<tbb::task_arena> arena;
    std::vector<ColorTarget> colors;
    DepthTarget depth;
    int width = 0, height = 0;
    ProgramState state;
    Viewport viewport;
    bool scissorOn = false;
    Rect scissor;
    std::array<std::shared_ptr<const tex::Texture>, kMaxProgramUnits> textures{};
    std::array<detail::BoundUnit, kMaxProgramUnits> units{};
    ProgramCounters counters;
    detail::DrawJob immediate;                           // a draw outside a batch
    std::vector<std::unique_ptr<detail::DrawJob>> pool;  // a batch's draws: the first batchSize
    size_t batchSize = 0;
    detail::DrawJob* issuing = nullptr;                  // beginDraw's draw, for submitDraw
    std::vector<ProgramCounters> tileCounters;
    std::vector<int> busyTiles;  // rasterize: the tiles holding triangles (several threads)

    Impl(const Profile& p, DeviceOptions o) : profile(p), options(o) { makeArena(); }
    void makeArena() {
        int n = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
        arena = std::make_unique<tbb::task_arena>(std::max(1, n));
    }
    // Clears write `value` to every texel of viewport ∩ scissor of a level's data.
    template <class T>
    void fillClearRect(T* data, const T& value) const {
        int64_t x0 = viewport.x, y0 = viewport.y;
        int64_t x1 = int64_t(viewport.x) + viewport.width, y1 = int64_t(viewport.y) + viewport.height;
        if (scissorOn) {
            x0 = std::max<int64_t>(x0, scissor.x);
            y0 = std::max<int64_t>(y0, scissor.y);
            x1 = std::min<int64_t>(x1, int64_t(scissor.x) + scissor.width);
            y1 = std::min<int64_t>(y1, int64_t(scissor.y) + scissor.height);
        }
        x0 = std::clamp<int64_t>(x0, 0, width);
        x1 = std::clamp<int64_t>(x1, 0, width);
        y0 = std::clamp<int64_t>(y0, 0, height);
        y1 = std::clamp<int64_t>(y1, 0, height);
        // A scissor of negative extent leaves x1 < x0: nothing to clear (std::fill of a
        // reversed range would run off the level; the trace fuzz tests found it).
        if (x1 <= x0) return;
        for (int64_t y = y0; y < y1; ++y)
            std::fill(data + y * width + x0, data + y * width + x1, value);
    }
    void requireTargets() const {
        if (width == 0) throw InvalidState("no render target attached (setRenderTargets)");
    }
    void setup(detail::DrawJob& job);
    void rasterize(std::span<detail::DrawJob* const> jobs);
    // Runs body(i) for i in [0, n) on the arena's threads, grain `grain`.
    template <class Body>
    void parallel(size_t n, size_t grain, const Body& body) {
        [[maybe_unused]] int forkJoin = 0;  // the address TSan's fork/join edges name
        RG_TSAN_RELEASE(&forkJoin);
        arena->execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain), [&](const tbb::blocked_range<size_t>& r) {
                RG_TSAN_ACQUIRE(&forkJoin);
                for (size_t i = r.begin(); i < r.end(); ++i) body(i);
                RG_TSAN_RELEASE(&forkJoin);
            });
        });
        RG_TSAN_ACQUIRE(&forkJoin);
    }
};

ProgrammableDevice::ProgrammableDevice(const Profile& profile, DeviceOptions options) {
    profile.require(Feature::VertexProgram, "programmable device");
    profile.require(Feature::FragmentProgram, "programmable device");
    impl_ = std::make_unique<Impl>(profile, options);
}
ProgrammableDevice::~ProgrammableDevice() {
    // A batch left open is run, so that no issued draw is lost (and a recorder's final
    // hashes are of the pixels its trace's draws make); a destructor must not throw.
    if (batching_) {
        try {
            endBatch();
        } catch (const std::exception&) {
        }
    }
    // The recorder's trace gets the final target hashes while the targets still exist; a
    // destructor must not throw, and a recorder that cannot write them any more (already
    // finished) has nothing to add.
    if (recorder_) {
        try {
            recorder_->detach(*this);
        } catch (const Error&) {
        }
    }
}

const Profile& ProgrammableDevice::profile() const { return impl_->profile; }
void ProgrammableDevice::setPath(Path path) {
    requireNoBatch("setPath");
    impl_->options.path = path;
}
void ProgrammableDevice::setThreads(int threads) {
    requireNoBatch("setThreads");
    impl_->options.threads = threads;
    impl_->makeArena();
}

void ProgrammableDevice::setRenderTargets(std::span<const ColorTarget> colors, const DepthTarget& depth) {
    Impl& m = *impl_;
    requireNoBatch("setRenderTargets");
    if (colors.size() > size_t(kMaxColorTargets))
        throw InvalidState(std::to_string(colors.size()) + " colour targets; at most " +
                           std::to_string(kMaxColorTargets));
    if (colors.size() > 1) m.profile.require(Feature::MultipleRenderTargets);
    int w = 0, h = 0;
    auto check = [&](const std::shared_ptr<tex::Texture>& t, int level, int face, const char* what,
                     bool wantDepth) {
        if (!t) throw InvalidState(std::string(what) + " has no texture");
        if (!t->isRenderTarget())
            throw InvalidState(std::string(what) + " is a " + std::string(t->format().name) +
                               " texture not created as a render target (createRenderTarget)");
        if (t->format().isDepth != wantDepth)
            throw InvalidState(std::string(what) + " has format " + std::string(t->format().name));
        if (level < 0 || level >= t->levels() || face < 0 || face >= t->faces())
            throw InvalidState(std::string(what) + " level " + std::to_string(level) + " face " +
                               std::to_string(face) + " does not exist");
        const auto& s = t->levelSize(level);
        if (w == 0) {
            w = s[0];
            h = s[1];
        } else if (s[0] != w || s[1] != h) {
            throw InvalidState(std::string(what) + " is " + std::to_string(s[0]) + "x" +
                               std::to_string(s[1]) + " but the other targets are " +
                               std::to_string(w) + "x" + std::to_string(h));
        }
    };
    for (size_t i = 0; i < colors.size(); ++i) {
        const std::string what = "render target " + std::to_string(i);
        check(colors[i].texture, colors[i].level, colors[i].face, what.c_str(), false);
    }
    if (depth.texture) check(depth.texture, depth.level, depth.face, "depth target", true);
    m.colors.assign(colors.begin(), colors.end());
    m.depth = depth;
    m.width = w;
    m.height = h;
    m.viewport = Viewport{0, 0, w, h, 0.0f, 1.0f};
    m.scissorOn = false;
}

int ProgrammableDevice::targetWidth() const { return impl_->width; }
int ProgrammableDevice::targetHeight() const { return impl_->height; }
void ProgrammableDevice::setState(const ProgramState& state) {
    if (!(state.pointSize > 0.0f) || !(state.pointSize <= 8192.0f))
        throw InvalidState("point size " + std::to_string(state.pointSize) + " outside (0, 8192]");
    // Booleans are 0 or 1, as the trace format writes them (docs/trace-format.md).
    if (state.depthTest > 1 || state.depthWrite > 1)
        throw InvalidState("depthTest/depthWrite other than 0 or 1");
    for (size_t k = 0; k < state.blend.size(); ++k)
        if (state.blend[k].enable > 1)
            throw InvalidState("render target " + std::to_string(k) + ": blend enable other than 0 or 1");
    // BOTHSRCALPHA and BOTHINVSRCALPHA are source factors that set the destination's too
    // (docs/hardware.md, "Blending"); as a destination factor they mean nothing.
    for (size_t k = 0; k < state.blend.size(); ++k)
        if (state.blend[k].dst == BlendFactor::BothSrcAlpha || state.blend[k].dst == BlendFactor::BothInvSrcAlpha)
            throw InvalidState("render target " + std::to_string(k) + ": BOTHSRCALPHA / BOTHINVSRCALPHA as the "
                               "destination blend factor (they are source factors that set the destination's)");
    impl_->state = state;
}
const ProgramState& ProgrammableDevice::state() const { return impl_->state; }

void ProgrammableDevice::setViewport(const Viewport& vp) {
    Impl& m = *impl_;
    m.requireTargets();
    if (vp.width <= 0 || vp.height <= 0 || vp.x < 0 || vp.y < 0 ||
        int64_t(vp.x) + vp.width > m.width || int64_t(vp.y) + vp.height > m.height)
        throw InvalidState("viewport " + std::to_string(vp.width) + "x" + std::to_string(vp.height) +
                           " at (" + std::to_string(vp.x) + ", " + std::to_string(vp.y) +
                           ") is empty or outside the " + std::to_string(m.width) + "x" +
                           std::to_string(m.height) + " target");
    m.viewport = vp;
}

void ProgrammableDevice::setScissor(const Rect* rect) {
    impl_->scissorOn = rect != nullptr;
    if (rect) impl_->scissor = *rect;
}

void ProgrammableDevice::setTexture(int unit, std::shared_ptr<const tex::Texture> texture,
                                    const tex::SamplerState& sampler) {
    if (unit < 0 || unit >= kMaxProgramUnits || unit >= impl_->profile.maxTextureStages)
        throw InvalidState("texture unit " + std::to_string(unit) + " outside the " +
                           std::to_string(std::min(kMaxProgramUnits, impl_->profile.maxTextureStages)) +
                           " units of profile '" + std::string(impl_->profile.name) + "'");
    if (texture && !texture->complete())
        throw InvalidState("texture bound to unit " + std::to_string(unit) + " has levels never uploaded");
    const detail::BoundUnit b{texture.get(), sampler, detail::nearestFloat2D(texture.get(), sampler),
                              detail::linearFloatCube(texture.get(), sampler),
                              detail::linearFloat2D(texture.get(), sampler)};
    impl_->units[size_t(unit)] = b;
    impl_->textures[size_t(unit)] = std::move(texture);
}

std::span<const ColorTarget> ProgrammableDevice::colorTargets() const { return impl_->colors; }
const DepthTarget& ProgrammableDevice::depthTarget() const { return impl_->depth; }
const Viewport& ProgrammableDevice::viewport() const { return impl_->viewport; }
const Rect* ProgrammableDevice::scissor() const { return impl_->scissorOn ? &impl_->scissor : nullptr; }

const std::shared_ptr<const tex::Texture>& ProgrammableDevice::texture(int unit) const {
    if (unit < 0 || unit >= kMaxProgramUnits) throw InvalidState("texture unit " + std::to_string(unit) + " out of range");
    return impl_->textures[size_t(unit)];
}

const tex::SamplerState& ProgrammableDevice::sampler(int unit) const {
    if (unit < 0 || unit >= kMaxProgramUnits) throw InvalidState("texture unit " + std::to_string(unit) + " out of range");
    return impl_->units[size_t(unit)].sampler;
}

void ProgrammableDevice::setRecorder(std::shared_ptr<TraceRecorder> recorder) {
    if (recorder == recorder_) return;
    requireNoBatch("setRecorder");
    if (recorder) recorder->attach(*this);  // first, so that a refused recorder changes nothing
    if (recorder_) recorder_->detach(*this);
    recorder_ = std::move(recorder);
}

void ProgrammableDevice::recordDraw(std::type_index program, std::span<const uint8_t> vertexProgram,
                                    std::span<const uint8_t> fragmentProgram, uint32_t units,
                                    ProgramPrimitive primitive, std::span<const uint8_t> vertices,
                                    uint32_t stride, std::span<const uint32_t> indices) {
    recorder_->programDraw(*this, program, vertexProgram, fragmentProgram, units, primitive, vertices, stride,
                           indices);
}

void ProgrammableDevice::beginFrame() {
    requireNoBatch("beginFrame");
    impl_->counters = ProgramCounters{};
    if (recorder_) recorder_->beginFrame();
}
const ProgramCounters& ProgrammableDevice::counters() const { return impl_->counters; }


void ProgrammableDevice::clearColor(int target, const glm::vec4& value) {
    Impl& m = *impl_;
    requireNoBatch("clearColor");
    if (target < 0 || size_t(target) >= m.colors.size())
        throw InvalidState("clear of render target " + std::to_string(target) + ", which is not attached");
    if (recorder_) recorder_->clearColor(*this, target, value);
    const ColorTarget& ct = m.colors[size_t(target)];
    tex::Texture& t = *ct.texture;
    if (!t.isFloat())
        m.fillClearRect(t.renderData8(ct.level, ct.face), tex::floatToRgba8(value));
    else if (t.singleChannel())
        m.fillClearRect(t.renderDataR(ct.level, ct.face), detail::toStored(t.desc().format, value).x);
    else
        m.fillClearRect(t.renderDataF(ct.level, ct.face), detail::toStored(t.desc().format, value));
}

void ProgrammableDevice::clearDepth(float value) {
    Impl& m = *impl_;
    requireNoBatch("clearDepth");
    if (!m.depth.texture) throw InvalidState("depth clear without a depth target");
    if (recorder_) recorder_->clearDepth(*this, value);
    const bool d24 = m.depth.texture->desc().format == tex::TexelFormat::Depth24;
    m.fillClearRect(m.depth.texture->renderDataR(m.depth.level, m.depth.face),
                    detail::storedDepth(d24, double(value)));
}

detail::ProgramDraw& ProgrammableDevice::beginDraw(int varyings, uint32_t targets, uint32_t units,
                                                   ProgramPrimitive primitive, size_t vertexCount,
                                                   std::span<const uint32_t> indices,
                                                   uint32_t vertexUnits) {
    Impl& m = *impl_;
    // Vertex texture fetch: the units the vertex program declares are checked as the
    // fragment program's are (bound, not a target of this draw), and within the G80's 16.
    for (int u = 0; u < 32; ++u) {
        if (!((vertexUnits >> u) & 1u)) continue;
        if (u >= kMaxVertexUnits || !m.units[size_t(u)].texture)
            throw InvalidState("vertex program reads texture unit " + std::to_string(u) +
                               (u >= kMaxVertexUnits ? ", past the profile's " + std::to_string(kMaxVertexUnits) +
                                                           " vertex texture units"
                                                     : std::string(", which has no texture bound")));
        const tex::Texture* t = m.units[size_t(u)].texture;
        for (size_t k = 0; k < m.colors.size(); ++k)
            if (m.colors[k].texture.get() == t)
                throw InvalidState("vertex texture unit " + std::to_string(u) + " samples render target " +
                                   std::to_string(k) + " while the draw writes it");
        if (m.depth.texture.get() == t && (m.state.depthWrite || m.state.depthTest))
            throw InvalidState("vertex texture unit " + std::to_string(u) +
                               " samples the depth target while the draw uses it");
    }
    m.requireTargets();
    const uint32_t attached = (1u << m.colors.size()) - 1u;
    for (int k = 0; k < 32; ++k)
        if (((targets >> k) & 1u) && !((attached >> k) & 1u))
            throw InvalidState("fragment program writes render target " + std::to_string(k) +
                               ", which is not attached (" + std::to_string(m.colors.size()) +
                               " attached)");
    for (int u = 0; u < 32; ++u) {
        if (!((units >> u) & 1u)) continue;
        if (u >= kMaxProgramUnits || !m.units[size_t(u)].texture)
            throw InvalidState("fragment program reads texture unit " + std::to_string(u) +
                               ", which has no texture bound");
        const tex::Texture* t = m.units[size_t(u)].texture;
        for (size_t k = 0; k < m.colors.size(); ++k)
            if (m.colors[k].texture.get() == t)
                throw InvalidState("texture unit " + std::to_string(u) + " samples render target " +
                                   std::to_string(k) + " while the draw writes it");
        if (m.depth.texture.get() == t && (m.state.depthWrite || m.state.depthTest))
            throw InvalidState("texture unit " + std::to_string(u) +
                               " samples the depth target while the draw uses it");
    }
    if (primitive == ProgramPrimitive::PointList && varyings >= kMaxVaryings)
        throw InvalidState("point primitives carry at most " + std::to_string(kMaxVaryings - 1) +
                           " varyings (the point coordinate takes the last slot)");
    for (uint32_t i : indices)
        if (i >= vertexCount)
            throw InvalidState("index " + std::to_string(i) + " past the " + std::to_string(vertexCount) +
                               " vertices of the draw");

    detail::DrawJob* job = &m.immediate;
    if (batching_) {
        if (m.batchSize == m.pool.size()) m.pool.push_back(std::make_unique<detail::DrawJob>());
        job = m.pool[m.batchSize].get();
        job->units = m.units;  // later draws of the batch may rebind
    }
    m.issuing = job;
    job->state = m.state;
    job->viewport = m.viewport;
    job->scissorOn = m.scissorOn;
    job->scissor = m.scissor;
    job->primitive = primitive;
    job->indices = indices;
    job->vertexCount = vertexCount;
    job->vertexUnits = vertexUnits;
    detail::ProgramDraw& d = job->d;
    d = detail::ProgramDraw{};
    d.subpixelBits = m.profile.subpixelBits;
    d.varyings = varyings;
    d.points = primitive == ProgramPrimitive::PointList;
    d.numTargets = int(m.colors.size());
    for (size_t k = 0; k < m.colors.size(); ++k) {
        const ColorTarget& ct = m.colors[k];
        detail::TargetView& v = d.targets[k];
        v.format = ct.texture->desc().format;
        v.width = m.width;
        v.blend = m.state.blend[k];
        if (ct.texture->singleChannel())
            v.data1 = ct.texture->renderDataR(ct.level, ct.face);
        else if (ct.texture->isFloat())
            v.dataF = ct.texture->renderDataF(ct.level, ct.face);
        else
            v.data8 = ct.texture->renderData8(ct.level, ct.face);
    }
    if (m.depth.texture && (m.state.depthTest || m.state.depthWrite)) {
        d.depthData = m.depth.texture->renderDataR(m.depth.level, m.depth.face);
        d.depthWidth = m.width;
        d.depthD24 = m.depth.texture->desc().format == tex::TexelFormat::Depth24;
        d.depthTest = m.state.depthTest != 0;
        d.depthWrite = m.state.depthWrite != 0;
        d.depthFunc = m.state.depthFunc;
    }
    d.ctx.units = batching_ ? &job->units : &m.units;
    d.ctx.declaredUnits = units;
    d.ctx.declaredTargets = targets;
    d.ctx.path = m.options.path;
    return d;
}

void ProgrammableDevice::requireNoBatch(const char* what) const {
    if (batching_) throw InvalidState(std::string(what) + " inside a draw batch (endBatch first)");
}

void ProgrammableDevice::beginBatch() {
    requireNoBatch("beginBatch");
    impl_->batchSize = 0;
    batching_ = true;
}

void ProgrammableDevice::endBatch() {
    Impl& m = *impl_;
    if (!batching_) throw InvalidState("endBatch without beginBatch");
    batching_ = false;
    std::vector<detail::DrawJob*> jobs;
    for (size_t i = 0; i < m.batchSize; ++i) jobs.push_back(m.pool[i].get());
    m.batchSize = 0;
    // The programs' copies go with the batch, run or not (a vertex program may throw).
    struct Release {
        std::span<detail::DrawJob* const> jobs;
        ~Release() {
            for (detail::DrawJob* j : jobs) j->held.reset();
        }
    } release{jobs};
    if (jobs.empty()) return;
    // Each draw's vertices and setup are its own, so the draws may be set up on any thread
    // in any order; rasterize meets them in issue order.
    if (m.options.path == Path::Reference || m.arena->max_concurrency() <= 1 || jobs.size() == 1)
        for (detail::DrawJob* j : jobs) m.setup(*j);
    else
        m.parallel(jobs.size(), 1, [&](size_t i) { m.setup(*jobs[i]); });
    m.rasterize(jobs);
}

void ProgrammableDevice::submitDraw(const DrawPrograms& programs, const void* stage, void* kernel,
                                    std::unique_ptr<detail::HeldPrograms> held) {
    Impl& m = *impl_;
    detail::DrawJob& job = *m.issuing;
    job.runVertices = programs.vertices;
    job.fast = programs.fast;
    job.reference = programs.reference;
    job.stage = stage;
    job.kernel = kernel;
    job.held = std::move(held);
    if (batching_) {
        ++m.batchSize;
        return;
    }
    detail::DrawJob* one = &job;
    m.setup(job);
    m.rasterize({&one, 1});
}

// The vertex stage, primitive assembly, clip and setup of one draw, and its binning into
// the tiles; its counters in job.counters.
void ProgrammableDevice::Impl::setup(detail::DrawJob& job) {
    using namespace detail;
    ProgramDraw& d = job.d;
    ProgramCounters& c = job.counters;
    c = ProgramCounters{};
    c.drawCalls = 1;

    // ---- vertex stage -----------------------------------------------------------------------
    // Each vertex is independent, so any split gives the same bytes. Vertex texture fetch:
    // each range counts its texels, the counts are summed (integers: the total does not
    // depend on the split).
    const size_t nv = job.vertexCount;
    job.vertices.resize(nv);
    c.vertexInvocations = nv;
    VertexContext::Setup vs;
    vs.units = d.ctx.units;
    vs.declaredUnits = job.vertexUnits;
    vs.path = options.path;
    auto range = [&](size_t b, size_t e) {
        VertexContext t(vs);
        job.runVertices(job.stage, b, e, job.vertices.data(), &t);
        std::atomic_ref<uint64_t>(c.vertexTextureFetches).fetch_add(t.fetches(), std::memory_order_relaxed);
    };
    constexpr size_t kVertexGrain = 2048;
    if (options.path == Path::Reference || nv < 2 * kVertexGrain || arena->max_concurrency() <= 1)
        range(0, nv);
    else
        parallel((nv + kVertexGrain - 1) / kVertexGrain, 1,
                 [&](size_t k) { range(k * kVertexGrain, std::min(nv, (k + 1) * kVertexGrain)); });

    const bool points = job.primitive == ProgramPrimitive::PointList;
    const int varyingFloats = 4 * d.varyings + (points ? 2 : 0);
    const Rect* scissor = job.scissorOn ? &job.scissor : nullptr;
    const CullMode cull = points ? CullMode::None : job.state.cull;
    const DrawContext dc = makeProgramDrawContext(width, height, job.viewport, scissor, cull, d.subpixelBits,
                                                  varyingFloats, d.depthData != nullptr, options.path);
    const ProgramPrimitive primitive = job.primitive;

    // ---- primitive assembly, clip and setup (the fixed-function code) ---------------------
    auto toProcessed = [&](const ProgramVertex& pv, ProcessedVertex& out) {
        out.clip = pv.clip;
        for (int a = 0; a < 4 * d.varyings; ++a)
            out.attr[size_t(kColorAttrs + a)] = pv.varyings[size_t(a >> 2)][a & 3];
        projectProgramVertex(dc, out);
    };
    const size_t n = job.indices.empty() ? job.vertices.size() : job.indices.size();
    auto vertexAt = [&](size_t i) -> const ProgramVertex& {
        return job.vertices[job.indices.empty() ? i : size_t(job.indices[i])];
    };
    TriangleChunk& chunk = job.chunk;
    chunk.tris.clear();
    chunk.texPlanes.clear();
    GeometryCounters gc;
    const Rgba8 none{};
    if (points) {
        // A point is the square of edge pointSize centred on its position: two triangles
        // sharing the diagonal, so the top-left rule gives each covered pixel to one.
        const float hx = job.state.pointSize / float(job.viewport.width);
        const float hy = job.state.pointSize / float(job.viewport.height);
        static constexpr float kCorner[4][4] = {  // NDC offset signs, then point coordinate
            {-1, 1, 0, 0}, {1, 1, 1, 0}, {-1, -1, 0, 1}, {1, -1, 1, 1}};
        job.processed.resize(4);
        for (size_t i = 0; i < n; ++i) {
            const ProgramVertex& pv = vertexAt(i);
            for (int c = 0; c < 4; ++c) {
                ProgramVertex corner = pv;
                corner.clip.x = pv.clip.x + kCorner[c][0] * hx * pv.clip.w;
                corner.clip.y = pv.clip.y + kCorner[c][1] * hy * pv.clip.w;
                ProcessedVertex& pr = job.processed[size_t(c)];
                toProcessed(corner, pr);
                pr.attr[size_t(kColorAttrs + 4 * d.varyings)] = kCorner[c][2];
                pr.attr[size_t(kColorAttrs + 4 * d.varyings + 1)] = kCorner[c][3];
            }
            GeometryCounters pc;
            clipAndSetup(dc, job.processed[0], job.processed[1], job.processed[2], none, none, chunk.tris,
                         chunk.texPlanes, pc);
            clipAndSetup(dc, job.processed[1], job.processed[3], job.processed[2], none, none, chunk.tris,
                         chunk.texPlanes, pc);
            gc.add(pc);
        }
        c.primitivesSubmitted += n;
    } else {
        // Each vertex projected once, however many indices name it (a closed mesh's vertex is
        // shared by about six triangles): a processed vertex is a function of its vertex
        // alone, so the triangles set up from it are the same bytes.
        job.processed.resize(nv);
        for (size_t i = 0; i < nv; ++i) toProcessed(job.vertices[i], job.processed[i]);
        auto processedAt = [&](uint32_t i) -> const ProcessedVertex& {
            return job.processed[job.indices.empty() ? size_t(i) : size_t(job.indices[i])];
        };
        const Primitive prim = primitive == ProgramPrimitive::TriangleList    ? Primitive::TriangleList
                               : primitive == ProgramPrimitive::TriangleStrip ? Primitive::TriangleStrip
                                                                              : Primitive::TriangleFan;
        const uint32_t count = triangleCount(prim, uint32_t(n));
        for (uint32_t i = 0; i < count; ++i) {
            const auto v = triangleVertices(prim, i);
            clipAndSetup(dc, processedAt(v[0]), processedAt(v[1]), processedAt(v[2]), none, none, chunk.tris,
                         chunk.texPlanes, gc);
        }
        c.primitivesSubmitted += count;
    }
    c.trianglesDrawn += gc.drawn;
    c.trianglesCulled += gc.culled;
    c.trianglesClipped += gc.clipped;
    c.primitivesInvalid += gc.invalid;

    job.tris.resize(chunk.tris.size());
    for (size_t i = 0; i < chunk.tris.size(); ++i) {
        const SetupTriangle& s = chunk.tris[i];
        ProgramTriangle& t = job.tris[i];
        t.A = s.A;
        t.B = s.B;
        t.C = s.C;
        t.minX = s.minX; t.minY = s.minY; t.maxX = s.maxX; t.maxY = s.maxY;
        t.x0 = s.x0; t.y0 = s.y0;
        t.zc = s.zc; t.zdx = s.zdx; t.zdy = s.zdy;
        t.iwC = s.invW.c; t.iwDx = s.invW.dx; t.iwDy = s.invW.dy;
        t.planes = chunk.texPlanes.empty() ? nullptr
                                           : reinterpret_cast<const float*>(chunk.texPlanes.data() + s.texPlanes);
    }

    if (options.path == Path::Fast) {
        const int tilesX = (width + kTileSize - 1) >> kTileShift;
        const int tilesY = (height + kTileSize - 1) >> kTileShift;
        binChunk(chunk, tilesX, tilesY);
    }
}

// The pixels of the draws `jobs`, set up, in issue order: on the reference path triangle
// by triangle; on the fast path tile by tile, each tile's triangles of every draw in draw
// and triangle order, the tiles on the threads.
void ProgrammableDevice::Impl::rasterize(std::span<detail::DrawJob* const> jobs) {
    using namespace detail;
    for (const DrawJob* j : jobs) counters.add(j->counters);
    if (options.path == Path::Reference) {
        ProgramCounters c;
        for (DrawJob* j : jobs)
            for (const ProgramTriangle& t : j->tris) j->reference(j->kernel, t, 0, 0, 0, 0, c);
        counters.add(c);
        return;
    }
    const int tilesX = (width + kTileSize - 1) >> kTileShift;
    const int tilesY = (height + kTileSize - 1) >> kTileShift;
    const int tiles = tilesX * tilesY;
    auto shade = [&](int tile, int x0, int y0, int x1, int y1, ProgramCounters& c) {
        for (DrawJob* j : jobs) {
            const TriangleChunk& chunk = j->chunk;
            const uint32_t b = chunk.binStart[size_t(tile)], e = chunk.binStart[size_t(tile) + 1];
            if (e > b) j->fast(j->kernel, j->tris.data(), chunk.binItems.data() + b, e - b, x0, y0, x1, y1, c);
        }
    };
    if (arena->max_concurrency() <= 1) {
        ProgramCounters c;
        for (int tile = 0; tile < tiles; ++tile) {
            const int x0 = (tile % tilesX) << kTileShift, y0 = (tile / tilesX) << kTileShift;
            const int x1 = std::min(width, x0 + kTileSize) - 1, y1 = std::min(height, y0 + kTileSize) - 1;
            shade(tile, x0, y0, x1, y1, c);
        }
        counters.add(c);
        return;
    }
    // The tiles holding triangles, each one task; where there are fewer than four per
    // thread (a small mesh: one chess piece covers one to four tiles), each is run as its
    // sixteen 16² parts, so that the draw still spreads over the threads (the impostor
    // pieces' glass on two threads: 1.34× at best with whole tiles, 1.69× with 32²
    // quarters, 1.93× with 16² parts, from each draw's pixels). Any split into
    // rectangles of even origin gives the same bytes: no quad straddles one, a pixel's
    // fragments are merged in primitive order within its rectangle, and the counters
    // add up (ProgrammablePathsAgree compares every thread count with the reference).
    std::vector<int>& busy = busyTiles;
    busy.clear();
    for (int tile = 0; tile < tiles; ++tile)
        for (const DrawJob* j : jobs)
            if (j->chunk.binStart[size_t(tile) + 1] > j->chunk.binStart[size_t(tile)]) {
                busy.push_back(tile);
                break;
            }
    const int split = int(busy.size()) < 4 * arena->max_concurrency() ? 4 : 1;  // per axis
    const int parts = split * split;
    const size_t tasks = busy.size() * size_t(parts);
    tileCounters.assign(tasks, ProgramCounters{});
    parallel(tasks, 1, [&](size_t task) {
        const int tile = busy[task / size_t(parts)], part = int(task % size_t(parts));
        int x0 = (tile % tilesX) << kTileShift, y0 = (tile / tilesX) << kTileShift;
        int x1 = std::min(width, x0 + kTileSize) - 1, y1 = std::min(height, y0 + kTileSize) - 1;
        if (split > 1) {
            const int size = kTileSize / split;
            x0 += (part % split) * size;
            y0 += (part / split) * size;
            x1 = std::min(x1, x0 + size - 1);
            y1 = std::min(y1, y0 + size - 1);
            if (x0 > x1 || y0 > y1) return;
        }
        shade(tile, x0, y0, x1, y1, tileCounters[task]);
    });
    for (const ProgramCounters& c : tileCounters) counters.add(c);
}

}  // namespace rg::raster
