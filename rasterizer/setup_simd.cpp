// The fast path's triangle setup (setupTrianglesFast): primitive assembly and setup of a
// run of triangles, four triangles per SIMD iteration. It computes every field
// setupTriangle (setup_triangle.cpp, the reference) computes, with the same IEEE
// operations on the same operands, so the SetupTriangle is bit for bit the same
// (tests/rasterizer/test_setup_simd.cpp compares them field by field on random
// triangles; tests/rasterizer/test_paths_agree.cpp compares whole frames).
//
// Why the four-triangle lanes are exact (docs/hardware.md, "Setup and rasterization"):
//   - the snapped coordinates of a vertex inside the guard band are integers below
//     2^22.01 (16385·2^8), so every integer of setup — differences (< 2^23.01), the area
//     and the edge constants C (< 2^47) — is exact in double; floor(v / 2^s) of the pixel
//     box is a multiplication by 2^−s (exact) and a floor; the int64 results are read back
//     from the mantissa (toInt64), exact below 2^51;
//   - 1/area is one division 2^2s/area, which rounds to exactly the reference's
//     1/(area·2^−2s) because scaling by a power of two commutes with rounding (no
//     overflow or underflow: 1 ≤ area < 2^50);
//   - the planes are makePlane's double operations lane by lane (sub, mul, the
//     double→float conversion rounding to nearest like the scalar cast); no FMA is
//     enabled (-ffp-contract=off, and the AVX2 target does not include FMA).
// The colour and texture-coordinate planes of a triangle are four channels per register
// (one channel per 64-bit lane). Triangles with a vertex outside a clip plane, invalid or
// with a non-finite window position take clipAndSetup, in their place in the order.
#include <immintrin.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include <glm/mat3x3.hpp>

#include "pipeline.h"
#include "raster_span_avx2.h"
#include "simd_lanes.h"


namespace rg::raster::detail {

namespace {

using namespace lanes;

// The per-triangle results of four triangles' geometry, one triangle per lane.
struct Geometry4 {
    I64x4 A[3], B[3], C[3];
    I32x4 minX, minY, maxX, maxY;
    F32x4 x0, y0;
    F64x4 zc, zdx, zdy;
    F32x4 wC, wDx, wDy;                // the 1/w plane
    F64x4 dx1, dy1, dx2, dy2, invArea;  // what the attribute planes share
    I64x4 keep;                        // all ones: not culled, pixels in the clip rect
    I64x4 swapped;                     // all ones: vertices 1 and 2 exchanged (A < 0)
    I64x4 quadCoverage;                // SetupTriangle::quadCoverage
};

// setupTriangle's geometry for the triangles (v[k][0], v[k][1], v[k][2]), k = 0..3, of
// vertices that need no clipping. V: ProcessedVertex or FastVertex (int32 sx, sy, converted
// exactly).
template <class V>
RG_LANES void setupGeometry4(const DrawContext& dc, const V* const (&v)[4][3], Geometry4& g) {
    const int s = dc.subpixelBits;
    const bool needInvW = (dc.gouraud && dc.perspectiveColor) || dc.numTexSets > 0;
    F64x4 X[3], Y[3], Z[3] = {}, W[3] = {};  // z and 1/w only when a plane needs them
    for (int j = 0; j < 3; ++j) {
        if constexpr (std::is_same_v<V, FastVertex>) {
            // (sx, sy, wz, invW) of the four records, one 16-byte load each, transposed
            // into lanes (instead of a load and an insert per value).
            static_assert(offsetof(FastVertex, sy) == 4 && offsetof(FastVertex, wz) == 8 &&
                          offsetof(FastVertex, invW) == 12);
            __m128i r[4];
            for (int k = 0; k < 4; ++k)
                r[k] = _mm_load_si128(reinterpret_cast<const __m128i*>(v[k][j]));
            const __m128i sxy01 = _mm_unpacklo_epi32(r[0], r[1]);  // sx0 sx1 sy0 sy1
            const __m128i sxy23 = _mm_unpacklo_epi32(r[2], r[3]);
            const __m128i zw01 = _mm_unpackhi_epi32(r[0], r[1]);   // wz0 wz1 w0 w1
            const __m128i zw23 = _mm_unpackhi_epi32(r[2], r[3]);
            X[j] = __builtin_convertvector((I32x4)_mm_unpacklo_epi64(sxy01, sxy23), F64x4);
            Y[j] = __builtin_convertvector((I32x4)_mm_unpackhi_epi64(sxy01, sxy23), F64x4);
            if (dc.depthOn)
                Z[j] = __builtin_convertvector((F32x4)_mm_unpacklo_epi64(zw01, zw23), F64x4);
            if (needInvW)
                W[j] = __builtin_convertvector((F32x4)_mm_unpackhi_epi64(zw01, zw23), F64x4);
            continue;
        } else {
            X[j] = toDouble(I64x4{v[0][j]->sx, v[1][j]->sx, v[2][j]->sx, v[3][j]->sx});
            Y[j] = toDouble(I64x4{v[0][j]->sy, v[1][j]->sy, v[2][j]->sy, v[3][j]->sy});
        }
        if (dc.depthOn)
            Z[j] = __builtin_convertvector(
                F32x4{v[0][j]->wz, v[1][j]->wz, v[2][j]->wz, v[3][j]->wz}, F64x4);
        if (needInvW)
            W[j] = __builtin_convertvector(
                F32x4{v[0][j]->invW, v[1][j]->invW, v[2][j]->invW, v[3][j]->invW}, F64x4);
    }

    // ---- orientation and culling -------------------------------------------------------
    F64x4 area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    I64x4 reject = (I64x4)(area == 0.0);
    if (dc.st.cull == CullMode::CW) reject |= (I64x4)(area > 0.0);
    if (dc.st.cull == CullMode::CCW) reject |= (I64x4)(area < 0.0);
    const I64x4 neg = (I64x4)(area < 0.0);
    auto swap12 = [&](F64x4(&a)[3]) {
        const F64x4 a1 = a[1];
        a[1] = neg ? a[2] : a[1];
        a[2] = neg ? a1 : a[2];
    };
    swap12(X);
    swap12(Y);
    swap12(Z);
    swap12(W);
    area = neg ? -area : area;
    g.swapped = neg;
    g.invArea = splat(double(int64_t{1} << (2 * s))) / area;

    // ---- pixel box -----------------------------------------------------------------------
    const double half = double(int64_t{1} << (s - 1)), one = double(int64_t{1} << s);
    const double inv = 1.0 / one;  // a power of two
    const F64x4 minXf = minLanes(X[0], minLanes(X[1], X[2]));
    const F64x4 maxXf = maxLanes(X[0], maxLanes(X[1], X[2]));
    const F64x4 minYf = minLanes(Y[0], minLanes(Y[1], Y[2]));
    const F64x4 maxYf = maxLanes(Y[0], maxLanes(Y[1], Y[2]));
    const F64x4 minX = maxLanes(splat(dc.clipX0), floorLanes(((minXf - half) + one - 1.0) * inv));
    const F64x4 minY = maxLanes(splat(dc.clipY0), floorLanes(((minYf - half) + one - 1.0) * inv));
    const F64x4 maxX = minLanes(splat(dc.clipX1 - 1), floorLanes((maxXf - half) * inv));
    const F64x4 maxY = minLanes(splat(dc.clipY1 - 1), floorLanes((maxYf - half) * inv));
    reject |= (I64x4)(minX > maxX) | (I64x4)(minY > maxY);
    g.keep = ~reject;
    g.minX = __builtin_convertvector(minX, I32x4);
    g.minY = __builtin_convertvector(minY, I32x4);
    g.maxX = __builtin_convertvector(maxX, I32x4);
    g.maxY = __builtin_convertvector(maxY, I32x4);

    // ---- edge functions with the top-left rule -----------------------------------------
    // With the coverage of the quad (QX, QY) a box inside one quad lies in
    // (quadCoverageOf): each E at the four pixel centres, exact in double (integers below
    // 2^49: C < 2^47, A·QX and B·QY < 2^45 for a box inside the target).
    const I64x4 boxX0 = toInt64(minX), boxY0 = toInt64(minY);
    const I64x4 boxX1 = toInt64(maxX), boxY1 = toInt64(maxY);
    const I64x4 qx = boxX0 & ~int64_t{1}, qy = boxY0 & ~int64_t{1};
    const F64x4 QX = toDouble(qx) * one + half, QY = toDouble(qy) * one + half;
    I64x4 inside[4] = {~I64x4{}, ~I64x4{}, ~I64x4{}, ~I64x4{}};  // pixel i: every E ≥ 0
    for (int e = 0; e < 3; ++e) {
        const int a = e, b = e == 2 ? 0 : e + 1;
        const F64x4 dxe = X[b] - X[a], dye = Y[b] - Y[a];
        const I64x4 topLeft = (I64x4)(dye < 0.0) | ((I64x4)(dye == 0.0) & (I64x4)(dxe > 0.0));
        const F64x4 c = dye * X[a] - dxe * Y[a];
        g.A[e] = toInt64(-dye);
        g.B[e] = toInt64(dxe);
        g.C[e] = toInt64(c) + ~topLeft;  // ~topLeft: −1 or 0
        // C as a double: c − 1 where the edge is not top-left (the bits of −1.0 or +0.0).
        const F64x4 cFull = c + (F64x4)(~topLeft & (I64x4)splat(-1.0));
        const F64x4 e0 = (cFull - dye * QX) + dxe * QY, stepX = -dye * one, stepY = dxe * one;
        inside[0] &= (I64x4)(e0 >= 0.0);
        inside[1] &= (I64x4)(e0 + stepX >= 0.0);
        inside[2] &= (I64x4)(e0 + stepY >= 0.0);
        inside[3] &= (I64x4)((e0 + stepX) + stepY >= 0.0);
    }
    I64x4 coverage = (inside[0] & 1) | (inside[1] & 2) | (inside[2] & 4) | (inside[3] & 8);
    coverage &= ~((I64x4)(qx < boxX0) & 0x5) & ~((I64x4)(qx + 1 > boxX1) & 0xA);
    coverage &= ~((I64x4)(qy < boxY0) & 0x3) & ~((I64x4)(qy + 1 > boxY1) & 0xC);
    g.quadCoverage = coverage & (I64x4)(boxX1 <= (boxX0 | 1)) & (I64x4)(boxY1 <= (boxY0 | 1));

    // ---- planes --------------------------------------------------------------------------
    const F64x4 x0 = X[0] * inv, y0 = Y[0] * inv;
    g.dx1 = X[1] * inv - x0;
    g.dy1 = Y[1] * inv - y0;
    g.dx2 = X[2] * inv - x0;
    g.dy2 = Y[2] * inv - y0;
    g.x0 = __builtin_convertvector(x0, F32x4);
    g.y0 = __builtin_convertvector(y0, F32x4);
    if (dc.depthOn) {
        const F64x4 da1 = Z[1] - Z[0], da2 = Z[2] - Z[0];
        g.zc = Z[0];
        g.zdx = (da1 * g.dy2 - da2 * g.dy1) * g.invArea;
        g.zdy = (da2 * g.dx1 - da1 * g.dx2) * g.invArea;
    }
    if (needInvW) {
        const F64x4 da1 = W[1] - W[0], da2 = W[2] - W[0];
        g.wC = __builtin_convertvector(W[0], F32x4);
        g.wDx = __builtin_convertvector((da1 * g.dy2 - da2 * g.dy1) * g.invArea, F32x4);
        g.wDy = __builtin_convertvector((da2 * g.dx1 - da1 * g.dx2) * g.invArea, F32x4);
    }
}

struct PlaneGeometry {  // one lane of Geometry4: what a triangle's planes share
    double dx1, dy1, dx2, dy2, invArea;
};

// makePlane for 4 channels (a_v = attr_v·(1/w of v) when perspective-correct) of 3
// vertices. Out of line: a function of the default target cannot inline an AVX2 one.
__attribute__((target("avx2"))) void colorPlanes4Avx2(__m128 a0, __m128 a1, __m128 a2,
                                                      double w0,
                                                      double w1, double w2,
                                                      bool perspective, const PlaneGeometry& g,
                                                      float* c, float* dx, float* dy) {
    __m256d p0 = _mm256_cvtps_pd(a0);
    __m256d p1 = _mm256_cvtps_pd(a1);
    __m256d p2 = _mm256_cvtps_pd(a2);
    if (perspective) {
        p0 = _mm256_mul_pd(p0, _mm256_set1_pd(w0));
        p1 = _mm256_mul_pd(p1, _mm256_set1_pd(w1));
        p2 = _mm256_mul_pd(p2, _mm256_set1_pd(w2));
    }
    const __m256d da1 = _mm256_sub_pd(p1, p0), da2 = _mm256_sub_pd(p2, p0);
    const __m256d inv = _mm256_set1_pd(g.invArea);
    const __m256d pdx =
        _mm256_mul_pd(_mm256_sub_pd(_mm256_mul_pd(da1, _mm256_set1_pd(g.dy2)),
                                    _mm256_mul_pd(da2, _mm256_set1_pd(g.dy1))),
                      inv);
    const __m256d pdy =
        _mm256_mul_pd(_mm256_sub_pd(_mm256_mul_pd(da2, _mm256_set1_pd(g.dx1)),
                                    _mm256_mul_pd(da1, _mm256_set1_pd(g.dx2))),
                      inv);
    _mm_storeu_ps(c, _mm256_cvtpd_ps(p0));
    _mm_storeu_ps(dx, _mm256_cvtpd_ps(pdx));
    _mm_storeu_ps(dy, _mm256_cvtpd_ps(pdy));
}

[[gnu::always_inline]] inline void colorPlanes4Sse2(__m128 a0, __m128 a1, __m128 a2,
                                                    double w0, double w1,
                                                    double w2, bool perspective,
                                                    const PlaneGeometry& g, float* c,
                                                    float* dx, float* dy) {
    for (int h = 0; h < 4; h += 2) {  // channels (h, h + 1) per register
        // channels (h, h + 1) in the low half
        __m128d p0 = _mm_cvtps_pd(h ? _mm_movehl_ps(a0, a0) : a0);
        __m128d p1 = _mm_cvtps_pd(h ? _mm_movehl_ps(a1, a1) : a1);
        __m128d p2 = _mm_cvtps_pd(h ? _mm_movehl_ps(a2, a2) : a2);
        if (perspective) {
            p0 = _mm_mul_pd(p0, _mm_set1_pd(w0));
            p1 = _mm_mul_pd(p1, _mm_set1_pd(w1));
            p2 = _mm_mul_pd(p2, _mm_set1_pd(w2));
        }
        const __m128d da1 = _mm_sub_pd(p1, p0), da2 = _mm_sub_pd(p2, p0);
        const __m128d inv = _mm_set1_pd(g.invArea);
        const __m128d pdx = _mm_mul_pd(_mm_sub_pd(_mm_mul_pd(da1, _mm_set1_pd(g.dy2)),
                                                  _mm_mul_pd(da2, _mm_set1_pd(g.dy1))),
                                       inv);
        const __m128d pdy = _mm_mul_pd(_mm_sub_pd(_mm_mul_pd(da2, _mm_set1_pd(g.dx1)),
                                                  _mm_mul_pd(da1, _mm_set1_pd(g.dx2))),
                                       inv);
        _mm_storel_epi64(reinterpret_cast<__m128i*>(c + h),
                         _mm_castps_si128(_mm_cvtpd_ps(p0)));
        _mm_storel_epi64(reinterpret_cast<__m128i*>(dx + h),
                         _mm_castps_si128(_mm_cvtpd_ps(pdx)));
        _mm_storel_epi64(reinterpret_cast<__m128i*>(dy + h),
                         _mm_castps_si128(_mm_cvtpd_ps(pdy)));
    }
}

// Attributes a..a+3 of a vertex: ProcessedVertex::attr, or for a FastVertex its diffuse
// (a = 0) or specular (a = 4) bytes widened to float (exact, as processVertexInto's
// float(d.r) and so on).
template <class V>
RG_LANES __m128 attr4(const V* v, int a) {
    if constexpr (std::is_same_v<V, FastVertex>) {
        uint32_t bits;
        std::memcpy(&bits, a == 0 ? &v->diffuse : &v->specular, 4);
        const __m128i z = _mm_setzero_si128();
        const __m128i b = _mm_cvtsi32_si128(int(bits));
        return _mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(b, z), z));
    } else {
        return _mm_loadu_ps(&v->attr[a]);
    }
}

// Lane k of `g` as the SetupTriangle setupTriangle builds, appended to `out`, with its
// texture planes appended to `texPool`. Constructed in place without zeroing
// (SetupTriangle::NoInit), so every member is written below, with the zero a
// value-initialised SetupTriangle holds wherever setup computes nothing. (Building it in a
// local and copying it costs more: the copy's 16-byte loads wait on the narrower field
// stores, measured.)
template <bool kAvx2, class V>
RG_LANES void emitTriangle(const DrawContext& dc, const Geometry4& g, int k,
                           const V* const (&tri)[3], Rgba8 flatDiffuse, Rgba8 flatSpecular,
                           std::vector<SetupTriangle>& out,
                           std::vector<Plane>& texPool) {
    SetupTriangle& t = out.emplace_back(SetupTriangle::NoInit{});
    for (int e = 0; e < 3; ++e) {
        t.A[e] = g.A[e][k];
        t.B[e] = g.B[e][k];
        t.C[e] = g.C[e][k];
    }
    t.minX = g.minX[k];
    t.minY = g.minY[k];
    t.maxX = g.maxX[k];
    t.maxY = g.maxY[k];
    t.x0 = g.x0[k];
    t.y0 = g.y0[k];
    t.quadCoverage = uint32_t(g.quadCoverage[k]);
    if (dc.depthOn) {
        t.zc = g.zc[k];
        t.zdx = g.zdx[k];
        t.zdy = g.zdy[k];
    } else {
        t.zc = t.zdx = t.zdy = 0.0;
    }
    const bool needInvW = (dc.gouraud && dc.perspectiveColor) || dc.numTexSets > 0;
    t.invW = needInvW ? Plane{g.wC[k], g.wDx[k], g.wDy[k]} : Plane{};
    const V* v0 = tri[0];
    const V* v1 = g.swapped[k] ? tri[2] : tri[1];
    const V* v2 = g.swapped[k] ? tri[1] : tri[2];
    const PlaneGeometry pg{g.dx1[k], g.dy1[k], g.dx2[k], g.dy2[k], g.invArea[k]};
    const double w0 = v0->invW, w1 = v1->invW, w2 = v2->invW;
    const int colors = dc.gouraud ? (dc.needSpecular ? 8 : 4) : 0;
    // Zeros where no plane is computed: channels 4..7 and, flat, 0..3 (16-byte stores; a
    // loop of run-time length compiled to a slow generic clear, measured).
    const F32x4 zero = {};
    if (colors < 8)
        for (float* z : {&t.colorC[4], &t.colorDx[4], &t.colorDy[4]}) std::memcpy(z, &zero, 16);
    if (colors < 4)
        for (float* z : {&t.colorC[0], &t.colorDx[0], &t.colorDy[0]}) std::memcpy(z, &zero, 16);
    for (int a = 0; a < colors; a += 4) {
        if constexpr (kAvx2)
            colorPlanes4Avx2(attr4(v0, a), attr4(v1, a), attr4(v2, a), w0, w1, w2,
                             dc.perspectiveColor, pg, &t.colorC[a], &t.colorDx[a],
                             &t.colorDy[a]);
        else
            colorPlanes4Sse2(attr4(v0, a), attr4(v1, a), attr4(v2, a), w0, w1, w2,
                             dc.perspectiveColor, pg, &t.colorC[a], &t.colorDx[a],
                             &t.colorDy[a]);
    }
    t.texPlanes = uint32_t(texPool.size());
    if constexpr (std::is_same_v<V, ProcessedVertex>) if (dc.numAttrs > kColorAttrs) {
        texPool.resize(texPool.size() + size_t(dc.numAttrs - kColorAttrs));
        Plane* p = texPool.data() + t.texPlanes;
        alignas(16) float c[4], dx[4], dy[4];
        int a = kColorAttrs;
        for (; a + 4 <= dc.numAttrs; a += 4, p += 4) {  // one set per step
            if constexpr (kAvx2)
                colorPlanes4Avx2(attr4(v0, a), attr4(v1, a), attr4(v2, a), w0, w1, w2, true,
                                 pg, c, dx, dy);
            else
                colorPlanes4Sse2(attr4(v0, a), attr4(v1, a), attr4(v2, a), w0, w1, w2, true,
                                 pg, c, dx, dy);
            for (int q = 0; q < 4; ++q) p[q] = Plane{c[q], dx[q], dy[q]};
        }
        for (; a < dc.numAttrs; ++a, ++p)  // a partial set (only programmable varyings)
            *p = makePlane(v0->attr[a] * w0, v1->attr[a] * w1, v2->attr[a] * w2, pg.dx1,
                           pg.dy1, pg.dx2, pg.dy2, pg.invArea);
    }
    // The provoking vertex's bytes matter only for flat shading.
    t.flatDiffuse = dc.gouraud ? Rgba8{} : flatDiffuse;
    t.flatSpecular = dc.gouraud ? Rgba8{} : flatSpecular;
}

// The matrices a FastVertex draw recomputes the ProcessedVertex of a clipped triangle's
// vertices with (processVertexInto), and whether to prefetch the records
// (setupTrianglesCompact).
struct Transforms {
    const glm::mat4& worldViewProj;
    const glm::mat4& worldView;
    const glm::mat3& normalMatrix;
    bool prefetch;
    const RowBand* band;  // non-null: only the triangles of one band of rows (RowBand)
};

// ---- a band's triangles (RowBand) ----------------------------------------------------
constexpr uint32_t kSelect = 256;       // triangles selected per call
constexpr uint32_t kOwned = 1u << 31;  // in a selected entry: the band owns the triangle

// Which of triangles [begin, end) the band sets up, in order, into `out` (triangle number,
// | kOwned where the band counts it); returns how many. A triangle's rows [first, last]
// are the minimum and maximum of its vertices' RowBand::rowSpans (the box's floors are
// monotonic in the snapped y, so the box's rows are those of its extreme vertices); its
// owner row is `first` clamped to the draw's clip rows (a vertex that needs clipping
// spans every row: the first band owns the triangle, and every band sets it up).
inline bool selectOne(const DrawContext& dc, const RowBand& band, uint32_t sa, uint32_t sb,
                      uint32_t sc, bool& mine) {
    const int first = std::min({int16_t(sa), int16_t(sb), int16_t(sc)});
    const int last = -std::min({int16_t(sa >> 16), int16_t(sb >> 16), int16_t(sc >> 16)});
    const int ownerRow = std::clamp(first, band.full->clipY0, band.full->clipY1 - 1);
    mine = ownerRow >= dc.clipY0 && ownerRow < dc.clipY1;
    return mine || (last >= dc.clipY0 && first < dc.clipY1);
}

// The reference selection: one triangle at a time, any primitive.
uint32_t selectBandScalar(const DrawContext& dc, const RowBand& band, Primitive primitive,
                          std::span<const uint32_t> indices, uint32_t begin, uint32_t end,
                          uint32_t* out) {
    uint32_t n = 0;
    for (uint32_t t = begin; t < end; ++t) {
        std::array<uint32_t, 3> tv = triangleVertices(primitive, t);
        if (!indices.empty())
            for (uint32_t& x : tv) x = indices[x];
        bool mine;
        if (selectOne(dc, band, band.rowSpans[tv[0]], band.rowSpans[tv[1]],
                      band.rowSpans[tv[2]], mine))
            out[n++] = t | (mine ? kOwned : 0u);
    }
    return n;
}

// Indexed lists on AVX2: eight triangles per step, their 24 indices split into the
// first, second and third vertex of each by permutes, the spans gathered, and the
// minima of both halves of the packed spans taken at once (vpminsw); the same answer as
// selectOne (PathsAgree.MeshesDrawnInBandsOfRowsGiveIdenticalBytesAndCounters, with and
// without RETROGLASS_NO_AVX2).
__attribute__((target("avx2"))) uint32_t selectBandListAvx2(const DrawContext& dc,
                                                            const RowBand& band,
                                                            const uint32_t* indices,
                                                            uint32_t begin, uint32_t end,
                                                            uint32_t* out) {
    const int* spans = reinterpret_cast<const int*>(band.rowSpans);
    // Lane k of vertex j of eight triangles is index 3k + j of the 24: from the first,
    // second or third register of eight indices, lane (3k + j) mod 8.
    const __m256i pickA0 = _mm256_setr_epi32(0, 3, 6, 0, 0, 0, 0, 0);
    const __m256i pickA1 = _mm256_setr_epi32(0, 0, 0, 1, 4, 7, 0, 0);
    const __m256i pickA2 = _mm256_setr_epi32(0, 0, 0, 0, 0, 0, 2, 5);
    const __m256i pickB0 = _mm256_setr_epi32(1, 4, 7, 0, 0, 0, 0, 0);
    const __m256i pickB1 = _mm256_setr_epi32(0, 0, 0, 2, 5, 0, 0, 0);
    const __m256i pickB2 = _mm256_setr_epi32(0, 0, 0, 0, 0, 0, 3, 6);
    const __m256i pickC0 = _mm256_setr_epi32(2, 5, 0, 0, 0, 0, 0, 0);
    const __m256i pickC1 = _mm256_setr_epi32(0, 0, 0, 3, 6, 0, 0, 0);
    const __m256i pickC2 = _mm256_setr_epi32(0, 0, 0, 0, 0, 1, 4, 7);
    const __m256i fullY0 = _mm256_set1_epi32(band.full->clipY0);
    const __m256i fullLast = _mm256_set1_epi32(band.full->clipY1 - 1);
    const __m256i bandY0m1 = _mm256_set1_epi32(dc.clipY0 - 1);
    const __m256i bandY1 = _mm256_set1_epi32(dc.clipY1);
    uint32_t n = 0, t = begin;
    for (; t + 8 <= end; t += 8) {
        const uint32_t* p = indices + 3 * size_t(t);
        const __m256i i0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
        const __m256i i1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + 8));
        const __m256i i2 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p + 16));
        // a: 0,3,6 | 9,12,15 | 18,21; b: 1,4,7 | 10,13 | 16,19,22; c: 2,5 | 8,11,14 | 17,20,23
        const __m256i a = _mm256_blend_epi32(
            _mm256_blend_epi32(_mm256_permutevar8x32_epi32(i0, pickA0),
                               _mm256_permutevar8x32_epi32(i1, pickA1), 0x38),
            _mm256_permutevar8x32_epi32(i2, pickA2), 0xC0);
        const __m256i b = _mm256_blend_epi32(
            _mm256_blend_epi32(_mm256_permutevar8x32_epi32(i0, pickB0),
                               _mm256_permutevar8x32_epi32(i1, pickB1), 0x18),
            _mm256_permutevar8x32_epi32(i2, pickB2), 0xE0);
        const __m256i c = _mm256_blend_epi32(
            _mm256_blend_epi32(_mm256_permutevar8x32_epi32(i0, pickC0),
                               _mm256_permutevar8x32_epi32(i1, pickC1), 0x1C),
            _mm256_permutevar8x32_epi32(i2, pickC2), 0xE0);
        const __m256i span = _mm256_min_epi16(
            _mm256_min_epi16(_mm256_i32gather_epi32(spans, a, 4),
                             _mm256_i32gather_epi32(spans, b, 4)),
            _mm256_i32gather_epi32(spans, c, 4));
        const __m256i first = _mm256_srai_epi32(_mm256_slli_epi32(span, 16), 16);
        const __m256i last = _mm256_sub_epi32(_mm256_setzero_si256(), _mm256_srai_epi32(span, 16));
        const __m256i owner = _mm256_min_epi32(_mm256_max_epi32(first, fullY0), fullLast);
        const __m256i mine = _mm256_and_si256(_mm256_cmpgt_epi32(owner, bandY0m1),
                                              _mm256_cmpgt_epi32(bandY1, owner));
        const __m256i meets = _mm256_and_si256(_mm256_cmpgt_epi32(last, bandY0m1),
                                               _mm256_cmpgt_epi32(bandY1, first));
        unsigned keep = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_or_si256(mine, meets))));
        const unsigned owned = unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(mine)));
        while (keep) {
            const unsigned k = unsigned(__builtin_ctz(keep));
            keep &= keep - 1;
            out[n++] = (t + k) | ((owned >> k) & 1u) << 31;
        }
    }
    const std::span<const uint32_t> all(indices, 3 * size_t(end));
    return n + selectBandScalar(dc, band, Primitive::TriangleList, all, t, end, out + n);
}

template <bool kAvx2, bool kIndexedList>
RG_LANES uint32_t selectBand(const DrawContext& dc, const RowBand& band, Primitive primitive,
                             std::span<const uint32_t> indices, uint32_t begin, uint32_t end,
                             uint32_t* out) {
    if constexpr (kAvx2 && kIndexedList)
        return selectBandListAvx2(dc, band, indices.data(), begin, end, out);
    else
        return selectBandScalar(dc, band, primitive, indices, begin, end, out);
}

// kIndexedList: the caller checked that `primitive` is a triangle list with indices (most
// meshes), so that the assembly below compiles to loads of consecutive indices instead of
// a switch and two branches per triangle and vertex.
// kBanded (FastVertex only): transforms->band names a band of rows; the triangles whose
// box misses its rows are skipped (the band's own clip rect, `dc`, would reject them), and
// the counters count only the triangles the band owns (RowBand), so that the bands of a
// draw together count each triangle once, as one setup over the whole clip rect would.
// Vertices: the submitted vertices, a span of Vertex (ProcessedVertex) or a VertexSource
// (FastVertex, whose records carry the colour bytes: the source is read only to clip).
template <bool kAvx2, class V, bool kIndexedList = false, bool kBanded = false,
          class Vertices>
RG_LANES void setupRangeBody(const DrawContext& dc, Primitive primitive, uint32_t begin,
                             uint32_t end, std::span<const uint32_t> indices,
                             const Vertices& vertices, const V* processed,
                             const Transforms* transforms, std::vector<SetupTriangle>& out,
                             std::vector<Plane>& texPool, GeometryCounters& gc) {
    if constexpr (kIndexedList) primitive = Primitive::TriangleList;
    out.reserve(out.size() + (end - begin));
    const bool indexed = kIndexedList || !indices.empty();
    // The vertices of triangles kPrefetch ahead are requested from memory: a draw's
    // vertex array is far larger than L2 (216 or 32 bytes each), and the loop body is too long
    // for the core to reach the next group's loads on its own (measured: a third of the
    // setup time went to waiting on the first vertex loads of a group). Not for records the
    // caller has just written (setupTrianglesCompact's `prefetch`).
    constexpr uint32_t kPrefetch = 16;
    const bool prefetch = !kBanded && (!transforms || transforms->prefetch);
    GeometryCounters notOwned;  // kBanded: the counts of triangles another band owns
    // kBanded: the band's triangles of [begin, end), kSelect at a time (selectBand).
    uint32_t selected[kSelect];
    uint32_t selectedCount = 0, selectedNext = 0, scanned = begin;
    for (uint32_t i = begin;; i += 4) {
        // ---- the next four triangles (of the band) ----------------------------------------
        uint32_t tri[4];
        int n = 0;
        unsigned owned = 0xF;  // bit k: triangle k's counts are this band's
        if constexpr (kBanded) {
            static_assert(std::is_same_v<V, FastVertex>);
            owned = 0;
            while (n < 4) {
                if (selectedNext == selectedCount) {
                    if (scanned == end) break;
                    const uint32_t stop = std::min(end, scanned + kSelect);
                    selectedCount = selectBand<kAvx2, kIndexedList>(
                        dc, *transforms->band, primitive, indices, scanned, stop, selected);
                    selectedNext = 0;
                    scanned = stop;
                    continue;
                }
                const uint32_t e = selected[selectedNext++];
                tri[n] = e & ~kOwned;
                owned |= (e >> 31) << n;
                ++n;
            }
            if (n == 0) break;
        } else {
            if (i >= end) break;
            n = int(std::min<uint32_t>(4, end - i));
            for (int k = 0; k < 4; ++k) tri[k] = i + uint32_t(k);
        }
        if (prefetch && i + kPrefetch + 4 <= end) {
            for (uint32_t k = 0; k < 4; ++k) {
                const std::array<uint32_t, 3> tv = triangleVertices(primitive, i + kPrefetch + k);
                for (uint32_t x : tv) {
                    const char* p = reinterpret_cast<const char*>(
                        &processed[indexed ? indices[x] : x]);
                    __builtin_prefetch(p);
                    if constexpr (sizeof(V) > 64) __builtin_prefetch(p + 64);
                }
            }
        }
        // ---- primitive assembly of up to four triangles ----------------------------------
        const V* v[4][3];
        uint32_t provoking[4], second[4], third[4];
        unsigned unclipped = 0;  // bit k: triangle k takes the SIMD setup
        for (int k = 0; k < 4; ++k) {
            if (k >= n) {  // a spare lane computes triangle 0 again, unused
                v[k][0] = v[0][0], v[k][1] = v[0][1], v[k][2] = v[0][2];
                continue;
            }
            const std::array<uint32_t, 3> tv = triangleVertices(primitive, tri[k]);
            const uint32_t a = indexed ? indices[tv[0]] : tv[0];
            const uint32_t b = indexed ? indices[tv[1]] : tv[1];
            const uint32_t c = indexed ? indices[tv[2]] : tv[2];
            provoking[k] = a;
            second[k] = b;
            third[k] = c;
            v[k][0] = &processed[a];
            v[k][1] = &processed[b];
            v[k][2] = &processed[c];
            unclipped |= unsigned(v[k][0]->unclipped & v[k][1]->unclipped & v[k][2]->unclipped)
                         << k;
        }
        // ---- setup, in triangle order ------------------------------------------------------
        if (dc.subpixelBits > 8) unclipped = 0;  // beyond the bounds above: the reference
        Geometry4 g;
        if (unclipped) setupGeometry4(dc, v, g);
        for (int k = 0; k < n; ++k) {
            GeometryCounters& counts = (owned >> k) & 1 ? gc : notOwned;
            // The provoking vertex's colours, which only flat shading reads (a FastVertex
            // record has them; a Vertex is not loaded otherwise).
            Rgba8 flatD{}, flatS{};
            if (!dc.gouraud) {
                if constexpr (std::is_same_v<V, FastVertex>) {
                    flatD = v[k][0]->diffuse;
                    flatS = v[k][0]->specular;
                } else {
                    flatD = vertices[provoking[k]].diffuse;
                    flatS = vertices[provoking[k]].specular;
                }
            }
            if (unclipped & (1u << k)) {
                ++counts.submitted;
                if (g.keep[k]) {
                    emitTriangle<kAvx2, V>(dc, g, k, v[k], flatD, flatS, out, texPool);
                    ++counts.drawn;
                } else {
                    ++counts.culled;
                }
            } else {
                if constexpr (std::is_same_v<V, FastVertex>) {
                    // The records hold too little to clip: the vertex stage again, scalar
                    // (the lanes' values, SetupSimd.EightVertexLanesEqualTheScalarVertexStage).
                    ProcessedVertex full[3];
                    const uint32_t idx[3] = {provoking[k], second[k], third[k]};
                    for (int j = 0; j < 3; ++j)
                        processVertexInto(dc, transforms->worldViewProj, transforms->worldView,
                                          transforms->normalMatrix, vertices.at(idx[j]),
                                          full[j]);
                    if constexpr (kBanded) {
                        // What the clipper makes of it may lie in any band, and a piece
                        // outside this band's rows would count as culled: the owner counts
                        // the triangle from a setup over the whole clip rect, whose
                        // triangles it then drops.
                        if ((owned >> k) & 1) {
                            const size_t tris = out.size(), planes = texPool.size();
                            clipAndSetup(*transforms->band->full, full[0], full[1], full[2],
                                         flatD, flatS, out, texPool, gc);
                            out.resize(tris);
                            texPool.resize(planes);
                        }
                        clipAndSetup(dc, full[0], full[1], full[2], flatD, flatS, out, texPool,
                                     notOwned);
                    } else {
                        clipAndSetup(dc, full[0], full[1], full[2], flatD, flatS, out, texPool,
                                     gc);
                    }
                } else {
                    (void)transforms;
                    clipAndSetup(dc, *v[k][0], *v[k][1], *v[k][2], flatD, flatS, out,
                                 texPool, gc);
                }
            }
        }
    }
}

__attribute__((target("avx2"))) void setupRangeAvx2(
    const DrawContext& dc, Primitive primitive, uint32_t begin, uint32_t end,
    std::span<const uint32_t> indices, std::span<const Vertex> vertices,
    const ProcessedVertex* processed, std::vector<SetupTriangle>& out,
    std::vector<Plane>& texPool, GeometryCounters& gc) {
    setupRangeBody<true>(dc, primitive, begin, end, indices, vertices, processed, nullptr,
                         out, texPool, gc);
}

void setupRangeSse2(const DrawContext& dc, Primitive primitive, uint32_t begin,
                    uint32_t end, std::span<const uint32_t> indices,
                    std::span<const Vertex> vertices, const ProcessedVertex* processed,
                    std::vector<SetupTriangle>& out, std::vector<Plane>& texPool,
                    GeometryCounters& gc) {
    setupRangeBody<false>(dc, primitive, begin, end, indices, vertices, processed, nullptr,
                          out, texPool, gc);
}

// Indexed triangle lists (most meshes) take the instantiation whose primitive assembly
// reads consecutive indices; strips, fans and unindexed draws the general one.
template <bool kAvx2>
RG_LANES void setupCompactBody(const DrawContext& dc, Primitive primitive, uint32_t begin,
                               uint32_t end, std::span<const uint32_t> indices,
                               const VertexSource& vertices, const FastVertex* processed,
                               const Transforms& tr, std::vector<SetupTriangle>& out,
                               std::vector<Plane>& texPool, GeometryCounters& gc) {
    const bool list = primitive == Primitive::TriangleList && !indices.empty();
    if (tr.band && list)
        setupRangeBody<kAvx2, FastVertex, true, true>(dc, primitive, begin, end, indices,
                                                      vertices, processed, &tr, out, texPool,
                                                      gc);
    else if (tr.band)
        setupRangeBody<kAvx2, FastVertex, false, true>(dc, primitive, begin, end, indices,
                                                       vertices, processed, &tr, out, texPool,
                                                       gc);
    else if (list)
        setupRangeBody<kAvx2, FastVertex, true>(dc, primitive, begin, end, indices, vertices,
                                                processed, &tr, out, texPool, gc);
    else
        setupRangeBody<kAvx2>(dc, primitive, begin, end, indices, vertices, processed, &tr,
                              out, texPool, gc);
}

__attribute__((target("avx2"))) void setupCompactAvx2(
    const DrawContext& dc, Primitive primitive, uint32_t begin, uint32_t end,
    std::span<const uint32_t> indices, const VertexSource& vertices,
    const FastVertex* processed, const Transforms& tr, std::vector<SetupTriangle>& out,
    std::vector<Plane>& texPool, GeometryCounters& gc) {
    setupCompactBody<true>(dc, primitive, begin, end, indices, vertices, processed, tr, out,
                           texPool, gc);
}

void setupCompactSse2(const DrawContext& dc, Primitive primitive, uint32_t begin,
                      uint32_t end, std::span<const uint32_t> indices,
                      const VertexSource& vertices, const FastVertex* processed,
                      const Transforms& tr, std::vector<SetupTriangle>& out,
                      std::vector<Plane>& texPool, GeometryCounters& gc) {
    setupCompactBody<false>(dc, primitive, begin, end, indices, vertices, processed, tr, out,
                            texPool, gc);
}

}  // namespace

void setupTrianglesFast(const DrawContext& dc, Primitive primitive, uint32_t begin,
                        uint32_t end, std::span<const uint32_t> indices,
                        std::span<const Vertex> vertices,
                        const ProcessedVertex* processed, std::vector<SetupTriangle>& out,
                        std::vector<Plane>& texPool, GeometryCounters& gc) {
    static const bool avx2 = haveAvx2();
    if (avx2)
        setupRangeAvx2(dc, primitive, begin, end, indices, vertices, processed, out,
                       texPool, gc);
    else
        setupRangeSse2(dc, primitive, begin, end, indices, vertices, processed, out,
                       texPool, gc);
}

void setupTrianglesCompact(const DrawContext& dc, Primitive primitive, uint32_t begin,
                           uint32_t end, std::span<const uint32_t> indices,
                           const VertexSource& vertices, const FastVertex* processed,
                           const glm::mat4& worldViewProj, const glm::mat4& worldView,
                           const glm::mat3& normalMatrix, std::vector<SetupTriangle>& out,
                           std::vector<Plane>& texPool, GeometryCounters& gc, bool prefetch,
                           const RowBand* band) {
    static const bool avx2 = haveAvx2();
    const Transforms tr{worldViewProj, worldView, normalMatrix, prefetch, band};
    if (avx2)
        setupCompactAvx2(dc, primitive, begin, end, indices, vertices, processed, tr, out,
                         texPool, gc);
    else
        setupCompactSse2(dc, primitive, begin, end, indices, vertices, processed, tr, out,
                         texPool, gc);
}

}  // namespace rg::raster::detail
