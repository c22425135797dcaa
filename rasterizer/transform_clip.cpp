// Vertex transform, primitive assembly and homogeneous clipping
// (docs/hardware.md, "Vertex transform and clipping").
#include <cmath>
#include <cstddef>
#include <cstring>
#include <type_traits>

#include <glm/mat3x3.hpp>

#include "pipeline.h"
#include "raster_span_avx2.h"
#include "simd_lanes.h"


namespace rg::raster::detail {

namespace {

bool finite(float v) { return std::isfinite(v); }

// Window position of a clip-space position: the D3D7 viewport transform
// (x right, y down, z in [MinZ, MaxZ]), or the identity for pre-transformed vertices.
void project(const DrawContext& dc, ProcessedVertex& v) {
    const glm::vec4& c = v.clip;
    if (dc.space == VertexSpace::Pretransformed) {
        v.wx = c.x / c.w;
        v.wy = c.y / c.w;
        v.wz = c.z / c.w;
    } else {
        float nx = c.x / c.w, ny = c.y / c.w, nz = c.z / c.w;
        v.wx = float(dc.vp.x) + (nx + 1.0f) * (0.5f * float(dc.vp.width));
        v.wy = float(dc.vp.y) + (1.0f - ny) * (0.5f * float(dc.vp.height));
        v.wz = dc.vp.minZ + nz * (dc.vp.maxZ - dc.vp.minZ);
    }
    v.invW = 1.0f / c.w;
    v.sx = snapToFixed(v.wx, dc.subpixelBits);
    v.sy = snapToFixed(v.wy, dc.subpixelBits);
}

float planeDistance(const glm::vec4& p, const glm::vec4& c) {
    return ((p.x * c.x + p.y * c.y) + p.z * c.z) + p.w * c.w;
}

uint32_t outcodeOf(const DrawContext& dc, const glm::vec4& clip) {
    uint32_t code = 0;
    for (int p = 0; p < 6; ++p)
        if (!(planeDistance(dc.planes[p], clip) >= 0.0f)) code |= 1u << p;
    return code;
}

// The point where edge in→out crosses a plane, always computed from the inside vertex so
// that the two triangles sharing a clipped edge get the same new vertex.
ProcessedVertex intersect(const DrawContext& dc, const ProcessedVertex& in, float dIn,
                          const ProcessedVertex& out, float dOut) {
    float t = dIn / (dIn - dOut);
    ProcessedVertex r;
    r.clip = in.clip + t * (out.clip - in.clip);
    for (int a = 0; a < dc.numAttrs; ++a) r.attr[a] = in.attr[a] + t * (out.attr[a] - in.attr[a]);
    project(dc, r);
    return r;
}

// The pixels a draw may write (viewport ∩ scissor ∩ target) and the clip planes: near,
// far and the guard band, shared by the fixed-function and programmable draws.
void setClipGeometry(DrawContext& dc, int width, int height, VertexSpace space,
                     const Viewport& vp, const Rect* scissor) {
    // int64: a scissor rectangle may lie anywhere, even near the int32 limits.
    int64_t x0 = std::max(0, vp.x), y0 = std::max(0, vp.y);
    int64_t x1 = std::min<int64_t>(width, int64_t(vp.x) + vp.width);
    int64_t y1 = std::min<int64_t>(height, int64_t(vp.y) + vp.height);
    if (scissor) {
        x0 = std::max<int64_t>(x0, scissor->x);
        y0 = std::max<int64_t>(y0, scissor->y);
        x1 = std::min<int64_t>(x1, int64_t(scissor->x) + scissor->width);
        y1 = std::min<int64_t>(y1, int64_t(scissor->y) + scissor->height);
    }
    dc.clipX0 = int(std::min<int64_t>(x0, width));
    dc.clipY0 = int(std::min<int64_t>(y0, height));
    dc.clipX1 = int(std::max<int64_t>(x1, 0));
    dc.clipY1 = int(std::max<int64_t>(y1, 0));

    const float G = float(kGuardBandPixels);
    dc.planes[0] = {0, 0, 1, 0};   // near: z ≥ 0 (Direct3D clip volume 0 ≤ z ≤ w)
    dc.planes[1] = {0, 0, -1, 1};  // far: z ≤ w
    if (space == VertexSpace::Pretransformed) {
        dc.planes[2] = {1, 0, 0, G};
        dc.planes[3] = {-1, 0, 0, G};
        dc.planes[4] = {0, 1, 0, G};
        dc.planes[5] = {0, -1, 0, G};
    } else {
        // window x = vx + (x/w + 1)·vw/2 ≥ −G  ⇔  x − kL·w ≥ 0, and so on.
        float kL = 2.0f * (-G - float(vp.x)) / float(vp.width) - 1.0f;
        float kR = 2.0f * (G - float(vp.x)) / float(vp.width) - 1.0f;
        float kT = 1.0f - 2.0f * (-G - float(vp.y)) / float(vp.height);
        float kB = 1.0f - 2.0f * (G - float(vp.y)) / float(vp.height);
        dc.planes[2] = {1, 0, 0, -kL};
        dc.planes[3] = {-1, 0, 0, kR};
        dc.planes[4] = {0, -1, 0, kT};
        dc.planes[5] = {0, 1, 0, -kB};
    }
}

}  // namespace

DrawContext makeDrawContext(const PipelineState& st, Framebuffer& fb, const tex::TextureUnits& tu,
                            Path path, VertexSpace space, const Viewport& vp, const Rect& scissor,
                            int subpixelBits) {
    DrawContext dc;
    dc.st = st;
    dc.fb = &fb;
    dc.tu = &tu;
    dc.path = path;
    dc.space = space;
    dc.vp = vp;
    dc.subpixelBits = subpixelBits;
    dc.passThrough = tu.passThrough();
    uint32_t sets = dc.passThrough ? 0u : tu.texCoordSetsUsed();
    for (int s = 0; s < tex::kMaxTexCoordSets; ++s)
        if (sets & (1u << s)) dc.texSets[dc.numTexSets++] = s;
    dc.numAttrs = kColorAttrs + 4 * dc.numTexSets;
    dc.gouraud = st.shade == ShadeMode::Gouraud;
    dc.perspectiveColor = st.perspectiveColor != 0;
    dc.needSpecular = st.specularEnable != 0 || !dc.passThrough;
    dc.depthOn = st.depthTest != 0 && fb.depthFormat() != DepthFormat::None;
    dc.depthMax = fb.depthMax();

    setClipGeometry(dc, fb.width(), fb.height(), space, vp, st.scissorTest ? &scissor : nullptr);
    return dc;
}

ProcessedVertex processVertex(const DrawContext& dc, const glm::mat4& worldViewProj,
                              const glm::mat4& worldView, const glm::mat3& normalMatrix,
                              const Vertex& v) {
    ProcessedVertex p;
    processVertexInto(dc, worldViewProj, worldView, normalMatrix, v, p);
    return p;
}

void processVertexInto(const DrawContext& dc, const glm::mat4& worldViewProj,
                       const glm::mat4& worldView, const glm::mat3& normalMatrix,
                       const Vertex& v, ProcessedVertex& p) {
    // Every field a later stage reads gets its value here, as in a fresh ProcessedVertex;
    // attr past numAttrs is never read and keeps whatever it held.
    p.wx = p.wy = p.wz = p.invW = 0.0f;
    p.sx = p.sy = 0;
    p.outcode = 0;
    const glm::vec4& in = v.position;
    tex::VertexEye eye;
    if (dc.space == VertexSpace::Pretransformed) {
        // XYZRHW: window x, y, z and RHW = 1/w. Held as the homogeneous point
        // (x·w, y·w, z·w, w) so that clipping is the same code for both spaces.
        p.valid = finite(in.x) && finite(in.y) && finite(in.z) && finite(in.w) && in.w != 0.0f;
        float w = 1.0f / in.w;
        p.valid = p.valid && finite(w);
        p.clip = glm::vec4(in.x * w, in.y * w, in.z * w, w);
        p.wx = in.x;
        p.wy = in.y;
        p.wz = in.z;
        p.invW = in.w;
        p.sx = snapToFixed(p.wx, dc.subpixelBits);
        p.sy = snapToFixed(p.wy, dc.subpixelBits);
        eye = {in, in, v.normal, v.normal};
    } else {
        glm::vec4 obj(in.x, in.y, in.z, 1.0f);
        p.valid = finite(in.x) && finite(in.y) && finite(in.z);
        p.clip = worldViewProj * obj;
        p.valid = p.valid && finite(p.clip.x) && finite(p.clip.y) && finite(p.clip.z) &&
                  finite(p.clip.w);
        if (p.valid) project(dc, p);
        if (dc.numTexSets > 0) {
            glm::vec3 n = normalMatrix * v.normal;
            float len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
            eye = {obj, worldView * obj, len > 0.0f ? n / len : n, v.normal};
        }
    }
    if (p.valid) p.outcode = outcodeOf(dc, p.clip);
    p.unclipped = unclippedVertex(p);
    const Rgba8 d = v.diffuse, s = v.specular;
    p.attr[0] = d.r; p.attr[1] = d.g; p.attr[2] = d.b; p.attr[3] = d.a;
    p.attr[4] = s.r; p.attr[5] = s.g; p.attr[6] = s.b; p.attr[7] = s.a;
    for (int k = 0; k < dc.numTexSets; ++k) {
        int set = dc.texSets[k];
        glm::vec4 tc = dc.tu->processVertexTexCoord(set, eye, v.tex[set]);
        for (int c = 0; c < 4; ++c) p.attr[kColorAttrs + 4 * k + c] = tc[c];
    }
}

// ---- the fast path's vertex pass ------------------------------------------------------
namespace {

using namespace lanes;

// processVertexInto's untransformed branch (numTexSets = 0) for v[0..7], lane k the
// scalar operations of vertex k in the same order: GLM's column sums
// (m0·x + m1·y) + (m2·z + m3·1), the divisions of project, snapToFixed in double, the
// outcode dot products summed left to right. No FMA (-ffp-contract=off; the AVX2 target
// does not include FMA).
// Out: ProcessedVertex (processVerticesFast) or FastVertex (processVerticesCompact, the
// same values in the fields it has). In: Vertex, or for FastVertex also VertexXyzDiffuse
// (toVertex's values: the same position, diffuse, specular 0).
template <class Out, class In>
RG_LANES void vertices8(const DrawContext& dc, const glm::mat4& m, const In* v, Out* out) {
    static_assert(offsetof(Vertex, position) == 0 && offsetof(VertexXyzDiffuse, position) == 0);
    // The eight positions as four 4×4 transposes of (x, y, z, w) rows, vertex k in lane k:
    // whole-vector loads and shuffles instead of 24 loads into single lanes.
    F32x4 pos[8];
    // (The fourth float is w, or VertexXyzDiffuse's colour bits: the transform reads
    // neither.)
    for (int k = 0; k < 8; ++k) std::memcpy(&pos[k], &v[k], sizeof(F32x4));
    const F32x8 r0 = __builtin_shufflevector(pos[0], pos[4], 0, 1, 2, 3, 4, 5, 6, 7);
    const F32x8 r1 = __builtin_shufflevector(pos[1], pos[5], 0, 1, 2, 3, 4, 5, 6, 7);
    const F32x8 r2 = __builtin_shufflevector(pos[2], pos[6], 0, 1, 2, 3, 4, 5, 6, 7);
    const F32x8 r3 = __builtin_shufflevector(pos[3], pos[7], 0, 1, 2, 3, 4, 5, 6, 7);
    // (x0 x1 y0 y1 | x4 x5 y4 y5), (x2 x3 y2 y3 | x6 x7 y6 y7), and the same for z, w.
    const F32x8 xy01 = __builtin_shufflevector(r0, r1, 0, 8, 1, 9, 4, 12, 5, 13);
    const F32x8 xy23 = __builtin_shufflevector(r2, r3, 0, 8, 1, 9, 4, 12, 5, 13);
    const F32x8 zw01 = __builtin_shufflevector(r0, r1, 2, 10, 3, 11, 6, 14, 7, 15);
    const F32x8 zw23 = __builtin_shufflevector(r2, r3, 2, 10, 3, 11, 6, 14, 7, 15);
    const F32x8 x = __builtin_shufflevector(xy01, xy23, 0, 1, 8, 9, 4, 5, 12, 13);
    const F32x8 y = __builtin_shufflevector(xy01, xy23, 2, 3, 10, 11, 6, 7, 14, 15);
    const F32x8 z = __builtin_shufflevector(zw01, zw23, 0, 1, 8, 9, 4, 5, 12, 13);
    I32x8 valid = finiteLanes(x) & finiteLanes(y) & finiteLanes(z);
    F32x8 c[4];
    for (int r = 0; r < 4; ++r)
        c[r] = (splat8(m[0][r]) * x + splat8(m[1][r]) * y) +
               (splat8(m[2][r]) * z + splat8(m[3][r]) * 1.0f);
    valid &= finiteLanes(c[0]) & finiteLanes(c[1]) & finiteLanes(c[2]) & finiteLanes(c[3]);

    // project(): the D3D7 viewport transform, then 1/w and the snapped position.
    const F32x8 nx = c[0] / c[3], ny = c[1] / c[3], nz = c[2] / c[3];
    const F32x8 wx = splat8(float(dc.vp.x)) + (nx + 1.0f) * (0.5f * float(dc.vp.width));
    const F32x8 wy = splat8(float(dc.vp.y)) + (1.0f - ny) * (0.5f * float(dc.vp.height));
    const F32x8 wz = splat8(dc.vp.minZ) + nz * (dc.vp.maxZ - dc.vp.minZ);
    const F32x8 invW = 1.0f / c[3];
    const double scale = double(int64_t{1} << dc.subpixelBits);
    const double limit = double(kGuardBandPixels + 1) * scale;
    // snapToFixed. Always inlined: a lambda does not inherit the AVX2 target of the body
    // it sits in, and an out-of-line call returning a 256-bit vector by value (at -O0)
    // would cross the ABI between AVX and non-AVX code (a crash in Debug builds).
    auto snap = [&](F32x4 f) __attribute__((always_inline)) {
        F64x4 d = __builtin_convertvector(f, F64x4) * scale + 0.5;
        d = d > -limit ? d : splat(-limit);  // also NaN
        d = d > limit ? splat(limit) : d;
        return toInt64(floorLanes(d));
    };
    const I64x4 sx[2] = {snap(lowHalf(wx)), snap(highHalf(wx))};
    const I64x4 sy[2] = {snap(lowHalf(wy)), snap(highHalf(wy))};

    // outcodeOf(): bit p where !(dot(plane p, clip) >= 0).
    I32x8 outcode = {};
    for (int p = 0; p < 6; ++p) {
        const glm::vec4& P = dc.planes[p];
        const F32x8 d = ((splat8(P.x) * c[0] + splat8(P.y) * c[1]) + splat8(P.z) * c[2]) +
                        splat8(P.w) * c[3];
        outcode |= ~(I32x8)(d >= 0.0f) & (1 << p);
    }
    outcode &= valid;
    const I32x8 unclipped = valid & (outcode == 0) & finiteLanes(wx) & finiteLanes(wy) &
                            finiteLanes(wz) & finiteLanes(invW);

    if constexpr (std::is_same_v<Out, FastVertex>) {
        // The eight records as columns (sx, sy, wz, invW | diffuse, specular, unclipped,
        // pad), an invalid vertex's first four zero as processVertexInto leaves them, then
        // transposed in registers and stored whole.
        static_assert(offsetof(FastVertex, diffuse) == 16 && offsetof(FastVertex, pad) == 28);
        const I32x4 sxLo = __builtin_convertvector(sx[0], I32x4), sxHi = __builtin_convertvector(sx[1], I32x4);
        const I32x4 syLo = __builtin_convertvector(sy[0], I32x4), syHi = __builtin_convertvector(sy[1], I32x4);
        const I32x8 cSx = __builtin_shufflevector(sxLo, sxHi, 0, 1, 2, 3, 4, 5, 6, 7) & valid;
        const I32x8 cSy = __builtin_shufflevector(syLo, syHi, 0, 1, 2, 3, 4, 5, 6, 7) & valid;
        const I32x8 cWz = (I32x8)wz & valid, cW = (I32x8)invW & valid;
        int32_t diffuse[8], specular[8] = {};
        for (int k = 0; k < 8; ++k) {
            std::memcpy(&diffuse[k], &v[k].diffuse, 4);
            if constexpr (std::is_same_v<In, Vertex>) std::memcpy(&specular[k], &v[k].specular, 4);
        }
        I32x8 cD, cS;
        std::memcpy(&cD, diffuse, sizeof cD);
        std::memcpy(&cS, specular, sizeof cS);
        const I32x8 cU = unclipped & 1, cP = {};
        // 4×4 transposes within each 128-bit half: records k and k + 4 per register.
        auto lo32 = [](I32x8 a, I32x8 b) __attribute__((always_inline)) {
            return __builtin_shufflevector(a, b, 0, 8, 1, 9, 4, 12, 5, 13);
        };
        auto hi32 = [](I32x8 a, I32x8 b) __attribute__((always_inline)) {
            return __builtin_shufflevector(a, b, 2, 10, 3, 11, 6, 14, 7, 15);
        };
        auto lo64 = [](I32x8 a, I32x8 b) __attribute__((always_inline)) {
            return __builtin_shufflevector(a, b, 0, 1, 8, 9, 4, 5, 12, 13);
        };
        auto hi64 = [](I32x8 a, I32x8 b) __attribute__((always_inline)) {
            return __builtin_shufflevector(a, b, 2, 3, 10, 11, 6, 7, 14, 15);
        };
        const I32x8 a01 = lo32(cSx, cSy), a23 = hi32(cSx, cSy);  // sx sy of 0 1 | 4 5 ...
        const I32x8 b01 = lo32(cWz, cW), b23 = hi32(cWz, cW);
        const I32x8 c01 = lo32(cD, cS), c23 = hi32(cD, cS);
        const I32x8 d01 = lo32(cU, cP), d23 = hi32(cU, cP);
        const I32x8 first[4] = {lo64(a01, b01), hi64(a01, b01), lo64(a23, b23), hi64(a23, b23)};
        const I32x8 second[4] = {lo64(c01, d01), hi64(c01, d01), lo64(c23, d23), hi64(c23, d23)};
        for (int k = 0; k < 4; ++k) {
            const I32x8 recK = __builtin_shufflevector(first[k], second[k], 0, 1, 2, 3, 8, 9, 10, 11);
            const I32x8 recK4 = __builtin_shufflevector(first[k], second[k], 4, 5, 6, 7, 12, 13, 14, 15);
            std::memcpy(static_cast<void*>(&out[k]), &recK, sizeof(FastVertex));
            std::memcpy(static_cast<void*>(&out[k + 4]), &recK4, sizeof(FastVertex));
        }
    } else {
        for (int k = 0; k < 8; ++k) {
            ProcessedVertex& p = out[k];
            p.clip = glm::vec4(c[0][k], c[1][k], c[2][k], c[3][k]);
            p.valid = valid[k] != 0;
            if (p.valid) {  // an invalid vertex keeps the zeros processVertexInto gives it
                p.wx = wx[k];
                p.wy = wy[k];
                p.wz = wz[k];
                p.invW = invW[k];
                p.sx = sx[k >> 2][k & 3];
                p.sy = sy[k >> 2][k & 3];
            } else {
                p.wx = p.wy = p.wz = p.invW = 0.0f;
                p.sx = p.sy = 0;
            }
            p.outcode = uint32_t(outcode[k]);
            p.unclipped = unclipped[k] != 0;
            const Rgba8 d = v[k].diffuse, s = v[k].specular;
            p.attr[0] = d.r; p.attr[1] = d.g; p.attr[2] = d.b; p.attr[3] = d.a;
            p.attr[4] = s.r; p.attr[5] = s.g; p.attr[6] = s.b; p.attr[7] = s.a;
        }
    }
}

template <bool kAvx2>
RG_LANES void verticesBody(const DrawContext& dc, const glm::mat4& worldViewProj,
                           const glm::mat4& worldView, const glm::mat3& normalMatrix,
                           std::span<const Vertex> in, size_t begin, size_t end,
                           ProcessedVertex* out) {
    size_t i = begin;
    if (dc.space == VertexSpace::Untransformed && dc.numTexSets == 0)
        for (; i + 8 <= end; i += 8) vertices8(dc, worldViewProj, &in[i], &out[i]);
    for (; i < end; ++i) processVertexInto(dc, worldViewProj, worldView, normalMatrix, in[i], out[i]);
}

// FastVertex from processVertexInto's result (the vertices the lanes leave over).
void compactFrom(const ProcessedVertex& p, const Vertex& v, FastVertex& f) {
    f.sx = int32_t(p.sx);
    f.sy = int32_t(p.sy);
    f.wz = p.wz;
    f.invW = p.invW;
    f.diffuse = v.diffuse;
    f.specular = v.specular;
    f.unclipped = p.unclipped ? 1u : 0u;
    f.pad = 0;
}

template <bool kAvx2>
RG_LANES void compactBody(const DrawContext& dc, const glm::mat4& worldViewProj,
                          const glm::mat4& worldView, const glm::mat3& normalMatrix,
                          const VertexSource& in, size_t begin, size_t end, FastVertex* out) {
    size_t i = begin;
    if (!in.full.empty())
        for (; i + 8 <= end; i += 8) vertices8(dc, worldViewProj, &in.full[i], &out[i]);
    else
        for (; i + 8 <= end; i += 8) vertices8(dc, worldViewProj, &in.xyzDiffuse[i], &out[i]);
    for (; i < end; ++i) {
        const Vertex v = in.at(i);
        ProcessedVertex p;
        processVertexInto(dc, worldViewProj, worldView, normalMatrix, v, p);
        compactFrom(p, v, out[i]);
    }
}

__attribute__((target("avx2"))) void compactAvx2(
    const DrawContext& dc, const glm::mat4& worldViewProj, const glm::mat4& worldView,
    const glm::mat3& normalMatrix, const VertexSource& in, size_t begin, size_t end,
    FastVertex* out) {
    compactBody<true>(dc, worldViewProj, worldView, normalMatrix, in, begin, end, out);
}

void compactSse2(const DrawContext& dc, const glm::mat4& worldViewProj,
                 const glm::mat4& worldView, const glm::mat3& normalMatrix,
                 const VertexSource& in, size_t begin, size_t end, FastVertex* out) {
    compactBody<false>(dc, worldViewProj, worldView, normalMatrix, in, begin, end, out);
}

__attribute__((target("avx2"))) void verticesAvx2(
    const DrawContext& dc, const glm::mat4& worldViewProj, const glm::mat4& worldView,
    const glm::mat3& normalMatrix, std::span<const Vertex> in, size_t begin, size_t end,
    ProcessedVertex* out) {
    verticesBody<true>(dc, worldViewProj, worldView, normalMatrix, in, begin, end, out);
}

void verticesSse2(const DrawContext& dc, const glm::mat4& worldViewProj,
                  const glm::mat4& worldView, const glm::mat3& normalMatrix,
                  std::span<const Vertex> in, size_t begin, size_t end, ProcessedVertex* out) {
    verticesBody<false>(dc, worldViewProj, worldView, normalMatrix, in, begin, end, out);
}

}  // namespace

void processVerticesFast(const DrawContext& dc, const glm::mat4& worldViewProj,
                         const glm::mat4& worldView, const glm::mat3& normalMatrix,
                         std::span<const Vertex> in, size_t begin, size_t end,
                         ProcessedVertex* out) {
    static const bool avx2 = haveAvx2();
    if (avx2)
        verticesAvx2(dc, worldViewProj, worldView, normalMatrix, in, begin, end, out);
    else
        verticesSse2(dc, worldViewProj, worldView, normalMatrix, in, begin, end, out);
}

void processVerticesCompact(const DrawContext& dc, const glm::mat4& worldViewProj,
                            const glm::mat4& worldView, const glm::mat3& normalMatrix,
                            const VertexSource& in, size_t begin, size_t end,
                            FastVertex* out) {
    static const bool avx2 = haveAvx2();
    if (avx2)
        compactAvx2(dc, worldViewProj, worldView, normalMatrix, in, begin, end, out);
    else
        compactSse2(dc, worldViewProj, worldView, normalMatrix, in, begin, end, out);
}

void clipAndSetup(const DrawContext& dc, const ProcessedVertex& v0, const ProcessedVertex& v1,
                  const ProcessedVertex& v2, Rgba8 flatDiffuse, Rgba8 flatSpecular,
                  std::vector<SetupTriangle>& out, std::vector<Plane>& texPool,
                  GeometryCounters& gc) {
    ++gc.submitted;
    if (!v0.valid || !v1.valid || !v2.valid) {
        ++gc.invalid;
        return;
    }
    // Outcodes (bit p set when the vertex is outside plane p), computed per vertex.
    const unsigned code[3] = {v0.outcode, v1.outcode, v2.outcode};
    if (code[0] & code[1] & code[2]) {  // all outside one plane: trivially rejected
        ++gc.culled;
        return;
    }
    if ((code[0] | code[1] | code[2]) == 0) {
        // Set up in place; a culled triangle is popped again.
        if (setupTriangle(dc, v0, v1, v2, flatDiffuse, flatSpecular, out.emplace_back(), texPool)) {
            ++gc.drawn;
        } else {
            out.pop_back();
            ++gc.culled;
        }
        return;
    }
    SetupTriangle t{};  // zero wherever setup computes nothing

    // Sutherland–Hodgman against each plane some vertex is outside of.
    ++gc.clipped;
    std::array<ProcessedVertex, 9> bufA, bufB;
    std::array<float, 9> dist;
    int n = 3;
    bufA[0] = v0; bufA[1] = v1; bufA[2] = v2;
    ProcessedVertex* cur = bufA.data();
    ProcessedVertex* nxt = bufB.data();
    unsigned planesToClip = code[0] | code[1] | code[2];
    for (int p = 0; p < 6 && n >= 3; ++p) {
        if (!(planesToClip & (1u << p))) continue;
        for (int i = 0; i < n; ++i) dist[i] = planeDistance(dc.planes[p], cur[i].clip);
        int m = 0;
        for (int i = 0; i < n; ++i) {
            int j = (i + 1) % n;
            bool inI = dist[i] >= 0.0f, inJ = dist[j] >= 0.0f;
            if (inI) nxt[m++] = cur[i];
            if (inI && !inJ) nxt[m++] = intersect(dc, cur[i], dist[i], cur[j], dist[j]);
            if (!inI && inJ) nxt[m++] = intersect(dc, cur[j], dist[j], cur[i], dist[i]);
        }
        n = m;
        std::swap(cur, nxt);
    }
    bool any = false;
    for (int k = 1; k + 1 < n; ++k)
        if (setupTriangle(dc, cur[0], cur[k], cur[k + 1], flatDiffuse, flatSpecular, t, texPool)) {
            out.push_back(t);
            any = true;
        }
    if (any)
        ++gc.drawn;
    else
        ++gc.culled;
}

DrawContext makeProgramDrawContext(int width, int height, const Viewport& vp, const Rect* scissor,
                                   CullMode cull, int subpixelBits, int varyingFloats, bool depth,
                                   Path path) {
    DrawContext dc;
    dc.st.cull = cull;
    dc.path = path;
    dc.space = VertexSpace::Untransformed;
    dc.vp = vp;
    dc.subpixelBits = subpixelBits;
    dc.passThrough = false;
    // Varyings ride in the texture-coordinate slots: every one perspective-correct, no
    // colour planes. numTexSets only has to be non-zero for setup to build the 1/w plane.
    dc.numTexSets = varyingFloats > 0 ? 1 : 0;
    dc.numAttrs = kColorAttrs + varyingFloats;
    dc.gouraud = false;
    dc.perspectiveColor = false;
    dc.needSpecular = false;
    dc.depthOn = depth;
    setClipGeometry(dc, width, height, VertexSpace::Untransformed, vp, scissor);
    return dc;
}

void projectProgramVertex(const DrawContext& dc, ProcessedVertex& v) {
    const glm::vec4& c = v.clip;
    v.valid = finite(c.x) && finite(c.y) && finite(c.z) && finite(c.w);
    if (!v.valid) return;
    project(dc, v);
    v.outcode = outcodeOf(dc, v.clip);
}

}  // namespace rg::raster::detail
