// The fast rasterizer: triangles binned into 64×64 tiles that one thread owns each, row
// spans solved exactly from the integer edge functions instead of testing every pixel,
// a constant-colour span fill where nothing varies per pixel, and processQuad()
// instantiated per (depth, blend, texture) so that the inner loop has no state branches.
// It visits exactly the pixels the reference visits, each pixel's triangles in the same
// order, and runs the same per-pixel arithmetic (fragment_quad.h).
#include "raster_tiles.h"

#include <algorithm>
#include <optional>

#include "fragment_quad.h"
#include "fragment_quad_sse.h"
#include "fragment_quad_textured.h"
#include "raster_span_avx2.h"

namespace rg::raster::detail {

void binChunk(TriangleChunk& chunk, int tilesX, int tilesY) {
    // Counting sort by tile without a second array: count into binStart[tile], make each
    // entry the end of its tile's run, then place the triangles last to first, stepping
    // each tile's entry down to the start of its run (items stay in triangle order).
    const int tiles = tilesX * tilesY;
    chunk.binStart.assign(size_t(tiles) + 1, 0);
    uint32_t* bin = chunk.binStart.data();
    for (const SetupTriangle& t : chunk.tris) {
        const int tx0 = t.minX >> kTileShift, tx1 = t.maxX >> kTileShift;
        const int ty0 = t.minY >> kTileShift, ty1 = t.maxY >> kTileShift;
        if (tx0 == tx1 && ty0 == ty1) {  // the common case: inside one tile
            ++bin[ty0 * tilesX + tx0];
            continue;
        }
        for (int ty = ty0; ty <= ty1; ++ty)
            for (int tx = tx0; tx <= tx1; ++tx) ++bin[ty * tilesX + tx];
    }
    for (int i = 1; i < tiles; ++i) bin[i] += bin[i - 1];
    bin[tiles] = tiles > 0 ? bin[tiles - 1] : 0;
    chunk.binItems.resize(bin[tiles]);
    uint32_t* items = chunk.binItems.data();
    for (uint32_t n = uint32_t(chunk.tris.size()); n-- > 0;) {
        const SetupTriangle& t = chunk.tris[n];
        const int tx0 = t.minX >> kTileShift, tx1 = t.maxX >> kTileShift;
        const int ty0 = t.minY >> kTileShift, ty1 = t.maxY >> kTileShift;
        for (int ty = ty0; ty <= ty1; ++ty)
            for (int tx = tx0; tx <= tx1; ++tx) items[--bin[ty * tilesX + tx]] = n;
    }
}

namespace {

struct Box {
    int x0, y0, x1, y1;  // inclusive
};

// The textured walk's scratch, made once per run of triangles (a tile of a draw) instead
// of per triangle: value-initialising these 3 KiB for every triangle of a mesh of tiny
// ones took 46 % of quadWalk (rep stos; hybrid's layer passes, perf). Each quad writes
// every field the texture units read before they read it, so no triangle sees another's.
struct WalkScratch {
    std::array<tex::FragmentQuad, 2> fragment;
    sse::TexPlanes tplanes;
    sse::TexRowTerms trow;
    // The colour planes a textured quad interpolates (sse::Planes::count): the same for
    // every triangle of the draw, so decided once rather than per triangle.
    int colorPlanes;
    explicit WalkScratch(const DrawContext& dc)
        : colorPlanes(dc.gouraud ? (specularRead(dc) ? 8 : 4) : 0) {}
};

// Covered pixels of row py: [l, r] ∩ box. Edge e is E = R + K·px with
// R = C + A·half + B·Y and K = A·2^s; E ≥ 0 solved exactly in integers.
// Always inlined: in spanFill's row loop a call costs the flat fill 2% (measured).
[[gnu::always_inline]] inline bool rowSpan(const SetupTriangle& t, int py, int s,
                                           const Box& box, int& l, int& r) {
    const int64_t half = int64_t{1} << (s - 1);
    const int64_t Y = (int64_t(py) << s) + half;
    int64_t lo = box.x0, hi = box.x1;
    for (int e = 0; e < 3; ++e) {
        const int64_t R = t.C[e] + t.A[e] * half + t.B[e] * Y;
        const int64_t K = t.A[e] << s;
        if (K > 0) {
            lo = std::max(lo, -floorDiv(R, K));  // px ≥ ceil(−R/K)
        } else if (K < 0) {
            hi = std::min(hi, floorDiv(R, -K));  // px ≤ floor(R/−K)
        } else if (R < 0) {
            return false;
        }
    }
    if (lo > hi) return false;
    l = int(lo);
    r = int(hi);
    return true;
}

// Constant colour over the whole triangle: flat shading, or planes without slope.
// Returns the colour processQuad would compute for every pixel.
bool constantColor(const DrawContext& dc, const SetupTriangle& t, Rgba8& out) {
    if (!dc.gouraud) {
        out = t.flatDiffuse;
        return true;
    }
    for (int a = 0; a < 4; ++a)
        if (t.colorDx[a] != 0.0f || t.colorDy[a] != 0.0f) return false;
    float r = 1.0f;
    if (dc.perspectiveColor) {
        if (t.invW.dx != 0.0f || t.invW.dy != 0.0f) return false;
        r = 1.0f / t.invW.c;
    }
    uint8_t c[4];
    for (int a = 0; a < 4; ++a) {
        float v = t.colorC[a];
        if (dc.perspectiveColor) v = v * r;
        c[a] = colorToByte(v);
    }
    out = Rgba8{c[0], c[1], c[2], c[3]};
    return true;
}

// The covered span [l, r] of each row of `box` for the two constant-colour paths below,
// with the counters they share: every covered pixel generated; when `pass` (the alpha
// test, decided once on the constant alpha) written, and `write(row, l, r)` run on the
// row's pixels.
template <class Write>
[[gnu::always_inline]] inline void constantSpans(const DrawContext& dc, const SetupTriangle& t,
                                                 const Box& box, bool pass, RasterCounters& rc,
                                                 Write&& write) {
    const int s = dc.subpixelBits;
    Rgba8* base = dc.fb->color().data();
    const size_t width = size_t(dc.fb->width());
    for (int py = box.y0; py <= box.y1; ++py) {
        int l, r;
        if (!rowSpan(t, py, s, box, l, r)) continue;
        const uint64_t n = uint64_t(r - l + 1);
        rc.generated += n;
        if (!pass) continue;
        rc.written += n;
        write(base + size_t(py) * width, l, r);
    }
}

bool alphaPasses(const PipelineState& st, Rgba8 color) {
    return !st.alphaTest || comparePasses(st.alphaFunc, color.a, st.alphaRef);
}

// The span fill: passes no depth, blend, texture or specular, so each covered pixel
// receives the same colour (after alpha test and write mask, both decided once).
void spanFill(const DrawContext& dc, const SetupTriangle& t, const Box& box, Rgba8 color,
              RasterCounters& rc) {
    const uint8_t mask = dc.st.colorWriteMask;
    uint32_t bits;
    std::memcpy(&bits, &color, 4);
    const __m128i four = _mm_set1_epi32(int(bits));
    constantSpans(dc, t, box, alphaPasses(dc.st, color), rc, [&](Rgba8* row, int l, int r) {
        if (mask == kWriteRGBA) {
            // Four pixels a store (std::fill of the 4-byte struct compiled to one store a
            // pixel, measured).
            int x = l;
            for (; x + 3 <= r; x += 4) _mm_storeu_si128(reinterpret_cast<__m128i*>(row + x), four);
            for (; x <= r; ++x) row[x] = color;
        } else {
            for (int x = l; x <= r; ++x) row[x] = applyWriteMask(mask, color, row[x]);
        }
    });
}

// A constant colour blended over the framebuffer, with no depth, texture or specular
// (hybrid's alpha-clear polygon, 000 §5): every covered pixel's source is that colour, so
// each row's span is blended from it directly, four pixels per step with the quad
// kernel's two-pixel blend (sse::blend2, as quadOutputSse) and the rest with blendPixel,
// the function blend2 computes two pixels of. The same bytes and counters as the quad
// walk, without its per-quad interpolation of planes that have no slope.
void spanBlend(const DrawContext& dc, const SetupTriangle& t, const Box& box, Rgba8 color,
               RasterCounters& rc) {
    const PipelineState& st = dc.st;
    const uint8_t mask = st.colorWriteMask;
    const BlendFactor sf = st.srcBlend, df = st.dstBlend;
    const BlendOp op = st.blendOp;
    uint32_t bits;
    std::memcpy(&bits, &color, 4);
    const __m128i zero = _mm_setzero_si128();
    const __m128i src16 = _mm_unpacklo_epi8(_mm_set1_epi32(int(bits)), zero);  // two pixels
    const __m128i keep = _mm_set1_epi32(int(sse::writeMaskBytes(mask)));
    constantSpans(dc, t, box, alphaPasses(st, color), rc, [&](Rgba8* row, int l, int r) {
        rc.blendOps += uint64_t(r - l + 1);
        int x = l;
        for (; x + 3 <= r; x += 4) {
            __m128i* p = reinterpret_cast<__m128i*>(row + x);
            const __m128i dst = _mm_loadu_si128(p);
            const __m128i lo = sse::blend2(sf, df, op, src16, _mm_unpacklo_epi8(dst, zero));
            const __m128i hi = sse::blend2(sf, df, op, src16, _mm_unpackhi_epi8(dst, zero));
            __m128i out = _mm_packus_epi16(lo, hi);
            if (mask != kWriteRGBA)
                out = _mm_or_si128(_mm_and_si128(keep, out), _mm_andnot_si128(keep, dst));
            _mm_storeu_si128(p, out);
        }
        for (; x <= r; ++x)
            row[x] = applyWriteMask(mask, blendPixel(sf, df, op, color, row[x]), row[x]);
    });
}

// Boxes inside one even-aligned 2×2 quad (triangles of a pixel or two, the common case of
// dense meshes): the coverage of that one quad straight from the three edge functions,
// then the quad kernel, without the per-row set-up of quadWalk. Pass-through only (the
// texture stages keep their FragmentQuad scratch in quadWalk).
template <bool kDepth, int kBlendMode>
[[gnu::always_inline]] inline void singleQuad(const DrawContext& dc, const SetupTriangle& t,
                                              const Box& box, RasterCounters& rc) {
    constexpr bool kBlend = kBlendMode != kBlendNone;
    const int qx = box.x0 & ~1, qy = box.y0 & ~1;
    unsigned coverage;
    if (t.maxX <= (t.minX | 1) && t.maxY <= (t.minY | 1)) {
        // The triangle's own box is this quad (a tile cannot cut it: tiles are
        // even-aligned): its coverage came with the setup.
        coverage = t.quadCoverage;
    } else {  // a larger box that a tile edge cut down to one quad
        coverage = quadEdgeCoverage(t, qx, qy, dc.subpixelBits);
        coverage &= (qx >= box.x0 ? 0x5u : 0u) | (qx + 1 <= box.x1 ? 0xAu : 0u);
        coverage &= (qy >= box.y0 ? 0x3u : 0u) | (qy + 1 <= box.y1 ? 0xCu : 0u);
    }
    if (!coverage) return;
    if (qx + 1 < dc.fb->width() && qy + 1 < dc.fb->height()) {
        if (dc.gouraud && !dc.st.specularEnable) {
            // processQuadSse's interpolation with the diffuse planes in registers (no
            // Planes/RowTerms arrays): the same operations on the same values, namely
            // (c + dx·fx) + dy·fy, ·r, clamp, +½, truncate.
            const __m128 fx = _mm_sub_ps(_mm_setr_ps(float(qx) + 0.5f, float(qx + 1) + 0.5f,
                                                     float(qx) + 0.5f, float(qx + 1) + 0.5f),
                                         _mm_set1_ps(t.x0));
            const __m128 fy = _mm_sub_ps(_mm_setr_ps(float(qy) + 0.5f, float(qy) + 0.5f,
                                                     float(qy + 1) + 0.5f, float(qy + 1) + 0.5f),
                                         _mm_set1_ps(t.y0));
            bool perspective = dc.perspectiveColor;
            __m128 r = _mm_set1_ps(1.0f);
            if (perspective) {
                const Plane& w = t.invW;
                if (w.dx == 0.0f && w.dy == 0.0f && std::isfinite(w.c) && w.c != 0.0f) {
                    const float fr = w.c == 1.0f ? 1.0f : 1.0f / w.c;  // sse::Planes::load
                    perspective = fr != 1.0f;
                    r = _mm_set1_ps(fr);
                } else {
                    const __m128 wv = _mm_add_ps(
                        _mm_add_ps(_mm_set1_ps(w.c), _mm_mul_ps(_mm_set1_ps(w.dx), fx)),
                        _mm_mul_ps(_mm_set1_ps(w.dy), fy));
                    r = _mm_div_ps(_mm_set1_ps(1.0f), wv);
                }
            }
            __m128i ch[4];
            for (int a = 0; a < 4; ++a) {
                __m128 v = _mm_add_ps(
                    _mm_add_ps(_mm_set1_ps(t.colorC[a]), _mm_mul_ps(_mm_set1_ps(t.colorDx[a]), fx)),
                    _mm_mul_ps(_mm_set1_ps(t.colorDy[a]), fy));
                if (perspective) v = _mm_mul_ps(v, r);
                ch[a] = sse::channelToInt(v);
            }
            quadOutputSse<kDepth, kBlendMode>(dc, t, qx, qy, coverage,
                                              sse::toPixels(ch[0], ch[1], ch[2], ch[3]), rc);
            return;
        }
        sse::Planes planes;
        sse::RowTerms row;
        if (dc.gouraud) {
            planes.load(t, dc.st.specularEnable ? 8 : 4);
            row.load(planes, t, qy);
        }
        processQuadSse<kDepth, kBlendMode>(dc, t, planes, row, qx, qy, coverage, rc);
        return;
    }
    processQuad<true, kDepth, kBlend, true>(dc, t, nullptr, qx, qy, coverage, rc, nullptr);
}

bool inOneQuad(const Box& b) { return b.x1 <= (b.x0 | 1) && b.y1 <= (b.y0 | 1); }

// Narrow boxes (small triangles): the three edge functions stepped per pixel in int64,
// cheaper than solving row spans with divisions. Wide boxes: exact row spans.
constexpr int kSpanWalkMinWidth = 16;

// The quads of one triangle inside `box`. Quads wholly inside the target go to the SSE2
// kernels (they load and store both rows of the quad; fragment_quad_textured.h for quads
// with texture stages), the rest to the scalar template; all compute what
// processQuad<false, ...> (the reference) computes.
template <bool kDepth, int kBlendMode, bool kPassThrough>
void quadWalk(const DrawContext& dc, const SetupTriangle& t, const Plane* texPool, const Box& box,
              WalkScratch& scratch, RasterCounters& rc) {
    constexpr bool kBlend = kBlendMode != kBlendNone;
    const int s = dc.subpixelBits;
    const int fbW = dc.fb->width(), fbH = dc.fb->height();
    sse::Planes planes;
    sse::RowTerms row;
    // Textured quads: the run's scratch (WalkScratch), every field the texture units read
    // written per quad before it is read.
    std::array<tex::FragmentQuad, 2>* const fragment = &scratch.fragment;
    sse::TexPlanes* const tplanes = &scratch.tplanes;
    sse::TexRowTerms* const trow = &scratch.trow;
    if constexpr (!kPassThrough) {
        tplanes->load(texPool + t.texPlanes, dc.numTexSets);
        planes.load(t, scratch.colorPlanes);  // 1/w: every quad
    }
    // The AVX2 runs cover Gouraud colour without the specular add (raster_span_avx2.h).
    // Textured runs: any colour state.
    const bool useAvx2 =
        (!kPassThrough || (dc.gouraud && !dc.st.specularEnable)) && haveAvx2();
    if constexpr (kPassThrough)
        if (dc.gouraud) planes.load(t, dc.st.specularEnable ? 8 : 4);
    auto quad = [&](int qx, int qy, unsigned coverage) {
        if (qx + 1 < fbW && qy + 1 < fbH) {
            if constexpr (kPassThrough)
                processQuadSse<kDepth, kBlendMode>(dc, t, planes, row, qx, qy, coverage, rc);
            else
                processTexturedQuadSse<kDepth, kBlendMode>(dc, t, planes, row, *tplanes, *trow,
                                                           qx, qy, coverage, (*fragment)[0], rc);
            return;
        }
        processQuad<true, kDepth, kBlend, kPassThrough>(dc, t, texPool, qx, qy, coverage, rc,
                                                        kPassThrough ? nullptr : &(*fragment)[0]);
    };
    auto startRow = [&](int qy) {
        if constexpr (kPassThrough) {
            if (dc.gouraud) row.load(planes, t, qy);
        } else {
            row.load(planes, t, qy);
            trow->load(*tplanes, row.fy);
        }
    };

    if (box.x1 - box.x0 + 1 < kSpanWalkMinWidth) {
        const int64_t half = int64_t{1} << (s - 1);
        const int qx0 = box.x0 & ~1;
        int64_t stepX[3], stepY[3], rowE[3];
        for (int e = 0; e < 3; ++e) {
            stepX[e] = t.A[e] << s;
            stepY[e] = t.B[e] << s;
        }
        for (int qy = box.y0 & ~1; qy <= box.y1; qy += 2) {
            const int64_t Y = (int64_t(qy) << s) + half, X = (int64_t(qx0) << s) + half;
            for (int e = 0; e < 3; ++e) rowE[e] = t.C[e] + t.A[e] * X + t.B[e] * Y;
            // Rows of the quad inside the box.
            const unsigned rowMask = (qy >= box.y0 ? 0x3u : 0u) | (qy + 1 <= box.y1 ? 0xCu : 0u);
            bool rowStarted = false;
            for (int qx = qx0; qx <= box.x1; qx += 2) {
                // All three E ≥ 0 ⇔ the OR of the three has its sign bit clear.
                unsigned coverage = 0;
                for (int i = 0; i < 4; ++i) {
                    int64_t any = 0;
                    for (int e = 0; e < 3; ++e)
                        any |= rowE[e] + ((i & 1) ? stepX[e] : 0) + ((i >> 1) ? stepY[e] : 0);
                    coverage |= unsigned(any >= 0) << i;
                }
                const unsigned colMask = (qx >= box.x0 ? 0x5u : 0u) | (qx + 1 <= box.x1 ? 0xAu : 0u);
                coverage &= rowMask & colMask;
                if (coverage) {
                    if (!rowStarted) startRow(qy), rowStarted = true;
                    quad(qx, qy, coverage);
                }
                for (int e = 0; e < 3; ++e) rowE[e] += 2 * stepX[e];
            }
        }
        return;
    }
    for (int qy = box.y0 & ~1; qy <= box.y1; qy += 2) {
        int l0 = 0, r0 = -1, l1 = 0, r1 = -1;
        bool row0 = qy >= box.y0 && rowSpan(t, qy, s, box, l0, r0);
        bool row1 = qy + 1 <= box.y1 && rowSpan(t, qy + 1, s, box, l1, r1);
        if (!row0 && !row1) continue;
        startRow(qy);
        int l = row0 ? (row1 ? std::min(l0, l1) : l0) : l1;
        int r = row0 ? (row1 ? std::max(r0, r1) : r0) : r1;
        auto coverageAt = [&](int qx) {
            unsigned coverage = 0;
            coverage |= unsigned(row0 && qx >= l0 && qx <= r0) << 0;
            coverage |= unsigned(row0 && qx + 1 >= l0 && qx + 1 <= r0) << 1;
            coverage |= unsigned(row1 && qx >= l1 && qx <= r1) << 2;
            coverage |= unsigned(row1 && qx + 1 >= l1 && qx + 1 <= r1) << 3;
            return coverage;
        };
        // Runs of quads, two per AVX2 register, when every quad is inside the target.
        if (useAvx2 && qy + 1 < fbH && (r | 1) < fbW) {
            uint8_t cov[64];
            for (int qx = l & ~1; qx <= r;) {
                int n = 0;
                const int first = qx;
                for (; n < 64 && qx <= r; ++n, qx += 2) cov[n] = uint8_t(coverageAt(qx));
                if constexpr (kPassThrough)
                    quadRunAvx2<kDepth, kBlendMode>(dc, t, planes, row, qy, first, n, cov, rc);
                else
                    texturedRunAvx2<kDepth, kBlendMode>(dc, t, planes, row, *tplanes, *trow, qy,
                                                        first, n, cov, fragment->data(), rc);
            }
            continue;
        }
        for (int qx = l & ~1; qx <= r; qx += 2) {
            const unsigned coverage = coverageAt(qx);
            if (coverage) quad(qx, qy, coverage);
        }
    }
}

using QuadWalkFn = void (*)(const DrawContext&, const SetupTriangle&, const Plane*, const Box&,
                            WalkScratch&, RasterCounters&);
// A run of one chunk's triangles: items [begin, end) of its tris, or with `tile` of its
// bin list, each box clipped to the tile. Each triangle goes to the single-quad kernel
// (inlined here, with its state as template arguments: a call per triangle and the
// kernel's entry cost more than its work on meshes of tiny triangles, measured), the span
// fill or quadWalk.
using TriangleRunFn = void (*)(const DrawContext&, const TriangleChunk&, uint32_t begin,
                               uint32_t end, const Box* tile, QuadWalkFn walk,
                               WalkScratch&, RasterCounters&);

template <bool kSingleQuad, bool kDepth, int kBlendMode>
[[gnu::always_inline]] inline void triangleRunBody(const DrawContext& dc,
                                                   const TriangleChunk& chunk, uint32_t begin,
                                                   uint32_t end, const Box* tile,
                                                   QuadWalkFn walk, WalkScratch& scratch,
                                                   RasterCounters& rc) {
    // No texture, specular or depth: a triangle of one colour goes span by span
    // (spanBlend when blending, else spanFill).
    const bool spanPath = dc.passThrough && !dc.st.specularEnable && !dc.depthOn;
    const SetupTriangle* tris = chunk.tris.data();
    const uint32_t* items = chunk.binItems.data();
    for (uint32_t k = begin; k < end; ++k) {
        const SetupTriangle& t = tris[tile ? items[k] : k];
        Box box{t.minX, t.minY, t.maxX, t.maxY};
        if (tile) {
            box = Box{std::max(box.x0, tile->x0), std::max(box.y0, tile->y0),
                      std::min(box.x1, tile->x1), std::min(box.y1, tile->y1)};
            if (box.x0 > box.x1 || box.y0 > box.y1) continue;
        }
        Rgba8 color;
        if (kSingleQuad && inOneQuad(box))
            singleQuad<kDepth, kBlendMode>(dc, t, box, rc);
        else if (spanPath && constantColor(dc, t, color))
            (dc.st.blend ? spanBlend : spanFill)(dc, t, box, color, rc);
        else
            walk(dc, t, chunk.texPlanes.data(), box, scratch, rc);
    }
}

template <bool kSingleQuad, bool kDepth, int kBlendMode>
void triangleRun(const DrawContext& dc, const TriangleChunk& chunk, uint32_t begin,
                 uint32_t end, const Box* tile, QuadWalkFn walk, WalkScratch& scratch,
                 RasterCounters& rc) {
    triangleRunBody<kSingleQuad, kDepth, kBlendMode>(dc, chunk, begin, end, tile, walk, scratch,
                                                     rc);
}

// The same run compiled for AVX2 when the CPU has it: the same SSE operations on the
// same values (no FMA in the target), VEX-encoded, so that the single-quad kernel
// broadcasts each plane coefficient straight from memory and needs no register copies
// (218 -> 198 instructions per tiny triangle in callgrind).
template <bool kSingleQuad, bool kDepth, int kBlendMode>
__attribute__((target("avx2"))) void triangleRunAvx2(const DrawContext& dc,
                                                     const TriangleChunk& chunk,
                                                     uint32_t begin, uint32_t end,
                                                     const Box* tile, QuadWalkFn walk,
                                                     WalkScratch& scratch, RasterCounters& rc) {
    triangleRunBody<kSingleQuad, kDepth, kBlendMode>(dc, chunk, begin, end, tile, walk, scratch,
                                                     rc);
}

template <bool kDepth, int kBlendMode>
TriangleRunFn singleQuadRun(bool avx2) {
    return avx2 ? triangleRunAvx2<true, kDepth, kBlendMode> : triangleRun<true, kDepth, kBlendMode>;
}

// The run for the state: the single-quad kernel for pass-through quads (the texture
// stages keep their FragmentQuad scratch in quadWalk).
TriangleRunFn selectTriangleRun(const DrawContext& dc) {
    if (!dc.passThrough) return triangleRun<false, false, kBlendNone>;
    const PipelineState& st = dc.st;
    const bool avx2 = haveAvx2();
    auto pick = [&]<bool kDepth>() -> TriangleRunFn {
        if (!st.blend) return singleQuadRun<kDepth, kBlendNone>(avx2);
        if (st.blendOp == BlendOp::Add && st.srcBlend == BlendFactor::SrcAlpha &&
            st.dstBlend == BlendFactor::InvSrcAlpha)
            return singleQuadRun<kDepth, kBlendSrcAlphaInvSrcAlpha>(avx2);
        if (st.blendOp == BlendOp::Add && st.srcBlend == BlendFactor::One &&
            st.dstBlend == BlendFactor::One)
            return singleQuadRun<kDepth, kBlendOneOne>(avx2);
        return singleQuadRun<kDepth, kBlendGeneric>(avx2);
    };
    return dc.depthOn ? pick.template operator()<true>() : pick.template operator()<false>();
}

template <bool kDepth, bool kPassThrough>
QuadWalkFn selectBlend(const DrawContext& dc) {
    const PipelineState& st = dc.st;
    if (!st.blend) return quadWalk<kDepth, kBlendNone, kPassThrough>;
    if (st.blendOp == BlendOp::Add && st.srcBlend == BlendFactor::SrcAlpha &&
        st.dstBlend == BlendFactor::InvSrcAlpha)
        return quadWalk<kDepth, kBlendSrcAlphaInvSrcAlpha, kPassThrough>;
    if (st.blendOp == BlendOp::Add && st.srcBlend == BlendFactor::One &&
        st.dstBlend == BlendFactor::One)
        return quadWalk<kDepth, kBlendOneOne, kPassThrough>;
    return quadWalk<kDepth, kBlendGeneric, kPassThrough>;
}

QuadWalkFn selectQuadWalk(const DrawContext& dc) {
    if (dc.depthOn)
        return dc.passThrough ? selectBlend<true, true>(dc) : selectBlend<true, false>(dc);
    return dc.passThrough ? selectBlend<false, true>(dc) : selectBlend<false, false>(dc);
}

}  // namespace

void rasterizeTile(const DrawContext& dc, std::span<const TriangleChunk> chunks, int tile,
                   int tilesX, RasterCounters& out) {
    // Count locally and publish once: neighbouring tiles' counters share cache lines.
    RasterCounters rc;
    const int tx = tile % tilesX, ty = tile / tilesX;
    const Box tileBox{tx * kTileSize, ty * kTileSize, tx * kTileSize + kTileSize - 1,
                      ty * kTileSize + kTileSize - 1};
    const QuadWalkFn walk = selectQuadWalk(dc);
    const TriangleRunFn run = selectTriangleRun(dc);
    WalkScratch scratch(dc);
    for (const TriangleChunk& chunk : chunks)
        run(dc, chunk, chunk.binStart[tile], chunk.binStart[tile + 1], &tileBox, walk, scratch,
            rc);
    out.add(rc);
}

}  // namespace rg::raster::detail

namespace rg::raster::detail {

// One thread: no tiles to share out, so each chunk is rasterized right after its setup
// while its triangles are still in cache, each triangle over its whole box. Quads are
// even-aligned in both cases, so splitting a box at tile edges or not visits the same
// quads with the same coverage, and submission order is kept: the same bytes.
void rasterizeChunk(const DrawContext& dc, const TriangleChunk& chunk, RasterCounters& rc) {
    WalkScratch scratch(dc);
    selectTriangleRun(dc)(dc, chunk, 0, uint32_t(chunk.tris.size()), nullptr,
                          selectQuadWalk(dc), scratch, rc);
}

}  // namespace rg::raster::detail
