// 000 §5 "Adaptive Tessellation": ray paths are traced only at the vertices of a lens
// object, from the actual viewpoint, and a triangle whose vertices' paths differ is split
// where its edges are still long on screen.
//
//   front-facing triangles ─▶ trace their vertices (visibility ray + two greedy paths)
//     ─▶ per level: a triangle whose vertex paths differ (either term: path length, the
//        reflect/refract choice at an interface, exit directions > 3° apart) and that is
//        not wholly occluded splits its edges of screen length ≥ τ at their midpoints
//        (1-to-4, 1-to-3 or 1-to-2), midpoints found or made through the edge hash and
//        traced once
//     ─▶ t-junction removal: each leaf's boundary gathered from the edge hash by recursive
//        midpoint queries, the polygon cut into triangles (ears), so every interior edge of
//        the output lies in exactly two triangles.
//
// Levels are processed one at a time so the tracing of a level's new vertices runs in
// parallel while the decisions and the hash stay serial (deterministic vertex numbering).
#pragma once

#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "lens_scene.h"
#include "raycore/counters.h"
#include "raycore/tracer_two_term.h"

namespace rg::hybrid {

struct TessellationSettings {
    float tau = 3.0f;                // subdivision stops below this edge length, subpixels
    float exitAngleDegrees = 3.0f;   // 000 §5: exit directions further apart differ
    int maxLevel = 12;               // a cap the paper does not need to state (our choice)
    int maxDepth = 8;                // interfaces per path, as the ray tracer
    int threads = 0;                 // 0: all
};

// The device's view of the mesh: view·projection (Direct3D clip, 0 ≤ z ≤ w) and the pixel
// grid the device draws (display size × subsamples: τ is measured on it).
struct ScreenSpace {
    glm::mat4 viewProjection{1.0f};
    int width = 0, height = 0;
    glm::vec3 eye{0.0f};
};

// A vertex's run-time trace: its two paths and whether the eye sees it.
struct VertexTrace {
    ray::LensPaths paths;
    bool visible = false;
};

struct TessellationStats {
    int64_t baseTriangles = 0, frontTriangles = 0;
    int64_t baseVerticesTraced = 0, midpointsTraced = 0;
    int64_t splits4 = 0, splits3 = 0, splits2 = 0;
    int64_t leavesSame = 0, leavesSmall = 0, leavesOccluded = 0, leavesCapped = 0;
    int64_t outputTriangles = 0, tjunctionPolygons = 0;
    int64_t creaseVertices = 0;      // made for a side of a crease the other side split
    int maxLevel = 0;
    ray::RayCounts rays;             // visibility rays as Primary, path rays by kind
    double traceSeconds = 0, tessellateSeconds = 0;
    int64_t verticesTraced() const { return baseVerticesTraced + midpointsTraced; }
};

struct AdaptiveMesh {
    std::vector<glm::vec3> positions, normals;  // the object's vertices, then midpoints
    std::vector<uint32_t> positionId;            // per vertex: its position (LensObject)
    std::vector<VertexTrace> traces;             // meaningful where traced[i]
    std::vector<uint8_t> traced;
    std::vector<uint32_t> indices;               // conforming front-facing triangles
    std::vector<uint8_t> triangleLevel;          // subdivision level of each (Figure 5)
    std::vector<uint32_t> leaves;                // the subdivision's leaves (3 vertices
                                                 // each), before t-junction removal
    TessellationStats stats;
};

// Two paths of one term differ (000 §5): one is valid and the other not, their lengths or
// greedy choices differ, or their exit directions are more than the threshold apart
// (cosThreshold = cos of it).
bool pathsDiffer(const ray::PathSummary& a, const ray::PathSummary& b, float cosThreshold);
bool tracesDiffer(const VertexTrace& a, const VertexTrace& b, float cosThreshold);

// The run-time trace of one vertex seen from `eye`: a visibility ray against `visibility`
// (every lens object) and the two paths through `local` (the object alone, object 0).
// A vertex normal facing away from the eye (a silhouette vertex: the interpolated normal
// is not the face's) is tilted towards the eye until d·n = −0.02 (our choice).
VertexTrace traceVertex(const glm::vec3& p, const glm::vec3& n, const glm::vec3& eye,
                        const ray::Accel& local, const ray::Material& material,
                        const ray::Accel& visibility, int maxDepth, ray::RayCounts& counts);

AdaptiveMesh tessellateAdaptively(const LensObject& lens, const ray::Accel& local,
                                  const ray::Accel& visibility, const ScreenSpace& screen,
                                  const TessellationSettings& settings);

// The edge hash of 000 §5: an unordered vertex pair → the midpoint vertex. Open
// addressing, linear probing, power-of-two capacity.
class EdgeHash {
  public:
    static constexpr uint32_t kNone = ~0u;
    explicit EdgeHash(size_t expected = 1024);
    uint32_t find(uint32_t a, uint32_t b) const;
    void insert(uint32_t a, uint32_t b, uint32_t midpoint);  // (a, b) must be absent
    size_t size() const { return size_; }
    // Every vertex along edge (a, b), from a up to but excluding b, by recursive midpoint
    // queries (000 §5: "Recursive querying yields all vertices along the edge").
    void edgeVertices(uint32_t a, uint32_t b, std::vector<uint32_t>& out) const;

  private:
    static uint64_t key(uint32_t a, uint32_t b) {
        return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a;
    }
    void grow();
    std::vector<uint64_t> keys_;
    std::vector<uint32_t> values_;
    size_t size_ = 0;
};

// Cuts a triangle whose edges carry extra vertices into triangles without t-junctions
// and without zero-area pieces: `ring` is the boundary (corner 0, the vertices of edge 0,
// corner 1, ..., counter-clockwise), `edgeMask` per ring vertex the triangle edges it lies
// on (bit e: edge e = corner e → corner e+1; corners lie on two). Three ring vertices are
// collinear exactly when they share an edge bit. Ears of the best smallest angle first.
void triangulateRing(const std::vector<uint32_t>& ring, const std::vector<uint8_t>& edgeMask,
                     const std::vector<glm::vec3>& positions, std::vector<uint32_t>& out);

}  // namespace rg::hybrid
