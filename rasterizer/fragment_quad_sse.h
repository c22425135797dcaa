// The SSE2 twin of processQuad() (fragment_quad.h) for pass-through quads (no texture
// stage) that lie wholly inside the target: the fast path's inner loop.
//
// Same arithmetic, four pixels at a time:
//   - colours: the four pixels of one channel per __m128, (c + dx·fx) + dy·fy, ·r, clamp,
//     +½, truncate — the IEEE single operations of Plane::at and colorToByte, lane-wise;
//   - blending: two pixels (8 channels) per register in 16-bit lanes. mulDiv255's
//     t = a·b + 128 ≤ 65,153 and t + (t >> 8) ≤ 65,407 fit an unsigned 16-bit lane, so
//     _mm_mullo_epi16/_mm_srli_epi16 compute exactly arith8::mulDiv255; addSat is
//     min(a + b, 255), subSat is _mm_subs_epu16;
//   - alpha and depth tests stay scalar (the same functions as the reference).
// The randomized differential test covers every factor, operation and mask.
#pragma once

#include <emmintrin.h>

#include <cmath>

#include "fragment_quad.h"

namespace rg::raster::detail {

namespace sse {

// The bytes of an RGBA8 pixel the colour write mask lets through (0xFF per enabled
// channel), for selecting between the new and the stored pixel.
inline uint32_t writeMaskBytes(uint8_t mask) {
    return (mask & kWriteR ? 0x000000FFu : 0u) | (mask & kWriteG ? 0x0000FF00u : 0u) |
           (mask & kWriteB ? 0x00FF0000u : 0u) | (mask & kWriteA ? 0xFF000000u : 0u);
}

[[gnu::always_inline]] inline __m128i broadcastAlpha(__m128i x) {  // 16-bit lanes: (r g b a)(r g b a) → (a a a a)(a a a a)
    return _mm_shufflehi_epi16(_mm_shufflelo_epi16(x, 0xFF), 0xFF);
}

[[gnu::always_inline]] inline __m128i mulDiv255(__m128i a, __m128i b) {
    __m128i t = _mm_add_epi16(_mm_mullo_epi16(a, b), _mm_set1_epi16(128));
    return _mm_srli_epi16(_mm_add_epi16(t, _mm_srli_epi16(t, 8)), 8);
}

// blendFactorValue() for two pixels in 16-bit lanes.
[[gnu::always_inline]] inline __m128i factor(BlendFactor f, __m128i s, __m128i d) {
    const __m128i k255 = _mm_set1_epi16(255);
    switch (f) {
        case BlendFactor::Zero: return _mm_setzero_si128();
        case BlendFactor::One: return k255;
        case BlendFactor::SrcColor: return s;
        case BlendFactor::InvSrcColor: return _mm_sub_epi16(k255, s);
        case BlendFactor::SrcAlpha:
        case BlendFactor::BothSrcAlpha: return broadcastAlpha(s);
        case BlendFactor::InvSrcAlpha:
        case BlendFactor::BothInvSrcAlpha: return _mm_sub_epi16(k255, broadcastAlpha(s));
        case BlendFactor::DestAlpha: return broadcastAlpha(d);
        case BlendFactor::InvDestAlpha: return _mm_sub_epi16(k255, broadcastAlpha(d));
        case BlendFactor::DestColor: return d;
        case BlendFactor::InvDestColor: return _mm_sub_epi16(k255, d);
        case BlendFactor::SrcAlphaSat: {
            __m128i f3 = _mm_min_epi16(broadcastAlpha(s), _mm_sub_epi16(k255, broadcastAlpha(d)));
            const __m128i alphaLanes = _mm_set_epi16(-1, 0, 0, 0, -1, 0, 0, 0);
            return _mm_or_si128(_mm_andnot_si128(alphaLanes, f3), _mm_and_si128(alphaLanes, k255));
        }
    }
    return _mm_setzero_si128();
}

// blendPixel() for two pixels in 16-bit lanes. (srcF, dstF, op) are compile-time
// constants for the common modes (the switches fold away) and run-time values otherwise.
[[gnu::always_inline]] inline __m128i blend2(BlendFactor srcF, BlendFactor dstF, BlendOp op, __m128i s, __m128i d) {
    switch (op) {
        case BlendOp::Min: return _mm_min_epi16(s, d);
        case BlendOp::Max: return _mm_max_epi16(s, d);
        default: break;
    }
    const BlendFactor df = effectiveDestFactor(srcF, dstF);
    __m128i sp = mulDiv255(s, factor(srcF, s, d));
    __m128i dp = mulDiv255(d, factor(df, s, d));
    switch (op) {
        case BlendOp::Add: return _mm_min_epi16(_mm_add_epi16(sp, dp), _mm_set1_epi16(255));
        case BlendOp::Subtract: return _mm_subs_epu16(sp, dp);
        case BlendOp::RevSubtract: return _mm_subs_epu16(dp, sp);
        default: return sp;
    }
}

// Four channel vectors (pixels in lanes) → 16 bytes, pixel-major RGBA.
[[gnu::always_inline]] inline __m128i toPixels(__m128i r, __m128i g, __m128i b, __m128i a) {
    __m128i x = _mm_packus_epi16(_mm_packs_epi32(r, b), _mm_packs_epi32(g, a));
    // x = R0..R3 B0..B3 G0..G3 A0..A3
    __m128i lo = _mm_unpacklo_epi8(x, _mm_srli_si128(x, 8));     // R0 G0 R1 G1 … B0 A0 B1 A1 …
    return _mm_unpacklo_epi16(lo, _mm_srli_si128(lo, 8));        // R0 G0 B0 A0 R1 G1 B1 A1 …
}

[[gnu::always_inline]] inline __m128i channelToInt(__m128 v) {
    v = _mm_max_ps(v, _mm_setzero_ps());
    v = _mm_min_ps(v, _mm_set1_ps(255.0f));
    return _mm_cvttps_epi32(_mm_add_ps(v, _mm_set1_ps(0.5f)));
}

// Plane coefficients of one triangle broadcast once (per triangle, not per quad).
struct Planes {
    __m128 c[8], dx[8], dy[8];
    __m128 wc, wdx, wdy;
    // 1/w without slope (orthographic projections, equal RHW): the per-pixel 1.0f/w is
    // the same value for every pixel, so it is computed once; when it is exactly 1 the
    // ·r is the identity and is skipped. Both are exact, not approximations.
    bool flatW = false, unitW = false;
    __m128 flatR = _mm_set1_ps(1.0f);
    int count = 0;
    void load(const SetupTriangle& t, int n) {
        count = n;
        for (int a = 0; a < n; ++a) {
            c[a] = _mm_set1_ps(t.colorC[a]);
            dx[a] = _mm_set1_ps(t.colorDx[a]);
            dy[a] = _mm_set1_ps(t.colorDy[a]);
        }
        wc = _mm_set1_ps(t.invW.c);
        wdx = _mm_set1_ps(t.invW.dx);
        wdy = _mm_set1_ps(t.invW.dy);
        flatW = t.invW.dx == 0.0f && t.invW.dy == 0.0f && std::isfinite(t.invW.c) &&
                t.invW.c != 0.0f;
        if (flatW) {
            const float r = t.invW.c == 1.0f ? 1.0f : 1.0f / t.invW.c;  // 1/1 is exactly 1
            unitW = r == 1.0f;
            flatR = _mm_set1_ps(r);
        }
    }
};

// Per pair of rows: dy·fy of every plane (the same for every quad of the row pair, so
// computing it once is the same IEEE product).
struct RowTerms {
    __m128 fy;
    __m128 dyfy[8];
    __m128 wdyfy;
    void load(const Planes& p, const SetupTriangle& t, int qy) {
        fy = _mm_sub_ps(_mm_setr_ps(float(qy) + 0.5f, float(qy) + 0.5f, float(qy + 1) + 0.5f,
                                    float(qy + 1) + 0.5f),
                        _mm_set1_ps(t.y0));
        for (int a = 0; a < p.count; ++a) dyfy[a] = _mm_mul_ps(p.dy[a], fy);
        wdyfy = _mm_mul_ps(p.wdy, fy);
    }
};

// Interpolated colour of planes [first, first + 4) for the four pixels of the quad:
// (c + dx·fx) + dy·fy, ·r when perspective-correct.
[[gnu::always_inline]] inline __m128i colors(const Planes& p, const RowTerms& row, int first, __m128 fx,
                      bool perspective, __m128 r) {
    __m128i ch[4];
    for (int a = 0; a < 4; ++a) {
        const int k = first + a;
        __m128 v = _mm_add_ps(_mm_add_ps(p.c[k], _mm_mul_ps(p.dx[k], fx)), row.dyfy[k]);
        if (perspective) v = _mm_mul_ps(v, r);
        ch[a] = channelToInt(v);
    }
    return toPixels(ch[0], ch[1], ch[2], ch[3]);
}

constexpr uint8_t kPopcount4[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

// Per coverage mask: all ones in the 32-bit lanes of the covered pixels (bit i: lane i).
alignas(16) constexpr uint32_t kPixelMask[16][4] = {
    {0, 0, 0, 0}, {~0u, 0, 0, 0}, {0, ~0u, 0, 0}, {~0u, ~0u, 0, 0},
    {0, 0, ~0u, 0}, {~0u, 0, ~0u, 0}, {0, ~0u, ~0u, 0}, {~0u, ~0u, ~0u, 0},
    {0, 0, 0, ~0u}, {~0u, 0, 0, ~0u}, {0, ~0u, 0, ~0u}, {~0u, ~0u, 0, ~0u},
    {0, 0, ~0u, ~0u}, {~0u, 0, ~0u, ~0u}, {0, ~0u, ~0u, ~0u}, {~0u, ~0u, ~0u, ~0u}};

}  // namespace sse

// Blend modes the fast path compiles with constant factors; kBlendGeneric reads the state.
enum BlendMode { kBlendNone, kBlendGeneric, kBlendSrcAlphaInvSrcAlpha, kBlendOneOne };

template <bool kDepth, int kBlendMode>
[[gnu::always_inline]] inline void quadOutputSse(const DrawContext& dc, const SetupTriangle& t,
                                                 int qx, int qy, unsigned coverage, __m128i src,
                                                 RasterCounters& rc);

template <bool kDepth, int kBlendMode>
[[gnu::always_inline]] inline void processQuadSse(const DrawContext& dc, const SetupTriangle& t, const sse::Planes& planes,
                           const sse::RowTerms& row, int qx, int qy, unsigned coverage,
                           RasterCounters& rc) {
    const PipelineState& st = dc.st;

    // ---- interpolation -----------------------------------------------------------------
    __m128i src;
    const __m128 fx = _mm_sub_ps(_mm_setr_ps(float(qx) + 0.5f, float(qx + 1) + 0.5f,
                                             float(qx) + 0.5f, float(qx + 1) + 0.5f),
                                 _mm_set1_ps(t.x0));
    __m128 r = _mm_set1_ps(1.0f);
    const bool perspective = dc.perspectiveColor && !planes.unitW;
    if (dc.gouraud) {
        if (perspective) {
            if (planes.flatW) {
                r = planes.flatR;
            } else {
                __m128 w = _mm_add_ps(_mm_add_ps(planes.wc, _mm_mul_ps(planes.wdx, fx)), row.wdyfy);
                r = _mm_div_ps(_mm_set1_ps(1.0f), w);
            }
        }
        src = sse::colors(planes, row, 0, fx, perspective, r);
    } else {
        uint32_t bits;
        std::memcpy(&bits, &t.flatDiffuse, 4);
        src = _mm_set1_epi32(int(bits));
    }
    if (st.specularEnable) {
        __m128i spec;
        if (dc.gouraud) {
            spec = sse::colors(planes, row, 4, fx, perspective, r);
        } else {
            uint32_t bits;
            std::memcpy(&bits, &t.flatSpecular, 4);
            spec = _mm_set1_epi32(int(bits));
        }
        // addSpecular: rgb saturate-add, alpha untouched.
        src = _mm_adds_epu8(src, _mm_and_si128(spec, _mm_set1_epi32(0x00FFFFFF)));
    }

    quadOutputSse<kDepth, kBlendMode>(dc, t, qx, qy, coverage, src, rc);
}

// The second half of processQuadSse: alpha and depth tests, blend, write mask and store of
// the quad's four source pixels `src` (pixel-major RGBA, specular already added).
template <bool kDepth, int kBlendMode>
[[gnu::always_inline]] inline void quadOutputSse(const DrawContext& dc, const SetupTriangle& t,
                                                 int qx, int qy, unsigned coverage, __m128i src,
                                                 RasterCounters& rc) {
    const PipelineState& st = dc.st;
    // ---- alpha and depth tests (scalar, as in processQuad) ------------------------------
    Framebuffer& fb = *dc.fb;
    const size_t width = size_t(fb.width());
    const size_t row0 = size_t(qy) * width + size_t(qx), row1 = row0 + width;
    unsigned passed = coverage;
    if (!kDepth && !st.alphaTest) {
        rc.generated += sse::kPopcount4[coverage];
    } else {
        alignas(16) uint8_t bytes[16];
        _mm_store_si128(reinterpret_cast<__m128i*>(bytes), src);
        passed = 0;
        for (int i = 0; i < 4; ++i) {
            if (!(coverage & (1u << i))) continue;
            ++rc.generated;
            if (st.alphaTest && !comparePasses(st.alphaFunc, bytes[4 * i + 3], st.alphaRef)) continue;
            if constexpr (kDepth) {
                const int px = qx + (i & 1), py = qy + (i >> 1);
                const size_t idx = (i >> 1) ? row1 + (i & 1) : row0 + (i & 1);
                double z = (t.zc + t.zdx * ((double(px) + 0.5) - double(t.x0))) +
                           t.zdy * ((double(py) + 0.5) - double(t.y0));
                uint32_t zq = quantizeDepth(z, dc.depthMax);
                uint32_t& stored = fb.depth()[idx];
                if (!comparePasses(st.depthFunc, zq, stored)) continue;
                if (st.depthWrite) stored = zq;
            }
            passed |= 1u << i;
        }
    }
    if (!passed) return;
    const int n = sse::kPopcount4[passed];
    rc.written += uint64_t(n);

    // ---- blend, write mask, store -------------------------------------------------------
    Rgba8* color = fb.color().data();
    __m128i dst = _mm_unpacklo_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(color + row0)),
                                     _mm_loadl_epi64(reinterpret_cast<const __m128i*>(color + row1)));
    __m128i out = src;
    if constexpr (kBlendMode != kBlendNone) {
        const __m128i zero = _mm_setzero_si128();
        BlendFactor sf = st.srcBlend, df = st.dstBlend;
        BlendOp op = st.blendOp;
        if constexpr (kBlendMode == kBlendSrcAlphaInvSrcAlpha) {
            sf = BlendFactor::SrcAlpha, df = BlendFactor::InvSrcAlpha, op = BlendOp::Add;
        } else if constexpr (kBlendMode == kBlendOneOne) {
            sf = BlendFactor::One, df = BlendFactor::One, op = BlendOp::Add;
        }
        __m128i lo = sse::blend2(sf, df, op, _mm_unpacklo_epi8(src, zero), _mm_unpacklo_epi8(dst, zero));
        __m128i hi = sse::blend2(sf, df, op, _mm_unpackhi_epi8(src, zero), _mm_unpackhi_epi8(dst, zero));
        out = _mm_packus_epi16(lo, hi);
        rc.blendOps += uint64_t(n);
    }
    if (passed == 0xFu && st.colorWriteMask == kWriteRGBA) {  // the common whole quad
        _mm_storel_epi64(reinterpret_cast<__m128i*>(color + row0), out);
        _mm_storel_epi64(reinterpret_cast<__m128i*>(color + row1), _mm_srli_si128(out, 8));
        return;
    }
    // The bytes to write: the passed pixels (a table load instead of four selects; a
    // mesh of tiny triangles takes this path for nearly every quad), their enabled channels.
    __m128i m = _mm_load_si128(reinterpret_cast<const __m128i*>(sse::kPixelMask[passed]));
    if (st.colorWriteMask != kWriteRGBA) {
        m = _mm_and_si128(m, _mm_set1_epi32(int(sse::writeMaskBytes(st.colorWriteMask))));
    }
    out = _mm_or_si128(_mm_and_si128(m, out), _mm_andnot_si128(m, dst));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(color + row0), out);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(color + row1), _mm_srli_si128(out, 8));
}

}  // namespace rg::raster::detail
