// AVX2 runs of quads for the fast path (internal; see raster_span_avx2.cpp).
#pragma once

#include "fragment_quad_textured.h"

namespace rg::raster::detail {

// True when the CPU has AVX2 (checked once).
bool haveAvx2();

// Quads qx0, qx0 + 2, … (count of them) of the row pair at qy, with their coverage masks;
// Gouraud, no texture stage, no specular add, every quad inside the target. Two quads per
// 256-bit register, lane for lane the operations of processQuadSse.
template <bool kDepth, int kBlendMode>
void quadRunAvx2(const DrawContext& dc, const SetupTriangle& t, const sse::Planes& planes,
                 const sse::RowTerms& row, int qy, int qx0, int count, const uint8_t* coverage,
                 RasterCounters& rc);

// The same runs for quads with texture stages (every quad inside the target), two per
// 256-bit register, lane for lane processTexturedQuadSse; `q` points to two FragmentQuad
// scratch values of the triangle.
template <bool kDepth, int kBlendMode>
void texturedRunAvx2(const DrawContext& dc, const SetupTriangle& t, const sse::Planes& planes,
                     const sse::RowTerms& row, const sse::TexPlanes& tplanes,
                     const sse::TexRowTerms& trow, int qy, int qx0, int count,
                     const uint8_t* coverage, tex::FragmentQuad* q, RasterCounters& rc);

}  // namespace rg::raster::detail
