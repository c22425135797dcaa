// The fast path's kernel for quads with texture stages that lie wholly inside the target:
// processQuad<true, ...> (fragment_quad.h) with its per-pixel steps done four pixels at a
// time, and the fragment operations of processQuadSse (quadOutputSse).
//
// Same arithmetic as processQuad, lane for lane:
//   - 1/w: (c + dx·fx) + dy·fy, then 1/w in one divps — processQuad's own SSE form;
//   - colours: the four pixels of one channel per register (sse::colors), the IEEE
//     operations of colorPlanesToBytesSse; dy·fy is the same product whether computed per
//     quad or once per row pair (RowTerms);
//   - texture coordinates: per component ((c + dx·fx) + dy·fy)·r, transposed into the
//     FragmentQuad's per-pixel (s, t, r, q), as processQuad's kSpecialized branch;
//   - the stage cascade: TextureUnits::shadeQuad on the fast path, as processQuad calls it;
//   - specular add, alpha and depth tests, blend, write mask: processQuadSse's.
// Helper pixels are interpolated like covered ones (all four lanes), as processQuad does
// for a quad with texture stages. Compared with the reference under random textured states
// by PathsAgree.TexturedQuadsOnRandomStagesAndSamplers (tests/rasterizer).
#pragma once

#include <emmintrin.h>

#include <cstring>

#include "fragment_quad_sse.h"

namespace rg::raster::detail {

namespace sse {

// The texture-coordinate planes of one triangle (4 per used set), broadcast once.
struct TexPlanes {
    static constexpr int kMax = 4 * tex::kMaxTexCoordSets;
    __m128 c[kMax], dx[kMax], dy[kMax];
    int count = 0;
    void load(const Plane* p, int sets) {
        count = 4 * sets;
        for (int k = 0; k < count; ++k) {
            c[k] = _mm_set1_ps(p[k].c);
            dx[k] = _mm_set1_ps(p[k].dx);
            dy[k] = _mm_set1_ps(p[k].dy);
        }
    }
};
// dy·fy of each texture-coordinate plane for a row pair.
struct TexRowTerms {
    __m128 dyfy[TexPlanes::kMax];
    void load(const TexPlanes& p, __m128 fy) {
        for (int k = 0; k < p.count; ++k) dyfy[k] = _mm_mul_ps(p.dy[k], fy);
    }
};

}  // namespace sse

// Whether anything reads the quads' SPECULAR colour: the specular add, or an argument of a
// stage the texture units run (those before the first colour op DISABLE, D3D7). When
// nothing does, the kernels load 4 colour planes instead of 8 (sse::Planes::count) and
// leave FragmentQuad::specular at zero.
inline bool specularRead(const DrawContext& dc) {
    if (dc.st.specularEnable) return true;
    for (int i = 0; i < tex::kMaxStages; ++i) {
        const tex::StageState& s = dc.tu->stage(i);
        if (s.colorOp == tex::TextureOp::Disable) break;
        for (uint8_t a : {s.colorArg0, s.colorArg1, s.colorArg2, s.alphaArg0, s.alphaArg1,
                          s.alphaArg2})
            if ((a & tex::arg::SourceMask) == tex::arg::Specular) return true;
    }
    return false;
}

// `q` is the triangle's FragmentQuad scratch: this writes every field the texture units
// read (position, coverage, diffuse, specular when read, and the used coordinate sets).
template <bool kDepth, int kBlendMode>
[[gnu::always_inline]] inline void processTexturedQuadSse(
    const DrawContext& dc, const SetupTriangle& t, const sse::Planes& planes,
    const sse::RowTerms& row, const sse::TexPlanes& tplanes, const sse::TexRowTerms& trow,
    int qx, int qy, unsigned coverage, tex::FragmentQuad& q, RasterCounters& rc) {
    const PipelineState& st = dc.st;
    const __m128 fx = _mm_sub_ps(_mm_setr_ps(float(qx) + 0.5f, float(qx + 1) + 0.5f,
                                             float(qx) + 0.5f, float(qx + 1) + 0.5f),
                                 _mm_set1_ps(t.x0));
    // ---- 1/w, every pixel (texture coordinates are always perspective-correct) ---------
    const __m128 w =
        _mm_add_ps(_mm_add_ps(_mm_set1_ps(t.invW.c), _mm_mul_ps(_mm_set1_ps(t.invW.dx), fx)),
                   row.wdyfy);
    const __m128 r = _mm_div_ps(_mm_set1_ps(1.0f), w);

    // ---- colours ------------------------------------------------------------------------
    __m128i diffuse, specular = _mm_setzero_si128();
    if (dc.gouraud) {
        // processQuad multiplies by this r when perspectiveColor; by 1 (unitW) is exact.
        const bool perspective = dc.perspectiveColor && !planes.unitW;
        diffuse = sse::colors(planes, row, 0, fx, perspective, r);
        // 4 planes loaded: nothing reads SPECULAR (specularRead).
        if (planes.count == 8) specular = sse::colors(planes, row, 4, fx, perspective, r);
    } else {
        uint32_t bits;
        std::memcpy(&bits, &t.flatDiffuse, 4);
        diffuse = _mm_set1_epi32(int(bits));
        std::memcpy(&bits, &t.flatSpecular, 4);
        specular = _mm_set1_epi32(int(bits));
    }

    // ---- texture coordinates and the stage cascade --------------------------------------
    q.x = qx;
    q.y = qy;
    q.coverage = uint8_t(coverage);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(q.diffuse.data()), diffuse);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(q.specular.data()), specular);
    for (int k = 0; k < dc.numTexSets; ++k) {
        __m128 v[4];
        for (int c = 0; c < 4; ++c) {
            const int p = 4 * k + c;
            v[c] = _mm_mul_ps(
                _mm_add_ps(_mm_add_ps(tplanes.c[p], _mm_mul_ps(tplanes.dx[p], fx)), trow.dyfy[p]),
                r);
        }
        _MM_TRANSPOSE4_PS(v[0], v[1], v[2], v[3]);
        auto& dst = q.texCoord[size_t(dc.texSets[size_t(k)])];
        for (int i = 0; i < 4; ++i) _mm_storeu_ps(&dst[size_t(i)][0], v[i]);
    }
    std::array<Rgba8, 4> shaded;
    dc.tu->shadeQuad(q, shaded, dc.path);
    __m128i src = _mm_loadu_si128(reinterpret_cast<const __m128i*>(shaded.data()));
    if (st.specularEnable)  // addSpecular: rgb saturate-add, alpha untouched
        src = _mm_adds_epu8(src, _mm_and_si128(specular, _mm_set1_epi32(0x00FFFFFF)));

    quadOutputSse<kDepth, kBlendMode>(dc, t, qx, qy, coverage, src, rc);
}

}  // namespace rg::raster::detail
