// One 2×2 quad of one triangle through the rest of the pipeline: interpolation, the
// texture stages, specular add, alpha test, depth test, blend and colour write mask.
//
// Shared by both paths. The template flags let the fast path compile the per-state
// branches away; with kSpecialized = false every decision is read from the state at run
// time (the reference path). The fast path evaluates the four colour channels of a pixel
// with SSE2: _mm_add_ps/_mm_mul_ps/_mm_max_ps/_mm_min_ps/_mm_cvttps_epi32 are the same
// IEEE single operations, in the same order, as the scalar Plane::at and colorToByte, so
// the bytes cannot differ (and tests/rasterizer/test_paths_agree.cpp checks that they
// don't).
//
//      quad layout (FragmentQuad):   +---+---+
//                                    | 0 | 1 |   pixel i at (x + (i & 1), y + (i >> 1))
//                                    +---+---+
//                                    | 2 | 3 |
//                                    +---+---+
#pragma once

#include <xmmintrin.h>
#include <emmintrin.h>

#include <cstring>
#include <optional>

#include "pipeline.h"
#include "rasterizer/fragment_ops.h"

namespace rg::raster::detail {

// Four channels of one pixel: plane evaluation, optional ·r, then colorToByte per lane.
inline Rgba8 colorPlanesToBytesSse(const float* c, const float* dx, const float* dy, float fx,
                                   float fy, bool perspective, float r) {
    __m128 v = _mm_add_ps(_mm_add_ps(_mm_load_ps(c), _mm_mul_ps(_mm_load_ps(dx), _mm_set1_ps(fx))),
                          _mm_mul_ps(_mm_load_ps(dy), _mm_set1_ps(fy)));
    if (perspective) v = _mm_mul_ps(v, _mm_set1_ps(r));
    v = _mm_max_ps(v, _mm_setzero_ps());     // v > 0 ? v : 0 (NaN → 0)
    v = _mm_min_ps(v, _mm_set1_ps(255.0f));  // v < 255 ? v : 255
    __m128i i = _mm_cvttps_epi32(_mm_add_ps(v, _mm_set1_ps(0.5f)));
    i = _mm_packs_epi32(i, i);
    i = _mm_packus_epi16(i, i);
    uint32_t bits = uint32_t(_mm_cvtsi128_si32(i));
    Rgba8 out;
    std::memcpy(static_cast<void*>(&out), &bits, 4);
    return out;
}

// Blending with the factors as compile-time constants for the common modes, so the
// factor switches fold away; every branch calls the one blendPixel definition.
inline Rgba8 blendFast(const PipelineState& st, Rgba8 s, Rgba8 d) {
    if (st.blendOp == BlendOp::Add) {
        if (st.srcBlend == BlendFactor::SrcAlpha && st.dstBlend == BlendFactor::InvSrcAlpha)
            return blendPixel(BlendFactor::SrcAlpha, BlendFactor::InvSrcAlpha, BlendOp::Add, s, d);
        if (st.srcBlend == BlendFactor::One && st.dstBlend == BlendFactor::One)
            return blendPixel(BlendFactor::One, BlendFactor::One, BlendOp::Add, s, d);
        if (st.srcBlend == BlendFactor::DestColor && st.dstBlend == BlendFactor::Zero)
            return blendPixel(BlendFactor::DestColor, BlendFactor::Zero, BlendOp::Add, s, d);
        if (st.srcBlend == BlendFactor::Zero && st.dstBlend == BlendFactor::SrcColor)
            return blendPixel(BlendFactor::Zero, BlendFactor::SrcColor, BlendOp::Add, s, d);
        if (st.srcBlend == BlendFactor::One && st.dstBlend == BlendFactor::InvSrcAlpha)
            return blendPixel(BlendFactor::One, BlendFactor::InvSrcAlpha, BlendOp::Add, s, d);
        if (st.srcBlend == BlendFactor::SrcAlpha && st.dstBlend == BlendFactor::One)
            return blendPixel(BlendFactor::SrcAlpha, BlendFactor::One, BlendOp::Add, s, d);
    }
    return blendPixel(st.srcBlend, st.dstBlend, st.blendOp, s, d);
}

// `scratch`, when given, is a FragmentQuad the caller reuses for all quads of one triangle
// (every quad writes the same coordinate sets, the others stay zero), which saves zeroing
// its 600 bytes per quad; null: a fresh one.
template <bool kSpecialized, bool kDepth, bool kBlend, bool kPassThrough>
inline void processQuad(const DrawContext& dc, const SetupTriangle& t, const Plane* texPool,
                        int qx, int qy, unsigned coverage, RasterCounters& rc,
                        tex::FragmentQuad* scratch = nullptr) {
    const bool depthOn = kSpecialized ? kDepth : dc.depthOn;
    const bool blendOn = kSpecialized ? kBlend : dc.st.blend != 0;
    const bool passThrough = kSpecialized ? kPassThrough : dc.passThrough;
    const PipelineState& st = dc.st;
    const bool observed = !kSpecialized && dc.fragmentObserver != nullptr;

    // Helper pixels (coverage bit clear) are only interpolated when a texture stage needs
    // their derivatives; their values never reach the framebuffer.
    const unsigned evalMask = (passThrough && !observed) ? coverage : 0xFu;

    // ---- interpolation (docs/hardware.md, "Interpolation") -----------------------------
    float fx[4], fy[4], r[4] = {1, 1, 1, 1};
    for (int i = 0; i < 4; ++i) {
        fx[i] = (float(qx + (i & 1)) + 0.5f) - t.x0;
        fy[i] = (float(qy + (i >> 1)) + 0.5f) - t.y0;
    }
    const bool needR = (dc.gouraud && dc.perspectiveColor) || dc.numTexSets > 0;
    if (needR) {
        if (kSpecialized && evalMask == 0xFu) {  // the same four divisions, in one register
            const __m128 fx4 = _mm_loadu_ps(fx), fy4 = _mm_loadu_ps(fy);
            const __m128 w = _mm_add_ps(
                _mm_add_ps(_mm_set1_ps(t.invW.c), _mm_mul_ps(_mm_set1_ps(t.invW.dx), fx4)),
                _mm_mul_ps(_mm_set1_ps(t.invW.dy), fy4));
            _mm_storeu_ps(r, _mm_div_ps(_mm_set1_ps(1.0f), w));
        } else {
            for (int i = 0; i < 4; ++i)
                if (evalMask & (1u << i)) r[i] = 1.0f / t.invW.at(fx[i], fy[i]);
        }
    }

    std::array<Rgba8, 4> diffuse, specular;
    if (!dc.gouraud) {
        diffuse.fill(t.flatDiffuse);
        specular.fill(t.flatSpecular);
    } else if constexpr (kSpecialized) {
        for (int i = 0; i < 4; ++i) {
            if (!(evalMask & (1u << i))) continue;
            diffuse[i] = colorPlanesToBytesSse(&t.colorC[0], &t.colorDx[0], &t.colorDy[0], fx[i],
                                               fy[i], dc.perspectiveColor, r[i]);
            if (dc.needSpecular)
                specular[i] = colorPlanesToBytesSse(&t.colorC[4], &t.colorDx[4], &t.colorDy[4],
                                                    fx[i], fy[i], dc.perspectiveColor, r[i]);
        }
    } else {
        const int colors = dc.needSpecular ? 8 : 4;
        for (int i = 0; i < 4; ++i) {
            if (!(evalMask & (1u << i))) continue;
            uint8_t c[8] = {0, 0, 0, 0, 0, 0, 0, 0};
            for (int a = 0; a < colors; ++a) {
                float v = t.color(a).at(fx[i], fy[i]);
                if (dc.perspectiveColor) v = v * r[i];
                c[a] = colorToByte(v);
            }
            diffuse[i] = Rgba8{c[0], c[1], c[2], c[3]};
            specular[i] = Rgba8{c[4], c[5], c[6], c[7]};
        }
    }

    // ---- texture stages (texunit/) ------------------------------------------------------
    std::array<Rgba8, 4> color;
    std::optional<tex::FragmentQuad> own;
    tex::FragmentQuad* qp = scratch;
    if (!(passThrough && !observed) && !qp) qp = &own.emplace();
    if (passThrough && !observed) {
        color = diffuse;
    } else {
        tex::FragmentQuad& q = *qp;
        q.x = qx;
        q.y = qy;
        q.coverage = uint8_t(coverage);
        q.diffuse = diffuse;
        q.specular = specular;
        const Plane* tp = texPool + t.texPlanes;
        if constexpr (kSpecialized) {
            // One component of the four pixels per register, then a 4×4 transpose into
            // the per-pixel (s, t, r, q): the operations of Plane::at and ·r, lane-wise.
            const __m128 fx4 = _mm_loadu_ps(fx), fy4 = _mm_loadu_ps(fy), r4 = _mm_loadu_ps(r);
            for (int k = 0; k < dc.numTexSets; ++k) {
                __m128 v[4];
                for (int c = 0; c < 4; ++c) {
                    const Plane& p = tp[4 * k + c];
                    v[c] = _mm_mul_ps(
                        _mm_add_ps(_mm_add_ps(_mm_set1_ps(p.c), _mm_mul_ps(_mm_set1_ps(p.dx), fx4)),
                                   _mm_mul_ps(_mm_set1_ps(p.dy), fy4)),
                        r4);
                }
                _MM_TRANSPOSE4_PS(v[0], v[1], v[2], v[3]);
                for (int i = 0; i < 4; ++i) _mm_storeu_ps(&q.texCoord[dc.texSets[k]][i][0], v[i]);
            }
        } else {
            for (int k = 0; k < dc.numTexSets; ++k)
                for (int i = 0; i < 4; ++i)
                    for (int c = 0; c < 4; ++c)
                        q.texCoord[dc.texSets[k]][i][c] = tp[4 * k + c].at(fx[i], fy[i]) * r[i];
        }
        if (passThrough)
            color = diffuse;
        else
            dc.tu->shadeQuad(q, color, dc.path);
    }

    // ---- per-fragment operations --------------------------------------------------------
    Framebuffer& fb = *dc.fb;
    const int width = fb.width();
    unsigned written = 0;
    for (int i = 0; i < 4; ++i) {
        if (!(coverage & (1u << i))) continue;
        const int px = qx + (i & 1), py = qy + (i >> 1);
        ++rc.generated;
        Rgba8 c = color[i];
        if (st.specularEnable) c = addSpecular(c, specular[i]);
        if (st.alphaTest && !comparePasses(st.alphaFunc, c.a, st.alphaRef)) continue;
        const size_t idx = size_t(py) * size_t(width) + size_t(px);
        if (depthOn) {
            double z = (t.zc + t.zdx * ((double(px) + 0.5) - double(t.x0))) +
                       t.zdy * ((double(py) + 0.5) - double(t.y0));
            uint32_t zq = quantizeDepth(z, dc.depthMax);
            uint32_t& stored = fb.depth()[idx];
            if (!comparePasses(st.depthFunc, zq, stored)) continue;
            if (st.depthWrite) stored = zq;
        }
        ++rc.written;
        written |= 1u << i;
        Rgba8& dst = fb.color()[idx];
        if (blendOn) {
            if constexpr (kSpecialized)
                c = blendFast(st, c, dst);
            else
                c = blendPixel(st.srcBlend, st.dstBlend, st.blendOp, c, dst);
            ++rc.blendOps;
        }
        dst = applyWriteMask(st.colorWriteMask, c, dst);
    }
    if (observed) (*dc.fragmentObserver)(*qp, uint8_t(written));
}

}  // namespace rg::raster::detail
