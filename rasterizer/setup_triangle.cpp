// Triangle setup: snap to fixed point, cull, edge functions with the top-left rule, the
// pixel bounding box and the attribute planes (docs/hardware.md, "Setup and
// rasterization" and "Interpolation").
#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <type_traits>

#include "pipeline.h"
#include "raster_span_avx2.h"

namespace rg::raster::detail {

namespace {

// The plane through (0,0,a0), (dx1,dy1,a1), (dx2,dy2,a2), in double, stored in single;
// invArea = 1/(dx1·dy2 − dx2·dy1) is computed once per triangle.
Plane makePlane(double a0, double a1, double a2, double dx1, double dy1, double dx2, double dy2,
                double invArea) {
    double da1 = a1 - a0, da2 = a2 - a0;
    Plane p;
    p.c = float(a0);
    p.dx = float((da1 * dy2 - da2 * dy1) * invArea);
    p.dy = float((da2 * dx1 - da1 * dx2) * invArea);
    return p;
}

}  // namespace

bool setupTriangle(const DrawContext& dc, const ProcessedVertex& v0, const ProcessedVertex& v1,
                   const ProcessedVertex& v2, Rgba8 flatDiffuse, Rgba8 flatSpecular,
                   SetupTriangle& t, std::vector<Plane>& texPool) {
    const ProcessedVertex* v[3] = {&v0, &v1, &v2};
    for (const ProcessedVertex* p : v)
        if (!std::isfinite(p->wx) || !std::isfinite(p->wy) || !std::isfinite(p->wz) ||
            !std::isfinite(p->invW))
            return false;

    // ---- snap to fixed point ------------------------------------------------------------
    const int s = dc.subpixelBits;
    int64_t X[3], Y[3];
    for (int i = 0; i < 3; ++i) {
        X[i] = v[i]->sx;
        Y[i] = v[i]->sy;
    }

    // ---- orientation and culling (y points down: area > 0 is clockwise on screen) -------
    int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    if (area == 0) return false;
    if (dc.st.cull == CullMode::CW && area > 0) return false;
    if (dc.st.cull == CullMode::CCW && area < 0) return false;
    if (area < 0) {  // rasterize every triangle clockwise; vertex 0 stays first
        std::swap(X[1], X[2]);
        std::swap(Y[1], Y[2]);
        std::swap(v[1], v[2]);
        area = -area;
    }
    // 1/area in pixels², started early so that the division overlaps the edge setup.
    // double(area)·2^−2s equals dx1·dy2 − dx2·dy1 below exactly: every term is an integer
    // multiple of 2^−2s below 2^53.
    const double invArea = 1.0 / (double(area) * (1.0 / double(int64_t{1} << (2 * s))));

    // ---- pixel box: samples at pixel centres (X << s) + half ---------------------------
    const int64_t half = int64_t{1} << (s - 1);
    int64_t minXf = std::min({X[0], X[1], X[2]}), maxXf = std::max({X[0], X[1], X[2]});
    int64_t minYf = std::min({Y[0], Y[1], Y[2]}), maxYf = std::max({Y[0], Y[1], Y[2]});
    int64_t one = int64_t{1} << s;
    t.minX = int(std::max<int64_t>(dc.clipX0, (minXf - half + one - 1) >> s));
    t.minY = int(std::max<int64_t>(dc.clipY0, (minYf - half + one - 1) >> s));
    t.maxX = int(std::min<int64_t>(dc.clipX1 - 1, (maxXf - half) >> s));
    t.maxY = int(std::min<int64_t>(dc.clipY1 - 1, (maxYf - half) >> s));
    if (t.minX > t.maxX || t.minY > t.maxY) return false;

    // ---- edge functions with the top-left rule -----------------------------------------
    // E(P) = (b.x − a.x)(P.y − a.y) − (b.y − a.y)(P.x − a.x), positive inside. A sample on
    // an edge belongs to the triangle only when the edge is a top edge (horizontal, the
    // triangle below it) or a left edge (going up on screen, the triangle to its right).
    for (int e = 0; e < 3; ++e) {
        int a = e, b = (e + 1) % 3;
        int64_t dxe = X[b] - X[a], dye = Y[b] - Y[a];
        bool topLeft = dye < 0 || (dye == 0 && dxe > 0);
        t.A[e] = -dye;
        t.B[e] = dxe;
        t.C[e] = dye * X[a] - dxe * Y[a] - (topLeft ? 0 : 1);
    }

    // ---- attribute planes --------------------------------------------------------------
    const double inv = 1.0 / double(one);
    double x0 = double(X[0]) * inv, y0 = double(Y[0]) * inv;
    double dx1 = double(X[1]) * inv - x0, dy1 = double(Y[1]) * inv - y0;
    double dx2 = double(X[2]) * inv - x0, dy2 = double(Y[2]) * inv - y0;
    t.x0 = float(x0);
    t.y0 = float(y0);

    if (dc.depthOn) {  // only the depth test reads z
        double a0 = v[0]->wz, a1 = v[1]->wz, a2 = v[2]->wz;
        double da1 = a1 - a0, da2 = a2 - a0;
        t.zc = a0;
        t.zdx = (da1 * dy2 - da2 * dy1) * invArea;
        t.zdy = (da2 * dx1 - da1 * dx2) * invArea;
    }
    const bool needInvW = (dc.gouraud && dc.perspectiveColor) || dc.numTexSets > 0;
    if (needInvW)
        t.invW = makePlane(v[0]->invW, v[1]->invW, v[2]->invW, dx1, dy1, dx2, dy2, invArea);
    auto attrPlane = [&](int a, bool perspective) {
        double w0 = perspective ? double(v[0]->invW) : 1.0;
        double w1 = perspective ? double(v[1]->invW) : 1.0;
        double w2 = perspective ? double(v[2]->invW) : 1.0;
        return makePlane(v[0]->attr[a] * w0, v[1]->attr[a] * w1, v[2]->attr[a] * w2, dx1, dy1,
                         dx2, dy2, invArea);
    };
    if (dc.gouraud) {
        int colors = dc.needSpecular ? 8 : 4;
        for (int a = 0; a < colors; ++a) {
            Plane p = attrPlane(a, dc.perspectiveColor);
            t.colorC[a] = p.c;
            t.colorDx[a] = p.dx;
            t.colorDy[a] = p.dy;
        }
    }
    t.texPlanes = uint32_t(texPool.size());
    for (int a = kColorAttrs; a < dc.numAttrs; ++a) texPool.push_back(attrPlane(a, true));
    t.flatDiffuse = flatDiffuse;
    t.flatSpecular = flatSpecular;
    return true;
}

// ---- the fast path's setup ---------------------------------------------------------
// setupTrianglesFast computes every field setupTriangle computes, with the same IEEE
// operations on the same operands, so the SetupTriangle is bit for bit the same
// (tests/rasterizer/test_paths_agree.cpp draws every triangle of the fast path through
// it and compares with the reference path). Two things are cheaper:
//   - one division for 1/area: 2^2s/area rounds to exactly 1/(area·2^−2s), because
//     scaling by a power of two commutes with rounding (no overflow or underflow:
//     1 ≤ area < 2^50);
//   - the colour planes four channels at a time, one channel per 64-bit lane (AVX2 when
//     the CPU has it, else two SSE2 registers): sub, mul and the double→float conversion
//     (round to nearest, as the scalar cast) are lane-wise IEEE operations, and no FMA
//     is enabled, so each lane is makePlane's arithmetic for its channel.
namespace {

struct Geometry {  // what the plane evaluations share
    double dx1, dy1, dx2, dy2, invArea;
};

// makePlane for 4 channels (a_v = attr_v·(1/w of v) when perspective-correct) of 3
// vertices. Out of line: a function of the default target cannot inline an AVX2 one.
__attribute__((target("avx2"))) void colorPlanes4Avx2(const float* a0, const float* a1,
                                                      const float* a2, double w0,
                                                      double w1, double w2,
                                                      bool perspective, const Geometry& g,
                                                      float* c, float* dx, float* dy) {
    __m256d p0 = _mm256_cvtps_pd(_mm_loadu_ps(a0));
    __m256d p1 = _mm256_cvtps_pd(_mm_loadu_ps(a1));
    __m256d p2 = _mm256_cvtps_pd(_mm_loadu_ps(a2));
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

[[gnu::always_inline]] inline void colorPlanes4Sse2(const float* a0, const float* a1,
                                                    const float* a2, double w0, double w1,
                                                    double w2, bool perspective,
                                                    const Geometry& g, float* c,
                                                    float* dx, float* dy) {
    for (int h = 0; h < 4; h += 2) {  // channels (h, h + 1) per register
        __m128d p0 = _mm_cvtps_pd(
            _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(a0 + h))));
        __m128d p1 = _mm_cvtps_pd(
            _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(a1 + h))));
        __m128d p2 = _mm_cvtps_pd(
            _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(a2 + h))));
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

// Set up in a local and append it whole: std::vector's emplace_back() would first zero
// the 256 bytes (value-initialisation), and so would a plain local (the member
// initialisers). The local lives in raw storage instead (SetupTriangle is an aggregate,
// an implicit-lifetime type, so the byte array provides the object, C++20
// [intro.object]), and every member is written below, with the zero a fresh SetupTriangle
// holds wherever setup computes nothing.
template <bool kAvx2>
[[gnu::always_inline]] inline bool setupFastBody(
    const DrawContext& dc, const ProcessedVertex& v0, const ProcessedVertex& v1,
    const ProcessedVertex& v2, Rgba8 flatDiffuse, Rgba8 flatSpecular,
    std::vector<SetupTriangle>& out, std::vector<Plane>& texPool) {
    static_assert(std::is_aggregate_v<SetupTriangle> &&
                  std::is_trivially_copyable_v<SetupTriangle> &&
                  std::is_trivially_destructible_v<SetupTriangle>);
    alignas(SetupTriangle) unsigned char storage[sizeof(SetupTriangle)];
    SetupTriangle& t = *std::launder(reinterpret_cast<SetupTriangle*>(storage));
    const ProcessedVertex* v[3] = {&v0, &v1, &v2};
    for (const ProcessedVertex* p : v)
        if (!std::isfinite(p->wx) || !std::isfinite(p->wy) || !std::isfinite(p->wz) ||
            !std::isfinite(p->invW))
            return false;

    const int s = dc.subpixelBits;
    int64_t X[3] = {v0.sx, v1.sx, v2.sx}, Y[3] = {v0.sy, v1.sy, v2.sy};
    int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    if (area == 0) return false;
    if (dc.st.cull == CullMode::CW && area > 0) return false;
    if (dc.st.cull == CullMode::CCW && area < 0) return false;
    if (area < 0) {
        std::swap(X[1], X[2]);
        std::swap(Y[1], Y[2]);
        std::swap(v[1], v[2]);
        area = -area;
    }
    const int64_t one = int64_t{1} << s;
    const double invArea = double(int64_t{1} << (2 * s)) / double(area);

    const int64_t half = int64_t{1} << (s - 1);
    const int64_t minXf = std::min({X[0], X[1], X[2]}),
                  maxXf = std::max({X[0], X[1], X[2]});
    const int64_t minYf = std::min({Y[0], Y[1], Y[2]}),
                  maxYf = std::max({Y[0], Y[1], Y[2]});
    t.minX = int(std::max<int64_t>(dc.clipX0, (minXf - half + one - 1) >> s));
    t.minY = int(std::max<int64_t>(dc.clipY0, (minYf - half + one - 1) >> s));
    t.maxX = int(std::min<int64_t>(dc.clipX1 - 1, (maxXf - half) >> s));
    t.maxY = int(std::min<int64_t>(dc.clipY1 - 1, (maxYf - half) >> s));
    if (t.minX > t.maxX || t.minY > t.maxY) return false;

    for (int e = 0; e < 3; ++e) {
        const int a = e, b = e == 2 ? 0 : e + 1;
        const int64_t dxe = X[b] - X[a], dye = Y[b] - Y[a];
        const bool topLeft = dye < 0 || (dye == 0 && dxe > 0);
        t.A[e] = -dye;
        t.B[e] = dxe;
        t.C[e] = dye * X[a] - dxe * Y[a] - (topLeft ? 0 : 1);
    }

    const double inv = 1.0 / double(one);  // a power of two: exact, folded per s
    const double x0 = double(X[0]) * inv, y0 = double(Y[0]) * inv;
    const Geometry g{double(X[1]) * inv - x0, double(Y[1]) * inv - y0,
                     double(X[2]) * inv - x0, double(Y[2]) * inv - y0, invArea};
    t.x0 = float(x0);
    t.y0 = float(y0);

    if (dc.depthOn) {
        const double a0 = v[0]->wz, a1 = v[1]->wz, a2 = v[2]->wz;
        const double da1 = a1 - a0, da2 = a2 - a0;
        t.zc = a0;
        t.zdx = (da1 * g.dy2 - da2 * g.dy1) * invArea;
        t.zdy = (da2 * g.dx1 - da1 * g.dx2) * invArea;
    } else {
        t.zc = t.zdx = t.zdy = 0.0;
    }
    const bool needInvW = (dc.gouraud && dc.perspectiveColor) || dc.numTexSets > 0;
    if (needInvW)
        t.invW = makePlane(v[0]->invW, v[1]->invW, v[2]->invW, g.dx1, g.dy1, g.dx2, g.dy2,
                           invArea);
    else
        t.invW = Plane{};
    const double w0 = v[0]->invW, w1 = v[1]->invW, w2 = v[2]->invW;
    const int colors = dc.gouraud ? (dc.needSpecular ? 8 : 4) : 0;
    for (int a = colors; a < kColorAttrs; ++a)
        t.colorC[a] = t.colorDx[a] = t.colorDy[a] = 0.0f;
    for (int a = 0; a < colors; a += 4) {
        if constexpr (kAvx2)
            colorPlanes4Avx2(&v[0]->attr[a], &v[1]->attr[a], &v[2]->attr[a], w0, w1, w2,
                             dc.perspectiveColor, g, &t.colorC[a], &t.colorDx[a],
                             &t.colorDy[a]);
        else
            colorPlanes4Sse2(&v[0]->attr[a], &v[1]->attr[a], &v[2]->attr[a], w0, w1, w2,
                             dc.perspectiveColor, g, &t.colorC[a], &t.colorDx[a],
                             &t.colorDy[a]);
    }
    t.texPlanes = uint32_t(texPool.size());
    if (dc.numAttrs > kColorAttrs) {
        texPool.resize(texPool.size() + size_t(dc.numAttrs - kColorAttrs));
        Plane* out = texPool.data() + t.texPlanes;
        alignas(16) float c[4], dx[4], dy[4];
        int a = kColorAttrs;
        for (; a + 4 <= dc.numAttrs; a += 4, out += 4) {  // one set per step
            if constexpr (kAvx2)
                colorPlanes4Avx2(&v[0]->attr[a], &v[1]->attr[a], &v[2]->attr[a], w0, w1,
                                 w2, true, g, c, dx, dy);
            else
                colorPlanes4Sse2(&v[0]->attr[a], &v[1]->attr[a], &v[2]->attr[a], w0, w1,
                                 w2, true, g, c, dx, dy);
            for (int k = 0; k < 4; ++k) out[k] = Plane{c[k], dx[k], dy[k]};
        }
        for (; a < dc.numAttrs; ++a, ++out)  // a partial set (only programmable varyings)
            *out = makePlane(v[0]->attr[a] * w0, v[1]->attr[a] * w1, v[2]->attr[a] * w2,
                             g.dx1, g.dy1, g.dx2, g.dy2, invArea);
    }
    t.flatDiffuse = flatDiffuse;
    t.flatSpecular = flatSpecular;
    out.push_back(t);
    return true;
}

template <bool kAvx2>
[[gnu::always_inline]] inline void setupRangeBody(
    const DrawContext& dc, Primitive primitive, uint32_t begin, uint32_t end,
    std::span<const uint32_t> indices, std::span<const Vertex> vertices,
    const ProcessedVertex* processed, std::vector<SetupTriangle>& out,
    std::vector<Plane>& texPool, GeometryCounters& gc) {
    out.reserve(out.size() + (end - begin));
    const bool indexed = !indices.empty();
    for (uint32_t i = begin; i < end; ++i) {
        const std::array<uint32_t, 3> tv = triangleVertices(primitive, i);
        const uint32_t a = indexed ? indices[tv[0]] : tv[0];
        const uint32_t b = indexed ? indices[tv[1]] : tv[1];
        const uint32_t c = indexed ? indices[tv[2]] : tv[2];
        // The provoking vertex's bytes matter only for flat shading.
        const Rgba8 flatD = dc.gouraud ? Rgba8{} : vertices[a].diffuse;
        const Rgba8 flatS = dc.gouraud ? Rgba8{} : vertices[a].specular;
        const ProcessedVertex& pa = processed[a];
        const ProcessedVertex& pb = processed[b];
        const ProcessedVertex& pc = processed[c];
        if (pa.valid && pb.valid && pc.valid &&
            (pa.outcode | pb.outcode | pc.outcode) == 0) {
            ++gc.submitted;
            if (setupFastBody<kAvx2>(dc, pa, pb, pc, flatD, flatS, out, texPool))
                ++gc.drawn;
            else
                ++gc.culled;
        } else {
            clipAndSetup(dc, pa, pb, pc, flatD, flatS, out, texPool, gc);
        }
    }
}

__attribute__((target("avx2"))) void setupRangeAvx2(
    const DrawContext& dc, Primitive primitive, uint32_t begin, uint32_t end,
    std::span<const uint32_t> indices, std::span<const Vertex> vertices,
    const ProcessedVertex* processed, std::vector<SetupTriangle>& out,
    std::vector<Plane>& texPool, GeometryCounters& gc) {
    setupRangeBody<true>(dc, primitive, begin, end, indices, vertices, processed, out,
                         texPool, gc);
}

void setupRangeSse2(const DrawContext& dc, Primitive primitive, uint32_t begin,
                    uint32_t end, std::span<const uint32_t> indices,
                    std::span<const Vertex> vertices, const ProcessedVertex* processed,
                    std::vector<SetupTriangle>& out, std::vector<Plane>& texPool,
                    GeometryCounters& gc) {
    setupRangeBody<false>(dc, primitive, begin, end, indices, vertices, processed, out,
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

}  // namespace rg::raster::detail
