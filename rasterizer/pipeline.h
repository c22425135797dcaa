// Internal to rasterizer/: the values that flow between the stages of one draw call.
//
//   Device::draw ─▶ transform_clip.cpp (ProcessedVertex, clip polygon)
//                ─▶ setup_triangle.cpp (SetupTriangle: fixed-point edges, attribute planes)
//                ─▶ raster_reference.cpp  or  raster_tiles.cpp (2×2 quads)
//                ─▶ fragment_quad.h (texture stages, specular, alpha, depth, blend, mask)
//
// Both raster paths consume the same SetupTriangle and call the same processQuad(), so
// the only thing they may differ in is which quads they visit and in what order across
// tiles; docs/hardware.md explains why that cannot change a byte.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "core/color.h"
#include "core/path.h"
#include "rasterizer/counters.h"
#include "rasterizer/framebuffer.h"
#include "rasterizer/state.h"
#include "rasterizer/vertex.h"
#include "texunit/texture_units.h"

namespace rg::raster::detail {

// Guard band: window coordinates are clipped to [−16384, 16384] pixels in x and y before
// snapping. With 8 subpixel bits a snapped coordinate needs 23 bits with sign, an edge
// coefficient 24 bits and an edge value |E| < 2^48: int64 holds every edge function with
// 15 bits to spare (docs/hardware.md, "Setup and rasterization").
constexpr int kGuardBandPixels = 16384;

// Interpolated attributes per vertex: diffuse RGBA, specular RGBA (0..255 scale), then
// 4 components for each texture-coordinate set in use, in set order.
constexpr int kColorAttrs = 8;
constexpr int kMaxAttrs = kColorAttrs + 4 * tex::kMaxTexCoordSets;

struct ProcessedVertex {
    glm::vec4 clip{0.0f};        // homogeneous clip position (pre-transformed: w = 1/RHW)
    float wx = 0, wy = 0, wz = 0;  // window position
    float invW = 0;              // 1/w (RHW)
    int64_t sx = 0, sy = 0;      // window position snapped to fixed point (snapToFixed)
    uint32_t outcode = 0;        // bit p: outside clip plane p (computed once per vertex)
    bool valid = true;           // finite position, finite clip coordinates
    // valid, inside every clip plane (outcode 0) and a finite window position and 1/w: a
    // triangle of three such vertices needs no clipping and no checks in the fast setup
    // (setupTrianglesFast). Set by processVertexInto; false on vertices the clipper makes.
    bool unclipped = false;
    std::array<float, kMaxAttrs> attr{};
};

// Round to the nearest 1/2^s pixel, halves up: floor(x·2^s + ½), exact in double. The
// clamp only matters for points the clipper placed a rounding error outside the guard
// band (and for non-finite positions, which setup rejects anyway); it keeps every
// snapped coordinate inside the int64 bound above.
inline int64_t snapToFixed(float x, int s) {
    const double scale = double(int64_t{1} << s);
    const double limit = double(kGuardBandPixels + 1) * scale;
    double v = double(x) * scale + 0.5;
    if (!(v > -limit)) v = -limit;  // also NaN
    if (v > limit) v = limit;
    // floor for the clamped range: truncate, then step down for negative fractions.
    int64_t t = int64_t(v);
    return double(t) > v ? t - 1 : t;
}

// The fast path's vertex record for draws of untransformed vertices without texture
// coordinates (compactVertices): only what the four-triangle setup reads of a vertex that
// needs no clipping, 32 bytes instead of ProcessedVertex's 216, so that a mesh's vertices
// take a seventh of the cache and memory traffic (measured: small_triangles' setup
// waited on vertex loads). sx, sy, wz and invW are ProcessedVertex's, exact in int32 for
// subpixelBits ≤ 8 (|sx| ≤ 16385·2^8); the colours stay bytes (attr[0..7] is float() of
// them). A triangle with a vertex that is not `unclipped` recomputes its three
// ProcessedVertex with processVertexInto and takes clipAndSetup.
struct alignas(32) FastVertex {  // aligned: one cache line holds two whole records
    int32_t sx, sy;
    float wz, invW;
    Rgba8 diffuse, specular;
    uint32_t unclipped;  // 1: ProcessedVertex::unclipped
    uint32_t pad;
};
static_assert(sizeof(FastVertex) == 32);

// The definition of ProcessedVertex::unclipped.
inline bool unclippedVertex(const ProcessedVertex& p) {
    return p.valid && p.outcode == 0 && std::isfinite(p.wx) && std::isfinite(p.wy) &&
           std::isfinite(p.wz) && std::isfinite(p.invW);
}

// Per-draw constants shared by every stage.
struct DrawContext {
    PipelineState st;
    Framebuffer* fb = nullptr;
    const tex::TextureUnits* tu = nullptr;
    Path path = Path::Reference;
    VertexSpace space = VertexSpace::Untransformed;
    Viewport vp;
    int subpixelBits = 4;
    bool passThrough = true;      // no texture stage: fragment colour = diffuse
    int numTexSets = 0;
    std::array<int, tex::kMaxTexCoordSets> texSets{};  // which sets, in order
    int numAttrs = kColorAttrs;
    bool gouraud = true;
    bool perspectiveColor = true;
    bool needSpecular = false;    // specular add on, or a texture stage may read it
    bool depthOn = false;         // depth test with a depth buffer present
    uint32_t depthMax = 0;
    // Pixels that may be written: viewport ∩ scissor ∩ target, [x0, x1) × [y0, y1).
    int clipX0 = 0, clipY0 = 0, clipX1 = 0, clipY1 = 0;
    // Clip planes (inside: dot(plane, clip) ≥ 0): near, far, guard band left, right,
    // top, bottom.
    std::array<glm::vec4, 6> planes{};
    // Device::setFragmentObserver hook; only the reference raster loop calls it.
    const std::function<void(const tex::FragmentQuad&, uint8_t)>* fragmentObserver = nullptr;
};

// a(x, y) = c + dx·fx + dy·fy with fx = (x + ½) − x0 and fy = (y + ½) − y0 relative to
// the snapped position of the triangle's first vertex, all in single precision.
struct Plane {
    float c = 0, dx = 0, dy = 0;
    float at(float fx, float fy) const { return (c + dx * fx) + dy * fy; }
};

// The plane through (0,0,a0), (dx1,dy1,a1), (dx2,dy2,a2), in double, stored in single;
// invArea = 1/(dx1·dy2 − dx2·dy1) is computed once per triangle (setupTriangle).
inline Plane makePlane(double a0, double a1, double a2, double dx1, double dy1, double dx2,
                       double dy2, double invArea) {
    double da1 = a1 - a0, da2 = a2 - a0;
    Plane p;
    p.c = float(a0);
    p.dx = float((da1 * dy2 - da2 * dy1) * invArea);
    p.dy = float((da2 * dx1 - da1 * dx2) * invArea);
    return p;
}

// No member initialisers: `SetupTriangle t{}` and emplace_back() zero every field (value-
// initialisation), while the fast setup constructs with NoInit and writes every field
// itself, without first zeroing 256 bytes per triangle (setup_simd.cpp).
struct SetupTriangle {
    struct NoInit {};
    SetupTriangle() = default;
    explicit SetupTriangle(NoInit) {}

    // Edge i: E(X, Y) = C + A·X + B·Y on fixed-point sample positions; covered ⇔ E ≥ 0
    // (C carries the −1 of the top-left rule for edges that are not top or left).
    std::array<int64_t, 3> A, B, C;
    int minX, minY, maxX, maxY;  // inclusive pixel box, ∩ clip rect
    float x0, y0;                // snapped first vertex, pixels
    Plane invW;                  // 1/w
    // The triangle's coverage of the one even-aligned 2×2 quad its box lies in, or 0 when
    // the box spans more than one quad (quadCoverageOf). Computed at setup, where the fast
    // path has four triangles' edges in SIMD lanes, so that the rasterizer's single-quad
    // kernel (the common case of dense meshes) reads four bits instead of evaluating twelve
    // edge values; in the padding before colorC, on the cache line of the box and 1/w.
    uint32_t quadCoverage;
    // Colour planes (a/w when perspective-correct, else a), diffuse RGBA then specular
    // RGBA, stored as three arrays so that the fast path evaluates 4 channels per SSE op
    // with exactly the scalar operations of Plane::at. In this order, the fields a
    // Gouraud quad without depth or specular reads (edges, box, x0, y0, 1/w, diffuse
    // planes) lie in the first three of the four cache lines.
    alignas(16) std::array<float, kColorAttrs> colorC, colorDx, colorDy;
    double zc, zdx, zdy;         // window z plane, double precision
    Rgba8 flatDiffuse, flatSpecular;
    uint32_t texPlanes;          // first of 4·numTexSets planes in the draw's texture pool
    Plane color(int a) const { return Plane{colorC[a], colorDx[a], colorDy[a]}; }
};
static_assert(sizeof(SetupTriangle) == 256, "quadCoverage sits in padding");

// The pixels of the even-aligned 2×2 quad (qx, qy) inside all three edges of t: bit i for
// pixel (qx + (i & 1), qy + (i >> 1)) when all three E ≥ 0 at its centre, i.e. when the OR
// of the three has its sign bit clear.
inline unsigned quadEdgeCoverage(const SetupTriangle& t, int qx, int qy, int s) {
    const int64_t half = int64_t{1} << (s - 1);
    const int64_t X = (int64_t(qx) << s) + half, Y = (int64_t(qy) << s) + half;
    int64_t any[4] = {0, 0, 0, 0};
    for (int e = 0; e < 3; ++e) {
        const int64_t e0 = t.C[e] + t.A[e] * X + t.B[e] * Y;
        const int64_t sx = t.A[e] << s, sy = t.B[e] << s;
        any[0] |= e0;
        any[1] |= e0 + sx;
        any[2] |= e0 + sy;
        any[3] |= (e0 + sx) + sy;
    }
    return unsigned(any[0] >= 0) | unsigned(any[1] >= 0) << 1 | unsigned(any[2] >= 0) << 2 |
           unsigned(any[3] >= 0) << 3;
}

// SetupTriangle::quadCoverage from the edges and the box: when the box lies in one
// even-aligned 2×2 quad (qx, qy), its quadEdgeCoverage limited to the pixels inside the
// box; else 0.
inline uint32_t quadCoverageOf(const SetupTriangle& t, int s) {
    if (t.maxX > (t.minX | 1) || t.maxY > (t.minY | 1)) return 0;
    const int qx = t.minX & ~1, qy = t.minY & ~1;
    uint32_t coverage = quadEdgeCoverage(t, qx, qy, s);
    if (qx < t.minX) coverage &= 0xA;  // column qx outside the box
    if (qx + 1 > t.maxX) coverage &= 0x5;
    if (qy < t.minY) coverage &= 0xC;
    if (qy + 1 > t.maxY) coverage &= 0x3;
    return coverage;
}

// Geometry counters of one batch of triangles.
struct GeometryCounters {
    uint64_t submitted = 0, culled = 0, clipped = 0, drawn = 0, invalid = 0;
    void add(const GeometryCounters& o) {
        submitted += o.submitted; culled += o.culled; clipped += o.clipped;
        drawn += o.drawn; invalid += o.invalid;
    }
};

struct RasterCounters {
    uint64_t generated = 0, written = 0, blendOps = 0;
    void add(const RasterCounters& o) {
        generated += o.generated; written += o.written; blendOps += o.blendOps;
    }
};

// ---- transform_clip.cpp ----------------------------------------------------------------
DrawContext makeDrawContext(const PipelineState& st, Framebuffer& fb, const tex::TextureUnits& tu,
                            Path path, VertexSpace space, const Viewport& vp, const Rect& scissor,
                            int subpixelBits);
// Transforms one submitted vertex (world·view·projection, or the pre-transformed
// XYZRHW reading), runs texture-coordinate generation and computes its window position.
ProcessedVertex processVertex(const DrawContext& dc, const glm::mat4& worldViewProj,
                              const glm::mat4& worldView, const glm::mat3& normalMatrix,
                              const Vertex& v);
// processVertex writing into `p` (the fast path's vertex array) instead of returning a
// fresh, zeroed ProcessedVertex: the same values in every field a later stage reads.
void processVertexInto(const DrawContext& dc, const glm::mat4& worldViewProj,
                       const glm::mat4& worldView, const glm::mat3& normalMatrix,
                       const Vertex& v, ProcessedVertex& p);
// processVertexInto for vertices [begin, end) of `in` into the same slots of `out`: eight
// vertices per SIMD iteration (AVX2 when the CPU has it, else SSE2) for untransformed
// vertices without texture coordinates, each lane the scalar operations in order, so the
// same values in every field (tests/rasterizer/test_setup_simd.cpp); processVertexInto
// for the rest.
void processVerticesFast(const DrawContext& dc, const glm::mat4& worldViewProj,
                         const glm::mat4& worldView, const glm::mat3& normalMatrix,
                         std::span<const Vertex> in, size_t begin, size_t end,
                         ProcessedVertex* out);
// Whether a draw's fast path uses FastVertex records (compactVertices,
// setupTrianglesCompact) instead of ProcessedVertex.
inline bool compactVertices(const DrawContext& dc) {
    return dc.space == VertexSpace::Untransformed && dc.numTexSets == 0 &&
           dc.numAttrs == kColorAttrs && dc.subpixelBits <= 8;
}
// The vertices of a draw as submitted: Vertex records, or D3DFVF_XYZ | D3DFVF_DIFFUSE
// ones, which only the compact fast path reads as they are (Device::Impl::draw gives
// every other path toVertex of each).
struct VertexSource {
    std::span<const Vertex> full;
    std::span<const VertexXyzDiffuse> xyzDiffuse;  // when `full` is empty
    size_t size() const { return full.empty() ? xyzDiffuse.size() : full.size(); }
    Vertex at(size_t i) const { return full.empty() ? toVertex(xyzDiffuse[i]) : full[i]; }
};

// processVerticesFast for a draw where compactVertices(dc): the FastVertex of vertices
// [begin, end) of `in`, the same values as the fields of processVertexInto's result for
// in.at(i).
void processVerticesCompact(const DrawContext& dc, const glm::mat4& worldViewProj,
                            const glm::mat4& worldView, const glm::mat3& normalMatrix,
                            const VertexSource& in, size_t begin, size_t end,
                            FastVertex* out);
// The programmable pipeline (programmable.cpp) reuses clipping and setup: a context for a
// target of width×height whose `varyingFloats` attributes (from attr[kColorAttrs]) are all
// interpolated perspective-correctly, and the window position, snapped position and
// outcodes of a vertex whose clip position a vertex program wrote.
DrawContext makeProgramDrawContext(int width, int height, const Viewport& vp, const Rect* scissor,
                                   CullMode cull, int subpixelBits, int varyingFloats, bool depth,
                                   Path path);
void projectProgramVertex(const DrawContext& dc, ProcessedVertex& v);
// Primitive assembly: vertex numbers of triangle `i` and its flat-shading (provoking)
// vertex; the provoking vertex is always element 0 of the returned order.
inline uint32_t triangleCount(Primitive p, uint32_t n) {
    switch (p) {
        case Primitive::TriangleList: return n / 3;
        case Primitive::TriangleStrip:
        case Primitive::TriangleFan: return n >= 3 ? n - 2 : 0;
    }
    return 0;
}

// Strips: triangle i is (i, i+1, i+2), odd ones as (i, i+2, i+1) to keep the winding;
// the provoking vertex is the first (D3D7 flat shading). Fans: (i+1, i+2, 0), a rotation
// of (0, i+1, i+2) with the same winding, so that the provoking vertex is i+1, the
// Direct3D rule for flat-shaded fans.
inline std::array<uint32_t, 3> triangleVertices(Primitive p, uint32_t i) {
    switch (p) {
        case Primitive::TriangleList: return {3 * i, 3 * i + 1, 3 * i + 2};
        case Primitive::TriangleStrip:
            return (i & 1u) ? std::array<uint32_t, 3>{i, i + 2, i + 1}
                            : std::array<uint32_t, 3>{i, i + 1, i + 2};
        case Primitive::TriangleFan: return {i + 1, i + 2, 0};
    }
    return {0, 0, 0};
}

// Clips one triangle and sets up what reaches rasterization, appending to `out`.
void clipAndSetup(const DrawContext& dc, const ProcessedVertex& v0, const ProcessedVertex& v1,
                  const ProcessedVertex& v2, Rgba8 flatDiffuse, Rgba8 flatSpecular,
                  std::vector<SetupTriangle>& out, std::vector<Plane>& texPool,
                  GeometryCounters& gc);

// ---- setup_triangle.cpp ----------------------------------------------------------------
// Snaps, culls and computes edges and planes; false when culled or outside the clip rect.
bool setupTriangle(const DrawContext& dc, const ProcessedVertex& v0, const ProcessedVertex& v1,
                   const ProcessedVertex& v2, Rgba8 flatDiffuse, Rgba8 flatSpecular,
                   SetupTriangle& t, std::vector<Plane>& texPool);

// The fast path's primitive assembly and setup of triangles [begin, end) of a draw, in
// order: triangleVertices through `indices` (empty: none), the flat colours from the
// provoking vertex, the counters as clipAndSetup keeps them, with the setup inlined into
// the loop and the SIMD level chosen once per call (setup_triangle.cpp). Triangles that need no
// clipping get the same SetupTriangle and texture planes as setupTriangle, bit for bit,
// with the planes four channels per SIMD register; clipped ones take clipAndSetup (few,
// and the same bytes either way).
void setupTrianglesFast(const DrawContext& dc, Primitive primitive, uint32_t begin, uint32_t end,
                        std::span<const uint32_t> indices, std::span<const Vertex> vertices,
                        const ProcessedVertex* processed, std::vector<SetupTriangle>& out,
                        std::vector<Plane>& texPool, GeometryCounters& gc);
// setupTrianglesFast on FastVertex records (compactVertices(dc)): the same triangles,
// planes and counters; a triangle with a vertex that is not unclipped gets its vertices
// from processVertexInto(worldViewProj, worldView, normalMatrix) and takes clipAndSetup.
// prefetch = false when the caller has just written the records the triangles use (they
// are in cache; the prefetches' index loads and address arithmetic would be pure cost).
// band: only the triangles whose pixel box meets the rows of `dc`'s clip rect, counted
// as RowBand says (no prefetch).
struct RowBand;
void setupTrianglesCompact(const DrawContext& dc, Primitive primitive, uint32_t begin,
                           uint32_t end, std::span<const uint32_t> indices,
                           const VertexSource& vertices, const FastVertex* processed,
                           const glm::mat4& worldViewProj, const glm::mat4& worldView,
                           const glm::mat3& normalMatrix, std::vector<SetupTriangle>& out,
                           std::vector<Plane>& texPool, GeometryCounters& gc,
                           bool prefetch = true, const RowBand* band = nullptr);

// One of the horizontal bands of a draw's clip rect that the multi-thread path for meshes
// (device.cpp) gives each to one thread: that thread sets up and rasterizes, with a copy of
// the draw's context whose clip rows are the band's, every triangle whose box meets the
// band, so that no set-up triangle crosses cores and no binning or tile pass is needed. A
// triangle whose box meets several bands is set up in each, with the same edges and
// planes (the clip rect only bounds the box). Its counters belong to one band, the owner:
// the band holding the box's first row in the whole clip rect (the rect's nearest row for
// a box outside it), so that the owner's setup culls or draws it exactly as a setup over
// the whole rect would. Triangles that need clipping are counted by the first band.
struct RowBand {
    const DrawContext* full;    // the draw's context; its clip rect is not empty
    const uint32_t* rowSpans;   // rowSpanOf each vertex of the draw
};

// The rows a vertex gives the pixel box of its triangles, packed for the band selection
// (setup_simd.cpp): low 16 bits the first row of a box whose top vertex it is, high 16
// bits minus the last row of a box whose bottom vertex it is (negated so that the
// minimum of both halves over three vertices gives both ends); the floors are those of
// setupGeometry4's box, on the int32 snapped y (exact, |row| < 2^15 inside the guard
// band). A vertex that needs clipping spans every row.
inline uint32_t rowSpanOf(const FastVertex& v, int s) {
    if (!v.unclipped) return uint32_t(uint16_t(INT16_MIN)) | uint32_t(uint16_t(-INT16_MAX)) << 16;
    const int32_t half = int32_t{1} << (s - 1), one = int32_t{1} << s;
    const int32_t first = (v.sy - half + one - 1) >> s, last = (v.sy - half) >> s;
    return uint32_t(uint16_t(int16_t(first))) | uint32_t(uint16_t(int16_t(-last))) << 16;
}
// ---- raster_reference.cpp / raster_tiles.cpp -------------------------------------------
void rasterizeReference(const DrawContext& dc, const std::vector<SetupTriangle>& tris,
                        const std::vector<Plane>& texPool, RasterCounters& rc);

// ---- floor/ceil division for the span solver (exact on int64) --------------------------
inline int64_t floorDiv(int64_t a, int64_t b) {  // b > 0
    int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

}  // namespace rg::raster::detail
