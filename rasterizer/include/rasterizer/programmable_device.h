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

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <exception>
#include <memory>
#include <span>
#include <type_traits>
#include <typeindex>
#include <typeinfo>
#include <vector>

#include <glm/vec4.hpp>

#include "core/path.h"
#include "core/profile.h"
#include "rasterizer/device.h"
#include "rasterizer/fragment_ops.h"
#include "rasterizer/program.h"
#include "rasterizer/quad_program.h"
#include "rasterizer/quad_program_wide.h"
#include "rasterizer/state.h"

// The AVX2 kernel's shading is flattened: every call in it inlined, so that no 256-bit value
// crosses a call (a default-target callee takes them through memory; without flatten the
// impostor glass programs ran 2.1-2.6x slower, impostor_secant/height, 2 threads). The
// sanitizer builds define RETROGLASS_NO_FLATTEN (CMakeLists.txt): instrumenting one
// flattened glass kernel took 36 CPU-minutes and 5.6 GB under address,undefined, against
// about 1.5 unflattened; the operations, and so the bytes, are the same either way.
#ifdef RETROGLASS_NO_FLATTEN
#define RG_KERNEL_FLATTEN
#else
#define RG_KERNEL_FLATTEN gnu::flatten
#endif

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
inline bool depthPasses(CompareFunc f, float incoming, float stored) {
    return comparePasses(f, incoming, stored);
}
// storedDepth on a quad's four window z, two lanes per SSE2 register: the same IEEE double
// operations lane by lane. quantizeDepth's cases as a clamp, c = z > 0 ? min(z, 1) : 0 (NaN
// to 0); Depth24 then q = floor(c·(2^24 − 1) + ½) — the sum lies in [½, 2^24), where
// truncation is floor — and float(q / (2^24 − 1)), computed as float(q·(1/(2^24 − 1))):
// the division's bits for every 24-bit q (q/(2^24 − 1) repeats q's 24 bits in binary, so
// it is never within the product's error of a float rounding boundary; the test runs all
// 2^24), where the division cost a sky fragment more than its depth test. Depth32F float(c).
inline void storedDepthQuad(bool depthD24, const double (&z)[4], float (&out)[4]) {
    const __m128d zero = _mm_setzero_pd(), one = _mm_set1_pd(1.0);
    const __m128d maxD = _mm_set1_pd(double((1u << 24) - 1u)), half = _mm_set1_pd(0.5);
    const __m128d invMax = _mm_set1_pd(1.0 / double((1u << 24) - 1u));
    __m128 pair[2];
    for (int h = 0; h < 2; ++h) {
        const __m128d zz = _mm_loadu_pd(z + 2 * h);
        __m128d c = _mm_and_pd(_mm_cmpgt_pd(zz, zero), _mm_min_pd(zz, one));
        if (depthD24) {
            const __m128i q = _mm_cvttpd_epi32(_mm_add_pd(_mm_mul_pd(c, maxD), half));
            c = _mm_mul_pd(_mm_cvtepi32_pd(q), invMax);
        }
        pair[h] = _mm_cvtpd_ps(c);
    }
    _mm_storeu_ps(out, _mm_movelh_ps(pair[0], pair[1]));
}
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

// Window z at a quad's four pixels as shadeFragment computes it, (zc + zdx·fx) + zdy·fy in
// double, two pixels of a row per SSE2 register (the same IEEE operations lane by lane).
inline void quadDepths(const ProgramTriangle& t, int qx, int qy, double (&z)[4]) {
    const __m128d fx = _mm_sub_pd(_mm_setr_pd(double(qx) + 0.5, double(qx + 1) + 0.5), _mm_set1_pd(double(t.x0)));
    const __m128d zRow = _mm_add_pd(_mm_set1_pd(t.zc), _mm_mul_pd(_mm_set1_pd(t.zdx), fx));
    const double fy0 = (double(qy) + 0.5) - double(t.y0), fy1 = (double(qy + 1) + 0.5) - double(t.y0);
    _mm_storeu_pd(z, _mm_add_pd(zRow, _mm_mul_pd(_mm_set1_pd(t.zdy), _mm_set1_pd(fy0))));
    _mm_storeu_pd(z + 2, _mm_add_pd(zRow, _mm_mul_pd(_mm_set1_pd(t.zdy), _mm_set1_pd(fy1))));
}

// A pending quad's window z per pixel (a struct, so that arrays of them copy).
struct QuadDepths {
    double z[4];
};

// A quad program's quad before the program: the early depth test per covered lane; the
// lanes that passed, and the context begun on them. zStore: what depth writes store. z:
// each pixel's window z (quadDepths of the triangle that covers it).
inline uint32_t beginQuadLanes(const ProgramDraw& d, const double (&z)[4], const QuadVaryings& q,
                               const std::array<float, 4>& iw, uint32_t mask, int qx, int qy,
                               QuadContext& f, float (&zStore)[4], ProgramCounters& c) {
    const __m128 zf = _mm_movelh_ps(_mm_cvtpd_ps(_mm_loadu_pd(z)), _mm_cvtpd_ps(_mm_loadu_pd(z + 2)));
    uint32_t run = mask;
    c.fragmentsGenerated += uint32_t(std::popcount(mask));
    zStore[0] = zStore[1] = zStore[2] = zStore[3] = 0.0f;
    if (d.depthData) {
        storedDepthQuad(d.depthD24, z, zStore);  // uncovered lanes' values are never stored
        for (int p = 0; p < 4; ++p) {
            if (!((mask >> p) & 1u)) continue;
            const int px = qx + (p & 1), py = qy + (p >> 1);
            const float stored = d.depthData[size_t(py) * size_t(d.depthWidth) + size_t(px)];
            if (d.depthTest && !depthPasses(d.depthFunc, zStore[p], stored)) {
                ++c.fragmentsDepthFailed;
                run &= ~(1u << p);
            }
        }
    }
    const __m128 x0 = _mm_set1_ps(float(qx) + 0.5f), y0 = _mm_set1_ps(float(qy) + 0.5f);
    f.begin(d.ctx, &q, run,
            Vec4x4(Float4(_mm_add_ps(x0, _mm_setr_ps(0.0f, 1.0f, 0.0f, 1.0f))),
                   Float4(_mm_add_ps(y0, _mm_setr_ps(0.0f, 0.0f, 1.0f, 1.0f))), Float4(zf),
                   Float4(_mm_loadu_ps(iw.data()))));
    return run;
}
inline uint32_t beginQuadLanes(const ProgramDraw& d, const ProgramTriangle& t, const QuadVaryings& q,
                               const std::array<float, 4>& iw, uint32_t mask, int qx, int qy,
                               QuadContext& f, float (&zStore)[4], ProgramCounters& c) {
    double z[4];
    quadDepths(t, qx, qy, z);
    return beginQuadLanes(d, z, q, iw, mask, qx, qy, f, zStore, c);
}

// RGBA8 without blending or write mask: tex::floatToRgba8 on four lanes — max(x, 0) also
// maps NaN to 0 (MAXPS returns its second operand), then min(x, 1), x·255 + ½ and
// truncation (= floor here) — stored for the lanes in `lanes`, a full quad as two rows.
inline void storeQuadRgba8(const TargetView& t, int qx, int qy, const Vec4x4& o, uint32_t lanes) {
    auto unorm = [](__m128 x) {
        x = _mm_min_ps(_mm_max_ps(x, _mm_setzero_ps()), _mm_set1_ps(1.0f));
        return _mm_cvttps_epi32(_mm_add_ps(_mm_mul_ps(x, _mm_set1_ps(255.0f)), _mm_set1_ps(0.5f)));
    };
    const __m128i px = _mm_or_si128(_mm_or_si128(unorm(o.x.v), _mm_slli_epi32(unorm(o.y.v), 8)),
                                    _mm_or_si128(_mm_slli_epi32(unorm(o.z.v), 16), _mm_slli_epi32(unorm(o.w.v), 24)));
    Rgba8* row = t.data8 + size_t(qy) * size_t(t.width) + size_t(qx);  // Rgba8 is r, g, b, a in memory
    if (lanes == 15) {
        _mm_storel_epi64(reinterpret_cast<__m128i*>(static_cast<void*>(row)), px);
        _mm_storel_epi64(reinterpret_cast<__m128i*>(static_cast<void*>(row + t.width)),
                         _mm_unpackhi_epi64(px, px));
        return;
    }
    alignas(16) uint32_t v[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(v), px);
    for (int p = 0; p < 4; ++p)
        if ((lanes >> p) & 1u)
            std::memcpy(static_cast<void*>(row + size_t(p >> 1) * size_t(t.width) + size_t(p & 1)), &v[p], 4);
}

// After the program: per lane what shadeFragment does after the program (counters, depth
// write); the lanes that reach the output merger.
inline uint32_t finishQuadCounters(const ProgramDraw& d, int qx, int qy, const QuadContext& f,
                                   const float (&zStore)[4], ProgramCounters& c) {
    const uint32_t run = f.runLanes();
    const uint32_t discarded = f.discardedLanes() & run, alive = run & ~discarded;
    c.fragmentInvocations += uint32_t(std::popcount(run));
    c.fragmentsDiscarded += uint32_t(std::popcount(discarded));
    c.fragmentsWritten += uint32_t(std::popcount(alive));
    // The run lanes' fetch counts: their sum and their maximum (signed compares order them,
    // a lane's count being below 2^31).
    const __m128i n = _mm_and_si128(f.fetchLanes(), _mm_castps_si128(Mask4::fromBits(run).v));
    auto vmax = [](__m128i a, __m128i b) {
        const __m128i gt = _mm_cmpgt_epi32(a, b);
        return _mm_or_si128(_mm_and_si128(gt, a), _mm_andnot_si128(gt, b));
    };
    const __m128i sum2 = _mm_add_epi32(n, _mm_shuffle_epi32(n, _MM_SHUFFLE(1, 0, 3, 2)));
    const __m128i max2 = vmax(n, _mm_shuffle_epi32(n, _MM_SHUFFLE(1, 0, 3, 2)));
    const uint32_t fetches = uint32_t(_mm_cvtsi128_si32(_mm_add_epi32(sum2, _mm_shuffle_epi32(sum2, 0xB1))));
    const uint32_t most = uint32_t(_mm_cvtsi128_si32(vmax(max2, _mm_shuffle_epi32(max2, 0xB1))));
    c.textureFetches += fetches;
    if (most > c.maxFetchesPerFragment) c.maxFetchesPerFragment = most;
    if (!alive) return 0;
    if (d.depthData && d.depthWrite)
        for (int p = 0; p < 4; ++p)
            if ((alive >> p) & 1u)
                d.depthData[size_t(qy + (p >> 1)) * size_t(d.depthWidth) + size_t(qx + (p & 1))] = zStore[p];
    return alive;
}

// One RGBA8 target without blending or write mask: storeQuadRgba8 applies.
inline bool plainRgba8Target(const ProgramDraw& d) {
    const TargetView& t0 = d.targets[0];
    return d.numTargets == 1 && t0.data8 && !t0.blend.enable && t0.blend.writeMask == kWriteRGBA;
}

// The output merger for the lanes `alive` of a quad program's quad.
inline void mergeQuadLanes(const ProgramDraw& d, int qx, int qy, const QuadContext& f, uint32_t alive) {
    if (plainRgba8Target(d)) {
        if (const uint32_t lanes = f.writtenLanes(0) & alive) storeQuadRgba8(d.targets[0], qx, qy, f.outQuad(0), lanes);
        return;
    }
    mergeQuad(d, qx, qy, f, alive);
}

inline void finishQuadLanes(const ProgramDraw& d, int qx, int qy, const QuadContext& f,
                            const float (&zStore)[4], ProgramCounters& c) {
    if (const uint32_t alive = finishQuadCounters(d, qx, qy, f, zStore, c)) mergeQuadLanes(d, qx, qy, f, alive);
}

// storeQuadRgba8 for two whole quads at once, eight lanes per 256-bit operation (the AVX2
// kernel): the same MAXPS/MINPS operand order, x·255 + ½ and truncation lane by lane; each
// quad's two rows stored as storeQuadRgba8 stores them. A target function taking its
// vectors through references, like nearestFetchAvx2.
[[gnu::target("avx2")]] inline void storeQuadPairRgba8Avx2(const TargetView& t, int qxa, int qya, const Vec4x4& a,
                                                            int qxb, int qyb, const Vec4x4& b) {
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const __m256 scale = _mm256_set1_ps(255.0f), half = _mm256_set1_ps(0.5f);
    __m256i c[4];
    const Float4* ca[4] = {&a.x, &a.y, &a.z, &a.w};
    const Float4* cb[4] = {&b.x, &b.y, &b.z, &b.w};
    for (int k = 0; k < 4; ++k) {
        const __m256 v = _mm256_set_m128(cb[k]->v, ca[k]->v);
        const __m256 x = _mm256_min_ps(_mm256_max_ps(v, zero), one);
        c[k] = _mm256_slli_epi32(_mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(x, scale), half)), 8 * k);
    }
    const __m256i px = _mm256_or_si256(_mm256_or_si256(c[0], c[1]), _mm256_or_si256(c[2], c[3]));
    const __m128i pa = _mm256_castsi256_si128(px), pb = _mm256_extracti128_si256(px, 1);
    Rgba8* ra = t.data8 + size_t(qya) * size_t(t.width) + size_t(qxa);
    Rgba8* rb = t.data8 + size_t(qyb) * size_t(t.width) + size_t(qxb);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(static_cast<void*>(ra)), pa);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(static_cast<void*>(ra + t.width)), _mm_unpackhi_epi64(pa, pa));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(static_cast<void*>(rb)), pb);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(static_cast<void*>(rb + t.width)), _mm_unpackhi_epi64(pb, pb));
}

// The covered lanes `mask` of a quad through a quad program: the early depth test per
// lane, the program once for the lanes that passed, then per lane what shadeFragment does
// after the program. The counters are those of running the lanes one by one.
template <class FP, class Depths>
inline void shadeQuadLanes(const FP& fp, const ProgramDraw& d, const Depths& tOrZ,
                           const QuadVaryings& q, const std::array<float, 4>& iw, uint32_t mask,
                           int qx, int qy, QuadContext& f, ProgramCounters& c) {
    static_assert(!FP::kWritesDepth, "quad programs cannot write depth");
    float zStore[4];
    if (!beginQuadLanes(d, tOrZ, q, iw, mask, qx, qy, f, zStore, c)) return;
    fp(f);
    finishQuadLanes(d, qx, qy, f, zStore, c);
}

// The point-sampled fast case of a unit (NearestFloat2D; not valid() when the texture or
// sampler is not one), resolved once when the unit is bound.
NearestFloat2D nearestFloat2D(const tex::Texture* texture, const tex::SamplerState& sampler);
// The bilinear float cube-map case of a unit (LinearFloatCube; not valid() otherwise).
LinearFloatCube linearFloatCube(const tex::Texture* texture, const tex::SamplerState& sampler);
// The bilinear float 2D case of a unit (LinearFloat2D; not valid() otherwise).
LinearFloat2D linearFloat2D(const tex::Texture* texture, const tex::SamplerState& sampler);

// The CPU runs AVX2 and RETROGLASS_NO_AVX2 is not set (which keeps the SSE2 kernels, so
// the tests can hold both to the reference).
bool programAvx2();

// Quads per group for programs that run on a QuadGroupContext (quad_program.h): the SSE2
// kernel, and the AVX2 kernel's QuadGroupWideContext (two quads per 256-bit register; eight
// quads give the texel loads of four registers to overlap, measured faster than four or
// twelve on tir's frame; a program may ask for fewer, kWideQuads). A triangle's last
// quads, fewer than a group, run in pairs on the AVX2 kernel (ProgramKernel::shadeQuadPairs)
// and one by one on the SSE2 kernel.
constexpr int kGroupQuads = 4;
constexpr int kWideGroupQuads = 8;
// kLaneIndependent programs (ProgramKernel::runFusedGroups): pending quads a tile run may
// hold while other triangles fill their lanes, and the side of the rectangles it runs (a
// tile's; the map holds their quad positions, one more each way for an odd start).
constexpr int kFusionSlots = 64;
constexpr int kFusionSide = 64;
constexpr int kFusionMap = (kFusionSide / 2 + 1) * (kFusionSide / 2 + 1);

// A quad program written for any context (a template on it) also runs kGroupQuads quads
// at once on the fast path.
template <class FP>
constexpr bool kIsGroupProgram = kIsQuadProgram<FP> &&
                                 requires(const FP& fp, QuadGroupContext<kGroupQuads>& g,
                                          QuadGroupWideContext<kWideGroupQuads>& w,
                                          QuadGroupWideContext<2>& pair) {
                                     fp(g);
                                     fp(w);
                                     fp(pair);
                                 };

// The AVX2 kernel's quads per group for program FP: kWideGroupQuads, or the program's own
// kWideQuads (2, 4 or 8). Eight quads keep four 256-bit registers of independent fetch
// chains in flight, which tir's short searches over a small depth map want; a long program
// whose every value is four registers wide spills most of them instead (the impostors'
// glass programs: four quads measured 15-20 % faster than eight, and two slower again).
template <class FP>
constexpr int kWideQuads = [] {
    if constexpr (requires { FP::kWideQuads; }) {
        static_assert(FP::kWideQuads == 2 || FP::kWideQuads == 4 || FP::kWideQuads == 8,
                      "kWideQuads: 2, 4 or 8 quads a group");
        return int(FP::kWideQuads);
    } else {
        return kWideGroupQuads;
    }
}();

// A group program runs on the AVX2 kernel where the CPU has AVX2, unless it declares
// kWideKernel = false: then it takes the SSE2 kernel everywhere (the same bytes: the two
// kernels do the same IEEE operations, ProgrammablePathsAgree). The flattened kernel is the
// costliest code to compile (1.5-2 CPU-minutes a glass program), so a program that is never
// timed — the impostors' diagnostic variants, which write their searches' internals for the
// report's figures — leaves it out.
template <class FP>
constexpr bool kWideKernel = [] {
    if constexpr (requires { FP::kWideKernel; })
        return bool(FP::kWideKernel);
    else
        return true;
}();

// A program whose lanes never read one another: no derivative and no implicit-λ fetch (only
// sampleLevel with an explicit λ, varyings, fragCoord, outputs), declared by
// kLaneIndependent = true. Its fast path fills a quad's uncovered lanes with the pixels other
// triangles cover at the same quad (ProgramKernel::runFusedGroups): each lane still computes
// what it computes alone, from its own triangle's varyings, 1/w and z, so the bytes are the
// reference path's (ProgrammablePathsAgree and the golden traces hold the programs that
// declare it to that), while meshes of one- or two-pixel triangles, whose quads are a third
// to a half covered, run far fewer quads. A program that declares it and takes a derivative
// would read a neighbour of another triangle: only for programs that cannot.
template <class FP>
constexpr bool kLaneIndependent = [] {
    if constexpr (requires { FP::kLaneIndependent; })
        return bool(FP::kLaneIndependent);
    else
        return false;
}();

// The quads of a group through the program at once: what shadeQuadLanes does to each, in
// the same order for everything outside the program (the quads' pixels are distinct, so
// early tests before the other quads' depth writes see the same values). Quad i belongs
// to the triangles whose pixels' window z are zs[i]: a group may gather the quads of several
// small triangles (and a quad the pixels of several, kLaneIndependent).
template <class FP, int N, class Group>
inline void shadeQuadGroup(const FP& fp, const ProgramDraw& d, const std::array<QuadDepths, N>& zs,
                           const std::array<QuadVaryings, N>& q, const std::array<std::array<float, 4>, N>& iw,
                           const std::array<uint32_t, N>& mask, const std::array<int, N>& qx,
                           const std::array<int, N>& qy, Group& g, ProgramCounters& c) {
    static_assert(!FP::kWritesDepth, "quad programs cannot write depth");
    float zStore[N][4];
    uint32_t run = 0;
    for (int i = 0; i < N; ++i)
        run |= beginQuadLanes(d, zs[size_t(i)].z, q[size_t(i)], iw[size_t(i)], mask[size_t(i)], qx[size_t(i)],
                              qy[size_t(i)], g.quad(i), zStore[i], c);
    if (!run) return;
    g.beginGroup();
    fp(g);
    g.endGroup();
    if constexpr (std::is_same_v<Group, QuadGroupWideContext<N>>) {
        // The counters and depth writes of every quad, then the output merger quad after
        // quad, two whole quads of a plain RGBA8 target at once. The quads' pixels are
        // distinct and the counters are sums and a maximum, so the same bytes and counts
        // as finishing quad by quad.
        uint32_t alive[N];
        for (int i = 0; i < N; ++i)
            alive[i] = finishQuadCounters(d, qx[size_t(i)], qy[size_t(i)], g.quad(i), zStore[i], c);
        const bool plain = plainRgba8Target(d);
        for (int i = 0; i < N; i += 2) {
            const QuadContext &a = g.quad(i), &b = g.quad(i + 1);
            if (plain && (a.writtenLanes(0) & alive[i]) == 15u && (b.writtenLanes(0) & alive[i + 1]) == 15u) {
                storeQuadPairRgba8Avx2(d.targets[0], qx[size_t(i)], qy[size_t(i)], a.outQuad(0), qx[size_t(i + 1)],
                                       qy[size_t(i + 1)], b.outQuad(0));
                continue;
            }
            for (int j = i; j < i + 2; ++j)
                if (alive[j]) mergeQuadLanes(d, qx[size_t(j)], qy[size_t(j)], g.quad(j), alive[j]);
        }
    } else {
        for (int i = 0; i < N; ++i) finishQuadLanes(d, qx[size_t(i)], qy[size_t(i)], g.quad(i), zStore[i], c);
    }
}

// The coverage of the quads along a row for the AVX2 kernel: the three edge functions at a
// quad's four pixels as int64 lanes (edge e, pixel p: Ep[e][p]), OR-ed so that a lane's
// sign is set where any edge is negative — the integers and the test of runQuadGroups'
// scalar loop — then stepped to the next quad. Bit p: pixel p covered. A target function
// taking its vectors through memory, like nearestFetchAvx2; inlined into the flattened
// kernel, they stay in registers.
[[gnu::target("avx2")]] inline uint32_t quadCoverageStepAvx2(int64_t (&Ep)[3][4], const int64_t (&stepX)[3]) {
    __m256i e[3];
    for (int k = 0; k < 3; ++k) e[k] = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(Ep[k]));
    const __m256i any = _mm256_or_si256(_mm256_or_si256(e[0], e[1]), e[2]);
    const uint32_t negative = uint32_t(_mm256_movemask_pd(_mm256_castsi256_pd(any)));
    for (int k = 0; k < 3; ++k)
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(Ep[k]),
                            _mm256_add_epi64(e[k], _mm256_set1_epi64x(stepX[k])));
    return ~negative & 15u;
}

template <class FP>
struct ProgramKernel {
    const FP* fp;
    const ProgramDraw* d;

    // Fast path, a program other than a group program: the quads of triangle t inside the
    // inclusive rectangle (a tile).
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
                const uint32_t mask = quadCoverage(d, t, qx, qy, x0, y0, x1, y1);
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

    // Fast path: the quads of triangles items[0 .. count) of `tris` (tris[0 .. count) when
    // items is null), in that order, inside the inclusive rectangle. A group program's
    // groups gather quads across the triangles (runQuadGroups); any other program runs
    // triangle by triangle.
    static void runTriangles(void* self, const ProgramTriangle* tris, const uint32_t* items, uint32_t count,
                             int rx0, int ry0, int rx1, int ry1, ProgramCounters& c) {
        if constexpr (kIsGroupProgram<FP>) {
            const auto& k = *static_cast<const ProgramKernel*>(self);
            if constexpr (kWideKernel<FP>)
                if (programAvx2()) return runQuadGroupsAvx2(k, tris, items, count, rx0, ry0, rx1, ry1, c);
            runQuadGroups(k, tris, items, count, rx0, ry0, rx1, ry1, c);
        } else {
            for (uint32_t i = 0; i < count; ++i) runQuads(self, tris[items ? items[i] : i], rx0, ry0, rx1, ry1, c);
        }
    }

    // The covered pixels of the quad at (qx, qy) inside the inclusive rectangle, bit p for
    // pixel (qx + (p & 1), qy + (p >> 1)).
    static uint32_t quadCoverage(const ProgramDraw& d, const ProgramTriangle& t, int qx, int qy, int x0,
                                 int y0, int x1, int y1) {
        uint32_t mask = 0;
        for (int p = 0; p < 4; ++p) {
            const int px = qx + (p & 1), py = qy + (p >> 1);
            if (px >= x0 && px <= x1 && py >= y0 && py <= y1 && covers(t, px, py, d.subpixelBits))
                mask |= 1u << p;
        }
        return mask;
    }

    // runQuadGroups compiled for AVX2 machines (selected at run time, programAvx2): the same
    // SSE operations, VEX-encoded — three operands, so the quads' chains need no register
    // copies — and SSE4.1's inserts and extracts for the texel loads. No FMA (target
    // "avx2" alone, and -ffp-contract=off): every operation is the one of the SSE2 build.
    [[gnu::target("avx2"), RG_KERNEL_FLATTEN]] static void runQuadGroupsAvx2(const ProgramKernel& k,
                                                                     const ProgramTriangle* tris,
                                                                     const uint32_t* items, uint32_t count,
                                                                     int rx0, int ry0, int rx1, int ry1,
                                                                     ProgramCounters& c) {
        runQuadGroups<QuadGroupWideContext<kWideQuads<FP>>>(k, tris, items, count, rx0, ry0, rx1, ry1, c);
    }

    // The covered quads of triangle t inside the inclusive rectangle, row after row, as
    // emit(qx, qy, m), bit p of m for pixel (qx + (p & 1), qy + (p >> 1)). Coverage steps the
    // edge functions along each row of quads (the integers covers() computes, exactly).
    template <bool kWide, class Emit>
    [[gnu::always_inline]] static void forEachCoveredQuad(const ProgramDraw& d, const ProgramTriangle& t, int rx0,
                                                          int ry0, int rx1, int ry1, Emit&& emit) {
        const int x0 = std::max(rx0, t.minX), x1 = std::min(rx1, t.maxX);
        const int y0 = std::max(ry0, t.minY), y1 = std::min(ry1, t.maxY);
        if (x0 > x1 || y0 > y1) return;
        const int s = d.subpixelBits;
        const int64_t half = int64_t{1} << (s - 1);
        // Edge e at the quad's pixel p: E + off[e][p]; E steps by 2·A per quad along a row.
        int64_t off[3][4], stepX[3];
        for (int e = 0; e < 3; ++e) {
            const int64_t a = t.A[size_t(e)] << s, b = t.B[size_t(e)] << s;
            off[e][0] = 0;
            off[e][1] = a;
            off[e][2] = b;
            off[e][3] = a + b;
            stepX[e] = 2 * a;
        }
        for (int qy = y0 & ~1; qy <= y1; qy += 2) {
            const uint32_t rows = (qy >= y0 ? 3u : 0u) | (qy + 1 <= y1 ? 12u : 0u);
            const int64_t Y = (int64_t(qy) << s) + half;
            // The quads of the row that can be covered: an edge's largest value over a
            // quad's pixels must be ≥ 0. In double with a quad's margin, so the range only
            // skips quads the exact test below would reject.
            int qxa = x0 & ~1, qxb = x1;
            for (int e = 0; e < 3 && qxa <= qxb; ++e) {
                const int64_t a = t.A[size_t(e)], b = t.B[size_t(e)];
                const double rowBest = double(t.C[size_t(e)] + b * (Y + (b > 0 ? (int64_t{1} << s) : 0)));
                if (a == 0) {
                    if (rowBest < 0.0) qxa = qxb + 1;
                    continue;
                }
                // Largest value at quad qx: rowBest + a·X(qx + (a > 0)), X(px) = (px << s) + half.
                const double px = -(rowBest + double(a) * double(half)) / double(a * (int64_t{1} << s));
                if (a > 0) {  // value grows with x: quads from x ≥ px − 1
                    const double lo = std::floor(px) - 3.0;
                    if (lo > double(qxa)) qxa = lo > double(qxb) ? qxb + 1 : int(lo) & ~1;
                } else {  // quads up to px
                    const double hi = std::ceil(px) + 3.0;
                    if (hi < double(qxb)) qxb = hi < double(qxa) ? qxa - 1 : int(hi);
                }
            }
            const int qx0 = qxa & ~1;
            const int64_t X = (int64_t(qx0) << s) + half;
            int64_t E[3];
            for (int e = 0; e < 3; ++e) E[e] = t.C[size_t(e)] + t.A[size_t(e)] * X + t.B[size_t(e)] * Y;
            int64_t Ep[3][4];  // the AVX2 kernel's form of E + off
            if constexpr (kWide)
                for (int e = 0; e < 3; ++e)
                    for (int p = 0; p < 4; ++p) Ep[e][p] = E[e] + off[e][p];
            for (int qx = qx0; qx <= qxb; qx += 2) {
                uint32_t m = 0;
                if constexpr (kWide) {
                    m = quadCoverageStepAvx2(Ep, stepX);
                } else {
                    for (int p = 0; p < 4; ++p) {
                        const int64_t all = (E[0] + off[0][p]) | (E[1] + off[1][p]) | (E[2] + off[2][p]);
                        m |= uint32_t(all >= 0) << p;  // every edge ≥ 0
                    }
                    for (int e = 0; e < 3; ++e) E[e] += stepX[e];
                }
                m &= rows & ((qx >= x0 ? 5u : 0u) | (qx + 1 <= x1 ? 10u : 0u));
                if (m) emit(qx, qy, m);
            }
        }
    }

    // runTriangles for a group program: each triangle's covered quads in the same order,
    // kGroupQuads at a time, the groups gathered across the triangles — the chess pieces'
    // triangles cover a quad or two each, so groups of one triangle's quads were mostly
    // left over and ran in pairs. A quad whose pixels meet a pending quad's (an earlier,
    // overlapping triangle's) first runs the pending ones, so every pixel's fragments still
    // meet the depth test and the output merger in triangle order; a group's quads are then
    // always distinct pixels, as shadeQuadGroup needs. The last incomplete group runs quad
    // by quad (SSE2) or in pairs (AVX2). The counters add up locally. kLaneIndependent
    // programs take runFusedGroups instead.
    template <class Group = QuadGroupContext<kGroupQuads>>
    static void runQuadGroups(const ProgramKernel& k, const ProgramTriangle* tris, const uint32_t* items,
                              uint32_t count, int rx0, int ry0, int rx1, int ry1, ProgramCounters& counters) {
        if constexpr (kLaneIndependent<FP>) {
            // Rectangles of at most kFusionSide² pixels (a tile is one): disjoint pixels, so
            // each keeps its pixels' triangle order by itself.
            for (int y = ry0; y <= ry1; y += kFusionSide)
                for (int x = rx0; x <= rx1; x += kFusionSide)
                    runFusedGroups<Group>(k, tris, items, count, x, y, std::min(rx1, x + kFusionSide - 1),
                                          std::min(ry1, y + kFusionSide - 1), counters);
            return;
        } else {
            runUnfusedGroups<Group>(k, tris, items, count, rx0, ry0, rx1, ry1, counters);
        }
    }
    // Only one of the two is instantiated for a program (each holds the program).
    template <class Group>
    static void runUnfusedGroups(const ProgramKernel& k, const ProgramTriangle* tris, const uint32_t* items,
                                 uint32_t count, int rx0, int ry0, int rx1, int ry1, ProgramCounters& counters) {
        constexpr int N = Group::kQuads;
        constexpr bool kWide = std::is_same_v<Group, QuadGroupWideContext<kWideQuads<FP>>>;
        const ProgramDraw& d = *k.d;
        ProgramCounters c;
        std::array<QuadVaryings, N> q;
        std::array<std::array<float, 4>, N> iw;
        std::array<uint32_t, N> mask{};
        std::array<int, N> qxs{}, qys{};
        std::array<QuadDepths, N> zs{};
        Group g;
        int pending = 0;
        auto runPending = [&] {
            if constexpr (kWide)
                shadeQuadPairs<N>(*k.fp, d, zs, q, iw, mask, qxs, qys, pending, c);
            else
                for (int i = 0; i < pending; ++i)
                    shadeQuadLanes(*k.fp, d, zs[size_t(i)].z, q[size_t(i)], iw[size_t(i)], mask[size_t(i)],
                                   qxs[size_t(i)], qys[size_t(i)], g.quad(i), c);
            pending = 0;
        };
        for (uint32_t ti = 0; ti < count; ++ti) {
            const ProgramTriangle& t = tris[items ? items[ti] : ti];
            // Pending quads of earlier triangles: [0, earlier). This triangle's own quads are
            // distinct and need no check.
            int earlier = pending;
            forEachCoveredQuad<kWide>(d, t, rx0, ry0, rx1, ry1, [&](int qx, int qy, uint32_t m) {
                for (int i = 0; i < earlier; ++i)
                    if (qxs[size_t(i)] == qx && qys[size_t(i)] == qy && (mask[size_t(i)] & m)) {
                        runPending();
                        earlier = 0;
                        break;
                    }
                interpolateQuad(d, t, qx, qy, q[size_t(pending)], iw[size_t(pending)]);
                quadDepths(t, qx, qy, zs[size_t(pending)].z);
                mask[size_t(pending)] = m;
                qxs[size_t(pending)] = qx;
                qys[size_t(pending)] = qy;
                if (++pending == N) {
                    shadeQuadGroup<FP, N, Group>(*k.fp, d, zs, q, iw, mask, qxs, qys, g, c);
                    pending = 0;
                    earlier = 0;
                }
            });
        }
        runPending();
        counters.add(c);
    }

    // runQuadGroups for a kLaneIndependent program: a pool of up to kFusionSlots pending
    // quads, at most one per quad position of the rectangle (slotAt). A triangle's quad
    // whose pixels are free in the pending quad at its position goes into those lanes
    // (fuseQuad); one meeting a covered pixel first runs that pending quad (with the oldest
    // others, a group's worth), so each pixel's fragments still meet the depth test and the
    // output merger in triangle order. A quad whose four pixels are covered is complete:
    // kGroupQuads complete quads run as soon as there are that many; the pool full, its
    // oldest run; at the end, the rest. The pending quads are always distinct pixels, so the
    // order in which they run changes nothing. A mesh's tiny triangles thus run as whole
    // quads, where runQuadGroups ran each triangle's part of a quad as a quad of its own.
    template <class Group>
    static void runFusedGroups(const ProgramKernel& k, const ProgramTriangle* tris, const uint32_t* items,
                               uint32_t count, int rx0, int ry0, int rx1, int ry1, ProgramCounters& counters) {
        constexpr int N = Group::kQuads;
        constexpr int P = kFusionSlots;
        constexpr bool kWide = std::is_same_v<Group, QuadGroupWideContext<kWideQuads<FP>>>;
        const ProgramDraw& d = *k.d;
        ProgramCounters c;
        const int qx0 = rx0 & ~1, qy0 = ry0 & ~1, qw = ((rx1 - qx0) >> 1) + 1;
        FusionPool<Group>& pool = FusionPool<Group>::storage();
        auto &q = pool.q, &iw = pool.iw;
        auto& zs = pool.zs;
        auto& mask = pool.mask;
        auto &qxs = pool.qxs, &qys = pool.qys;
        auto& slotAt = pool.slotAt;
        auto &order = pool.order, &freeSlots = pool.freeSlots;
        slotAt.fill(-1);
        int pending = 0, nFree = P, complete = 0;
        for (int i = 0; i < P; ++i) freeSlots[size_t(i)] = int16_t(P - 1 - i);
        auto at = [&](int qx, int qy) -> int16_t& {
            return slotAt[size_t(((qy - qy0) >> 1) * qw + ((qx - qx0) >> 1))];
        };
        // Runs the pending slots at the order positions picked (n ≤ N of them) — out of
        // line, so that the flattened kernel holds the program once — then frees them.
        auto run = [&](const int (&picked)[N], int n) {
            if constexpr (kWide)
                runPickedAvx2(k, pool, picked, n, c);
            else
                runPickedSse2(k, pool, picked, n, c);
            bool gone[P] = {};
            for (int i = 0; i < n; ++i) {
                const int sl = order[size_t(picked[i])];
                at(qxs[size_t(sl)], qys[size_t(sl)]) = -1;
                if (mask[size_t(sl)] == 15u) --complete;
                freeSlots[size_t(nFree++)] = int16_t(sl);
                gone[picked[i]] = true;
            }
            int w = 0;
            for (int i = 0; i < pending; ++i)
                if (!gone[i]) order[size_t(w++)] = order[size_t(i)];
            pending = w;
        };
        // Runs `first` (an order position, or −1) and the oldest others up to N, or, with
        // onlyComplete, the oldest N complete quads.
        auto runOldest = [&](int first, bool onlyComplete) {
            int picked[N];
            int n = 0;
            if (first >= 0) picked[n++] = first;
            for (int i = 0; i < pending && n < N; ++i) {
                if (i == first || (onlyComplete && mask[size_t(order[size_t(i)])] != 15u)) continue;
                picked[n++] = i;
            }
            run(picked, n);
        };
        for (uint32_t ti = 0; ti < count; ++ti) {
            const ProgramTriangle& t = tris[items ? items[ti] : ti];
            forEachCoveredQuad<kWide>(d, t, rx0, ry0, rx1, ry1, [&](int qx, int qy, uint32_t m) {
                int16_t sl = at(qx, qy);
                if (sl >= 0 && (mask[size_t(sl)] & m)) {  // a pixel met again: that quad first
                    int pos = 0;
                    while (order[size_t(pos)] != sl) ++pos;
                    runOldest(pos, false);
                    sl = -1;
                }
                if (sl >= 0) {
                    fuseQuad(d, t, qx, qy, m, q[size_t(sl)], iw[size_t(sl)], zs[size_t(sl)]);
                    mask[size_t(sl)] |= m;
                } else {
                    if (nFree == 0) runOldest(-1, false);
                    sl = freeSlots[size_t(--nFree)];
                    at(qx, qy) = sl;
                    order[size_t(pending++)] = sl;
                    interpolateQuad(d, t, qx, qy, q[size_t(sl)], iw[size_t(sl)]);
                    quadDepths(t, qx, qy, zs[size_t(sl)].z);
                    mask[size_t(sl)] = m;
                    qxs[size_t(sl)] = qx;
                    qys[size_t(sl)] = qy;
                }
                if (mask[size_t(sl)] == 15u && ++complete >= N) runOldest(-1, true);
            });
        }
        while (pending > 0) runOldest(-1, false);
        counters.add(c);
    }

    // runFusedGroups' pending quads and the copies of those a group runs: a thread's own
    // (about 45 KiB: not on the stack of every tile run).
    template <class Group>
    struct FusionPool {
        static constexpr int N = Group::kQuads, P = kFusionSlots;
        std::array<QuadVaryings, P> q;
        std::array<std::array<float, 4>, P> iw;
        std::array<QuadDepths, P> zs;
        std::array<uint32_t, P> mask;
        std::array<int, P> qxs, qys;
        std::array<int16_t, kFusionMap> slotAt;
        std::array<int16_t, P> order;  // the pending slots, oldest first
        std::array<int16_t, P> freeSlots;
        std::array<QuadVaryings, N> gq;
        std::array<std::array<float, 4>, N> giw;
        std::array<QuadDepths, N> gz;
        std::array<uint32_t, N> gmask;
        std::array<int, N> gx, gy;
        Group g;
        static FusionPool& storage() {
            static thread_local FusionPool pool;
            return pool;
        }
    };
    // The pending quads at the order positions picked through the program: N as a group,
    // fewer as runQuadGroups runs its last ones.
    template <class Group, int N>
    static void runPicked(const ProgramKernel& k, FusionPool<Group>& p, const int (&picked)[N], int n,
                          ProgramCounters& c) {
        const ProgramDraw& d = *k.d;
        for (int i = 0; i < n; ++i) {
            const size_t sl = size_t(p.order[size_t(picked[i])]);
            p.gq[size_t(i)] = p.q[sl];
            p.giw[size_t(i)] = p.iw[sl];
            p.gz[size_t(i)] = p.zs[sl];
            p.gmask[size_t(i)] = p.mask[sl];
            p.gx[size_t(i)] = p.qxs[sl];
            p.gy[size_t(i)] = p.qys[sl];
        }
        if (n == N) {
            shadeQuadGroup<FP, N, Group>(*k.fp, d, p.gz, p.gq, p.giw, p.gmask, p.gx, p.gy, p.g, c);
        } else if constexpr (std::is_same_v<Group, QuadGroupWideContext<kWideQuads<FP>>>) {
            shadeQuadPairs<N>(*k.fp, d, p.gz, p.gq, p.giw, p.gmask, p.gx, p.gy, n, c);
        } else {
            for (int i = 0; i < n; ++i)
                shadeQuadLanes(*k.fp, d, p.gz[size_t(i)].z, p.gq[size_t(i)], p.giw[size_t(i)], p.gmask[size_t(i)],
                               p.gx[size_t(i)], p.gy[size_t(i)], p.g.quad(i), c);
        }
    }
    // The AVX2 kernel's: flattened on its own and never inlined, so runFusedGroups' several
    // calls share one copy of the program (inlined at each, a glass program's kernel took
    // over three times as long to compile).
    template <class Group, int N>
    [[gnu::noinline, gnu::target("avx2"), RG_KERNEL_FLATTEN]] static void runPickedAvx2(
        const ProgramKernel& k, FusionPool<Group>& p, const int (&picked)[N], int n, ProgramCounters& c) {
        runPicked<Group, N>(k, p, picked, n, c);
    }
    template <class Group, int N>
    [[gnu::noinline]] static void runPickedSse2(const ProgramKernel& k, FusionPool<Group>& p, const int (&picked)[N],
                                                int n, ProgramCounters& c) {
        runPicked<Group, N>(k, p, picked, n, c);
    }

    // kLaneIndependent: the pixels `m` of triangle t's quad at (qx, qy) into a pending quad
    // at the same position whose lanes m are uncovered — their varyings, 1/w and window z
    // from t, computed as interpolateQuad and quadDepths compute them for t's own quad.
    static void fuseQuad(const ProgramDraw& d, const ProgramTriangle& t, int qx, int qy, uint32_t m,
                         QuadVaryings& q, std::array<float, 4>& iw, QuadDepths& z) {
        QuadVaryings tq;
        std::array<float, 4> tiw;
        double tz[4];
        interpolateQuad(d, t, qx, qy, tq, tiw);
        quadDepths(t, qx, qy, tz);
        for (int p = 0; p < 4; ++p) {
            if (!((m >> p) & 1u)) continue;
            for (int a = 0; a < d.varyings; ++a) q.v[size_t(a)][size_t(p)] = tq.v[size_t(a)][size_t(p)];
            if (d.points) q.v[kMaxVaryings][size_t(p)] = tq.v[kMaxVaryings][size_t(p)];
            iw[size_t(p)] = tiw[size_t(p)];
            z.z[p] = tz[p];
        }
    }

    // The AVX2 kernel's last quads of a triangle, fewer than a group: two at a time in one
    // 256-bit register (QuadGroupWideContext<2>), the partner of an odd last quad empty —
    // covered by no lane, so it runs, fetches and writes nothing. Small triangles leave
    // most of their quads here (the tir refractor's, about 30 pixels each: more than half
    // of them), and a pair takes about the time of one quad alone on SSE lanes, whose
    // search is one chain of dependent steps. Each lane computes what it computes alone,
    // and the quads are distinct pixels of one triangle: the same bytes and counts.
    template <int N>
    static void shadeQuadPairs(const FP& fp, const ProgramDraw& d, const std::array<QuadDepths, N>& zs,
                               const std::array<QuadVaryings, N>& q, const std::array<std::array<float, 4>, N>& iw,
                               const std::array<uint32_t, N>& mask, const std::array<int, N>& qxs,
                               const std::array<int, N>& qys, int pending, ProgramCounters& c) {
        if (pending == 0) return;
        QuadGroupWideContext<2> pair;
        for (int i = 0; i < pending; i += 2) {
            const size_t a = size_t(i), b = size_t(i + 1 < pending ? i + 1 : i);
            const std::array<QuadVaryings, 2> q2{q[a], q[b]};
            const std::array<std::array<float, 4>, 2> iw2{iw[a], iw[b]};
            const std::array<uint32_t, 2> m2{mask[a], i + 1 < pending ? mask[b] : 0u};
            const std::array<int, 2> x2{qxs[a], qxs[b]}, y2{qys[a], qys[b]};
            const std::array<QuadDepths, 2> z2{zs[a], zs[b]};
            shadeQuadGroup<FP, 2, QuadGroupWideContext<2>>(fp, d, z2, q2, iw2, m2, x2, y2, pair, c);
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
// The fast path's: triangles items[0 .. count) of tris (tris[0 .. count) without items)
// inside the inclusive rectangle, in that order (ProgramKernel::runTriangles).
using TrianglesKernelFn = void (*)(void* self, const ProgramTriangle* tris, const uint32_t* items, uint32_t count,
                                   int rx0, int ry0, int rx1, int ry1, ProgramCounters& c);

// One vertex after the vertex program.
struct ProgramVertex {
    glm::vec4 clip{0.0f};
    Varyings varyings{};
};

// A draw's vertex stage with its types erased, so that the device can run it now or, in a
// batch, later and on another thread: the vertex program over vertices [b, e).
using VertexStageFn = void (*)(const void* self, size_t b, size_t e, ProgramVertex* out, VertexContext* fetch);

template <class VP, class V>
struct VertexStage {
    static constexpr bool kFetches = requires(const VP& p, const V& v, Varyings& o, VertexContext& t) { p(v, o, t); };
    const VP* vp;
    const V* vertices;
    static void run(const void* self, size_t b, size_t e, ProgramVertex* out, VertexContext* fetch) {
        const auto& s = *static_cast<const VertexStage*>(self);
        for (size_t i = b; i < e; ++i) {
            if constexpr (kFetches)
                out[i].clip = (*s.vp)(s.vertices[i], out[i].varyings, *fetch);
            else
                out[i].clip = (*s.vp)(s.vertices[i], out[i].varyings);
        }
    }
};

// A batched draw's own copies of its programs (the caller's may be gone by endBatch), with
// the vertex stage and the kernel pointing at them.
struct HeldPrograms {
    virtual ~HeldPrograms() = default;
};
template <class VP, class FP, class V>
struct HeldProgramsOf final : HeldPrograms {
    VP vp;
    FP fp;
    VertexStage<VP, V> stage;
    ProgramKernel<FP> kernel;
    HeldProgramsOf(const VP& v, const FP& f, const V* vertices, const ProgramDraw* d)
        : vp(v), fp(f), stage{&vp, vertices}, kernel{&fp, d} {}
};

// The key a draw's (vertex program, fragment program, vertex) types are registered under
// (program_registry.h) and recorded by.
template <class VP, class FP, class V>
struct ProgramTriple {};

// What a trace records of a program object: its bytes, none for an empty type (whose one
// byte is indeterminate).
template <class T>
std::span<const uint8_t> recordedBytes(const T& object) {
    if constexpr (std::is_empty_v<T>)
        return {};
    else
        return {reinterpret_cast<const uint8_t*>(&object), sizeof(T)};
}

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

    // ---- the state as set (what a trace recorder reads at each command) --------------------
    std::span<const ColorTarget> colorTargets() const;
    const DepthTarget& depthTarget() const;
    const Viewport& viewport() const;
    const Rect* scissor() const;  // nullptr: off
    const std::shared_ptr<const tex::Texture>& texture(int unit) const;
    const tex::SamplerState& sampler(int unit) const;

    // ---- capture ----------------------------------------------------------------------------
    // Attaches a trace recorder (rasterizer/trace.h, docs/trace-format.md version 2): it
    // writes the ProgrammableDevice record now and is fed at every command from then on.
    // Drawing with a program that is not registered (program_registry.h) is then an
    // error naming its types. nullptr (or another recorder) detaches the current one,
    // which writes the final hash of every render target the trace used; so does the
    // device's destruction.
    void setRecorder(std::shared_ptr<TraceRecorder> recorder);

    // ---- frames and commands --------------------------------------------------------------
    void beginFrame();
    void clearColor(int target, const glm::vec4& value);  // inside viewport ∩ scissor
    void clearDepth(float value);
    const ProgramCounters& counters() const;

    // ---- batches -----------------------------------------------------------------------------
    // Between beginBatch() and endBatch() draws are checked and recorded as they are issued
    // but not run: endBatch runs the vertex stage, clip and setup of every queued draw (the
    // draws shared over the threads), bins all their triangles into the tiles and shades
    // each tile's triangles in the order the draws were issued, with one fork and join for
    // the whole batch instead of one per draw (llvmpipe defers a frame's draws to its
    // scene the same way). The pixels and counters are those of drawing one by one: a
    // pixel's fragments still meet the output merger in primitive order (tests/programmable,
    // ProgrammableBatch). A batched draw keeps copies of its programs, of the state and of
    // the texture bindings; the caller keeps each draw's vertices and indices, and the
    // contents of every texture a draw reads, unchanged until endBatch, and reads the
    // targets only after it. Inside a batch, changing the targets, clearing, attaching a
    // recorder, beginFrame, setPath, setThreads and a second beginBatch are errors
    // (InvalidState). The destructor runs a batch left open.
    void beginBatch();
    void endBatch();
    bool batching() const { return batching_; }

    template <class VP, class FP, class V>
    void draw(const VP& vp, const FP& fp, ProgramPrimitive primitive, std::span<const V> vertices,
              std::span<const uint32_t> indices = {}) {
        static_assert(VP::kVaryings == FP::kVaryings, "vertex and fragment programs disagree on kVaryings");
        static_assert(FP::kVaryings >= 0 && FP::kVaryings <= kMaxVaryings, "too many varyings");
        constexpr uint32_t kVertexUnits = detail::vertexUnitsOf<VP>();
        static_assert(detail::VertexStage<VP, V>::kFetches == (kVertexUnits != 0),
                      "a vertex program that takes a VertexContext declares kVertexUnits, and one that "
                      "declares kVertexUnits takes a VertexContext");
        detail::ProgramDraw& d = beginDraw(FP::kVaryings, FP::kTargets, FP::kUnits, primitive,
                                           vertices.size(), indices, kVertexUnits);
        if (recorder_)  // after the draw's checks, before any pixel changes
            recordDraw(typeid(detail::ProgramTriple<VP, FP, V>), detail::recordedBytes(vp),
                       detail::recordedBytes(fp), FP::kUnits | kVertexUnits, primitive,
                       {reinterpret_cast<const uint8_t*>(vertices.data()), vertices.size_bytes()},
                       uint32_t(sizeof(V)), indices);
        const DrawPrograms programs{&detail::VertexStage<VP, V>::run, &detail::ProgramKernel<FP>::runTriangles,
                                    &detail::ProgramKernel<FP>::runPixels};
        if (batching_) {
            auto held = std::make_unique<detail::HeldProgramsOf<VP, FP, V>>(vp, fp, vertices.data(), &d);
            const void* stage = &held->stage;
            void* kernel = &held->kernel;
            submitDraw(programs, stage, kernel, std::move(held));
        } else {
            const detail::VertexStage<VP, V> stage{&vp, vertices.data()};
            detail::ProgramKernel<FP> kernel{&fp, &d};
            submitDraw(programs, &stage, &kernel, nullptr);
        }
    }

  private:
    struct DrawPrograms {
        detail::VertexStageFn vertices;
        detail::TrianglesKernelFn fast;
        detail::TriangleKernelFn reference;
    };
    // Checks a draw against the state and fills the draw being issued (in a batch, the next
    // queued one, with its own copy of the bindings); returns its ProgramDraw.
    detail::ProgramDraw& beginDraw(int varyings, uint32_t targets, uint32_t units,
                                   ProgramPrimitive primitive, size_t vertexCount,
                                   std::span<const uint32_t> indices, uint32_t vertexUnits = 0);
    // Runs the draw begun by beginDraw now, or queues it in a batch (`held` owns the
    // programs `stage` and `kernel` point into).
    void submitDraw(const DrawPrograms& programs, const void* stage, void* kernel,
                    std::unique_ptr<detail::HeldPrograms> held);
    void requireNoBatch(const char* what) const;
    void recordDraw(std::type_index program, std::span<const uint8_t> vertexProgram,
                    std::span<const uint8_t> fragmentProgram, uint32_t units, ProgramPrimitive primitive,
                    std::span<const uint8_t> vertices, uint32_t stride, std::span<const uint32_t> indices);

    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::shared_ptr<TraceRecorder> recorder_;  // here, not in Impl: draw() tests it inline
    bool batching_ = false;                    // the same
};

// A batch for a scope: beginBatch at construction, end() runs it. The destructor runs a
// batch end() did not (the scope left by an exception: the draws issued are not lost) and
// drops any error from it, as the device's destructor does.
class ProgramBatch {
  public:
    explicit ProgramBatch(ProgrammableDevice& device) : device_(device) { device_.beginBatch(); }
    ~ProgramBatch() {
        if (device_.batching()) {
            try {
                device_.endBatch();
            } catch (const std::exception&) {
            }
        }
    }
    ProgramBatch(const ProgramBatch&) = delete;
    ProgramBatch& operator=(const ProgramBatch&) = delete;
    void end() { device_.endBatch(); }

  private:
    ProgrammableDevice& device_;
};

}  // namespace rg::raster
