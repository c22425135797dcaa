// The programmable device (geforce8800): vertex program ─▶ clip (near/far, guard band)
// ─▶ viewport, snap ─▶ setup (the fixed-function edges, top-left rule and planes) ─▶
// 2×2 quads ─▶ early depth test ─▶ fragment program ─▶ late depth test ─▶ per-target
// blend and write mask ─▶ render targets (textures, sampled by later passes in place).
//
// Clipping, snapping and triangle setup are the fixed-function pipeline's own code, so
// both pipelines cover exactly the same pixels. Every float step is written down in
// docs/hardware.md ("Programmable profile"). The reference path walks each triangle's
// box pixel by pixel on one thread with tap-list texture fetches; the fast path bins
// triangles into 64×64 tiles that threads own, walks quads and fetches without the tap
// list. Both give the same bytes for any thread count (tests/programmable/).
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <type_traits>
#include <vector>

#include <glm/vec4.hpp>

#include "core/path.h"
#include "core/profile.h"
#include "rasterizer/device.h"
#include "rasterizer/program.h"
#include "rasterizer/quad_program.h"
#include "rasterizer/state.h"

namespace rg::raster {

namespace detail {

// One set-up triangle as the fragment kernel reads it (programmable.cpp fills it from the
// fixed-function setup). Edge i: E = C + A·X + B·Y at fixed-point pixel centres; covered
// ⇔ E ≥ 0 for all three. Planes are (c, dx, dy) per interpolated float, of a/w.
struct ProgramTriangle {
    std::array<int64_t, 3> A{}, B{}, C{};
    int minX = 0, minY = 0, maxX = -1, maxY = -1;  // inclusive, ∩ the clip rectangle
    float x0 = 0, y0 = 0;
    double zc = 0, zdx = 0, zdy = 0;
    float iwC = 0, iwDx = 0, iwDy = 0;
    const float* planes = nullptr;
};

struct TargetView {
    tex::TexelFormat format = tex::TexelFormat::RGBA8;
    int width = 0;
    Rgba8* data8 = nullptr;
    glm::vec4* dataF = nullptr;
    float* data1 = nullptr;  // R16F, R32F: one float per texel
    TargetBlend blend;
};

struct ProgramDraw {
    int subpixelBits = 8;
    int varyings = 0;           // vec4 varyings
    bool points = false;        // the point coordinate follows the varyings' planes
    int numTargets = 0;
    std::array<TargetView, kMaxColorTargets> targets{};
    // Depth attachment: window z quantized as the format stores it, compared as floats.
    float* depthData = nullptr;
    int depthWidth = 0;
    bool depthD24 = false;
    bool depthTest = false;
    bool depthWrite = false;
    CompareFunc depthFunc = CompareFunc::Less;
    FragmentContext::Setup ctx;
};

// The depth value the attachment stores for window z (docs/hardware.md): Depth24
// round(clamp(z)·(2^24 − 1)) / (2^24 − 1) rounded to float (a one-to-one, monotonic map
// of the 24-bit values, so float compares are integer compares); Depth32F clamp(z).
float storedDepth(bool depthD24, double z);
bool depthPasses(CompareFunc f, float incoming, float stored);
// The output merger for one fragment at pixel (x, y): blend and write every target the
// program wrote.
void mergeFragment(const ProgramDraw& d, int x, int y,
                   const std::array<glm::vec4, kMaxColorTargets>& out, uint32_t written);

// The output merger for the lanes `alive` of a quad program's quad at (qx, qy): RGBA8
// targets without blending convert and store the four lanes at once, the rest go through
// mergeFragment lane by lane. The same bytes as mergeFragment per lane.
void mergeQuad(const ProgramDraw& d, int qx, int qy, const QuadContext& f, uint32_t alive);

// A quad program (quad_program.h) takes a QuadContext; a scalar one a FragmentContext.
template <class FP>
constexpr bool kIsQuadProgram = requires(const FP& fp, QuadContext& q) { fp(q); };

// Interpolation (docs/hardware.md, "Programmable profile: interpolation"): every plane at
// fx = (x + ½) − x0, fy = (y + ½) − y0 as (c + dx·fx) + dy·fy in float, divided by 1/w.
inline void interpolateQuad(const ProgramDraw& d, const ProgramTriangle& t, int qx, int qy,
                            QuadVaryings& q, std::array<float, 4>& iw) {
    float fx[4], fy[4];
    for (int p = 0; p < 4; ++p) {
        fx[p] = (float(qx + (p & 1)) + 0.5f) - t.x0;
        fy[p] = (float(qy + (p >> 1)) + 0.5f) - t.y0;
        iw[size_t(p)] = (t.iwC + t.iwDx * fx[p]) + t.iwDy * fy[p];
    }
    const int n = 4 * d.varyings;
    for (int a = 0; a < n; ++a) {
        const float* pl = t.planes + 3 * a;
        for (int p = 0; p < 4; ++p)
            q.v[size_t(a >> 2)][size_t(p)][a & 3] = ((pl[0] + pl[1] * fx[p]) + pl[2] * fy[p]) / iw[size_t(p)];
    }
    if (d.points) {
        const float* pl = t.planes + 3 * n;
        for (int p = 0; p < 4; ++p) {
            glm::vec4& pc = q.v[kMaxVaryings][size_t(p)];
            pc.x = ((pl[0] + pl[1] * fx[p]) + pl[2] * fy[p]) / iw[size_t(p)];
            pc.y = ((pl[3] + pl[4] * fx[p]) + pl[5] * fy[p]) / iw[size_t(p)];
            pc.z = 0.0f;
            pc.w = 0.0f;
        }
    }
}

inline bool covers(const ProgramTriangle& t, int px, int py, int s) {
    const int64_t half = int64_t{1} << (s - 1);
    const int64_t X = (int64_t(px) << s) + half, Y = (int64_t(py) << s) + half;
    for (int e = 0; e < 3; ++e)
        if (t.C[size_t(e)] + t.A[size_t(e)] * X + t.B[size_t(e)] * Y < 0) return false;
    return true;
}

// One covered pixel through the early depth test, the program, the late depth test and
// the output merger. Both paths call exactly this.
template <class FP>
inline void shadeFragment(const FP& fp, const ProgramDraw& d, const ProgramTriangle& t,
                          const QuadVaryings& q, const std::array<float, 4>& iw, int p, int px,
                          int py, FragmentContext& f, ProgramCounters& c) {
    ++c.fragmentsGenerated;
    const double z = (t.zc + t.zdx * ((double(px) + 0.5) - double(t.x0))) +
                     t.zdy * ((double(py) + 0.5) - double(t.y0));
    float* depthTexel =
        d.depthData ? d.depthData + size_t(py) * size_t(d.depthWidth) + size_t(px) : nullptr;
    float zStore = depthTexel ? storedDepth(d.depthD24, z) : 0.0f;
    // Early depth test: a program that does not write depth cannot change the outcome.
    if (!FP::kWritesDepth && depthTexel && d.depthTest && !depthPasses(d.depthFunc, zStore, *depthTexel)) {
        ++c.fragmentsDepthFailed;
        return;
    }
    f.begin(d.ctx, &q, p, glm::vec4(float(px) + 0.5f, float(py) + 0.5f, float(z), iw[size_t(p)]));
    fp(f);
    ++c.fragmentInvocations;
    c.textureFetches += f.fetches();
    if (f.fetches() > c.maxFetchesPerFragment) c.maxFetchesPerFragment = f.fetches();
    if (f.discarded()) {
        ++c.fragmentsDiscarded;
        return;
    }
    if (FP::kWritesDepth && depthTexel) {
        zStore = storedDepth(d.depthD24, double(f.depthValue()));
        if (d.depthTest && !depthPasses(d.depthFunc, zStore, *depthTexel)) {
            ++c.fragmentsDepthFailed;
            return;
        }
    }
    if (depthTexel && d.depthWrite) *depthTexel = zStore;
    mergeFragment(d, px, py, f.outputs(), f.written());
    ++c.fragmentsWritten;
}

// The covered lanes `mask` of a quad through a quad program: the early depth test per
// lane, the program once for the lanes that passed, then per lane what shadeFragment does
// after the program. The counters are those of running the lanes one by one.
template <class FP>
inline void shadeQuadLanes(const FP& fp, const ProgramDraw& d, const ProgramTriangle& t,
                           const QuadVaryings& q, const std::array<float, 4>& iw, uint32_t mask,
                           int qx, int qy, QuadContext& f, ProgramCounters& c) {
    static_assert(!FP::kWritesDepth, "quad programs cannot write depth");
    float zf[4];
    float zStore[4] = {0, 0, 0, 0};
    uint32_t run = 0;
    for (int p = 0; p < 4; ++p) {
        const int px = qx + (p & 1), py = qy + (p >> 1);
        const double z = (t.zc + t.zdx * ((double(px) + 0.5) - double(t.x0))) +
                         t.zdy * ((double(py) + 0.5) - double(t.y0));
        zf[p] = float(z);
        if (!((mask >> p) & 1u)) continue;
        ++c.fragmentsGenerated;
        if (d.depthData) {
            zStore[p] = storedDepth(d.depthD24, z);
            const float stored = d.depthData[size_t(py) * size_t(d.depthWidth) + size_t(px)];
            if (d.depthTest && !depthPasses(d.depthFunc, zStore[p], stored)) {
                ++c.fragmentsDepthFailed;
                continue;
            }
        }
        run |= 1u << p;
    }
    if (!run) return;
    const float x0 = float(qx) + 0.5f, y0 = float(qy) + 0.5f;
    f.begin(d.ctx, &q, run,
            Vec4x4(Float4::lanes(x0, x0 + 1.0f, x0, x0 + 1.0f), Float4::lanes(y0, y0, y0 + 1.0f, y0 + 1.0f),
                   Float4::lanes(zf[0], zf[1], zf[2], zf[3]), Float4::lanes(iw[0], iw[1], iw[2], iw[3])));
    fp(f);
    uint32_t alive = 0;
    for (int p = 0; p < 4; ++p) {
        if (!((run >> p) & 1u)) continue;
        ++c.fragmentInvocations;
        c.textureFetches += f.fetches(p);
        if (f.fetches(p) > c.maxFetchesPerFragment) c.maxFetchesPerFragment = f.fetches(p);
        if ((f.discardedLanes() >> p) & 1u) {
            ++c.fragmentsDiscarded;
            continue;
        }
        alive |= 1u << p;
        ++c.fragmentsWritten;
        const int px = qx + (p & 1), py = qy + (p >> 1);
        if (d.depthData && d.depthWrite)
            d.depthData[size_t(py) * size_t(d.depthWidth) + size_t(px)] = zStore[p];
    }
    if (alive) mergeQuad(d, qx, qy, f, alive);
}

template <class FP>
struct ProgramKernel {
    const FP* fp;
    const ProgramDraw* d;

    // Fast path: the quads of triangle t inside the inclusive rectangle (a tile).
    static void runQuads(void* self, const ProgramTriangle& t, int rx0, int ry0, int rx1,
                         int ry1, ProgramCounters& c) {
        const auto& k = *static_cast<const ProgramKernel*>(self);
        const ProgramDraw& d = *k.d;
        const int x0 = std::max(rx0, t.minX), x1 = std::min(rx1, t.maxX);
        const int y0 = std::max(ry0, t.minY), y1 = std::min(ry1, t.maxY);
        if (x0 > x1 || y0 > y1) return;
        QuadVaryings q;
        std::array<float, 4> iw;
        std::conditional_t<kIsQuadProgram<FP>, QuadContext, FragmentContext> f;
        for (int qy = y0 & ~1; qy <= y1; qy += 2)
            for (int qx = x0 & ~1; qx <= x1; qx += 2) {
                uint32_t mask = 0;
                for (int p = 0; p < 4; ++p) {
                    const int px = qx + (p & 1), py = qy + (p >> 1);
                    if (px >= x0 && px <= x1 && py >= y0 && py <= y1 &&
                        covers(t, px, py, d.subpixelBits))
                        mask |= 1u << p;
                }
                if (!mask) continue;
                interpolateQuad(d, t, qx, qy, q, iw);
                if constexpr (kIsQuadProgram<FP>) {
                    shadeQuadLanes(*k.fp, d, t, q, iw, mask, qx, qy, f, c);
                } else {
                    for (int p = 0; p < 4; ++p)
                        if (mask & (1u << p))
                            shadeFragment(*k.fp, d, t, q, iw, p, qx + (p & 1), qy + (p >> 1), f, c);
                }
            }
    }

    // Reference path: the triangle's box pixel by pixel in scanline order; each pixel's
    // quad is interpolated for its derivatives.
    static void runPixels(void* self, const ProgramTriangle& t, int, int, int, int,
                          ProgramCounters& c) {
        const auto& k = *static_cast<const ProgramKernel*>(self);
        const ProgramDraw& d = *k.d;
        QuadVaryings q;
        std::array<float, 4> iw;
        std::conditional_t<kIsQuadProgram<FP>, QuadContext, FragmentContext> f;
        for (int py = t.minY; py <= t.maxY; ++py)
            for (int px = t.minX; px <= t.maxX; ++px) {
                if (!covers(t, px, py, d.subpixelBits)) continue;
                interpolateQuad(d, t, px & ~1, py & ~1, q, iw);
                const int p = (px & 1) | ((py & 1) << 1);
                // A quad program runs with this pixel's lane alone.
                if constexpr (kIsQuadProgram<FP>)
                    shadeQuadLanes(*k.fp, d, t, q, iw, 1u << p, px & ~1, py & ~1, f, c);
                else
                    shadeFragment(*k.fp, d, t, q, iw, p, px, py, f, c);
            }
    }
};

using TriangleKernelFn = void (*)(void* self, const ProgramTriangle& t, int rx0, int ry0,
                                  int rx1, int ry1, ProgramCounters& c);

// One vertex after the vertex program.
struct ProgramVertex {
    glm::vec4 clip{0.0f};
    Varyings varyings{};
};

}  // namespace detail

class ProgrammableDevice {
  public:
    // Throws rg::UnsupportedFeature unless the profile has vertex and fragment programs.
    explicit ProgrammableDevice(const Profile& profile, DeviceOptions options = {});
    ~ProgrammableDevice();
    ProgrammableDevice(const ProgrammableDevice&) = delete;
    ProgrammableDevice& operator=(const ProgrammableDevice&) = delete;

    const Profile& profile() const;
    void setPath(Path path);
    void setThreads(int threads);

    // ---- output merger --------------------------------------------------------------------
    // Attaches up to kMaxColorTargets colour targets and an optional depth target, all of
    // one size; resets the viewport and scissor to the whole target. Throws for a texture
    // that is not a render target, a format that cannot be rendered to, mismatched sizes,
    // more targets than the profile has (Feature::MultipleRenderTargets).
    void setRenderTargets(std::span<const ColorTarget> colors, const DepthTarget& depth = {});
    int targetWidth() const;
    int targetHeight() const;
    void setState(const ProgramState& state);
    const ProgramState& state() const;
    void setViewport(const Viewport& viewport);
    void setScissor(const Rect* rect);  // nullptr: off

    // ---- resources --------------------------------------------------------------------------
    // Binds a texture and its sampler to unit `unit` (< kMaxProgramUnits); nullptr unbinds.
    void setTexture(int unit, std::shared_ptr<const tex::Texture> texture,
                    const tex::SamplerState& sampler = {});

    // ---- frames and commands --------------------------------------------------------------
    void beginFrame();
    void clearColor(int target, const glm::vec4& value);  // inside viewport ∩ scissor
    void clearDepth(float value);
    const ProgramCounters& counters() const;

    template <class VP, class FP, class V>
    void draw(const VP& vp, const FP& fp, ProgramPrimitive primitive, std::span<const V> vertices,
              std::span<const uint32_t> indices = {}) {
        static_assert(VP::kVaryings == FP::kVaryings, "vertex and fragment programs disagree on kVaryings");
        static_assert(FP::kVaryings >= 0 && FP::kVaryings <= kMaxVaryings, "too many varyings");
        detail::ProgramDraw& d = beginDraw(FP::kVaryings, FP::kTargets, FP::kUnits, primitive,
                                           vertices.size(), indices);
        std::vector<detail::ProgramVertex>& out = vertexScratch(vertices.size());
        forEachVertexRange(vertices.size(), [&](size_t b, size_t e) {
            for (size_t i = b; i < e; ++i) out[i].clip = vp(vertices[i], out[i].varyings);
        });
        detail::ProgramKernel<FP> kernel{&fp, &d};
        finishDraw(primitive, indices, &detail::ProgramKernel<FP>::runQuads,
                   &detail::ProgramKernel<FP>::runPixels, &kernel);
    }

  private:
    detail::ProgramDraw& beginDraw(int varyings, uint32_t targets, uint32_t units,
                                   ProgramPrimitive primitive, size_t vertexCount,
                                   std::span<const uint32_t> indices);
    std::vector<detail::ProgramVertex>& vertexScratch(size_t n);
    void forEachVertexRange(size_t n, const std::function<void(size_t, size_t)>& body);
    void finishDraw(ProgramPrimitive primitive, std::span<const uint32_t> indices,
                    detail::TriangleKernelFn fast, detail::TriangleKernelFn reference,
                    void* kernel);

    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace rg::raster
