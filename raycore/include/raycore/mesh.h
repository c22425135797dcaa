// Plain triangle meshes shared by the rasterizer and the ray tracer: positions, per-vertex
// normals, uvs and indices, with named parts (triangle ranges) so that a demo can select
// e.g. the teapot's lid apart from its body (001 §6 decomposes the teapot that way).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace rg::ray {

// A contiguous range of triangles with a name. Parts never overlap and, when present,
// cover the whole mesh, so every triangle belongs to exactly one part.
struct MeshPart {
    std::string name;
    uint32_t firstTriangle = 0;
    uint32_t triangleCount = 0;
    friend bool operator==(const MeshPart&, const MeshPart&) = default;
};

// Where a mesh came from, kept so that a scene written back to JSON names the generator or
// the file rather than a list of vertices (docs/scene-format.md).
struct MeshSource {
    std::string kind;                       // "file" or a built-in shape name ("sphere", ...)
    std::string path;                       // for "file": as written in the scene file
    std::map<std::string, double> params;   // for shapes: their parameters
    friend bool operator==(const MeshSource&, const MeshSource&) = default;
};

struct Mesh {
    std::string name;
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // per vertex, unit length; same count as positions
    std::vector<glm::vec2> uvs;      // per vertex; same count as positions
    std::vector<uint32_t> indices;   // three per triangle, counter-clockwise seen from outside
    std::vector<MeshPart> parts;     // optional; see MeshPart
    MeshSource source;

    size_t triangleCount() const { return indices.size() / 3; }
    // The part holding triangle `tri`, as an index into `parts` (0 when there are no parts).
    uint32_t partOfTriangle(uint32_t tri) const;
    // Index of the part named `name`, or -1.
    int findPart(const std::string& name) const;
};

// An empty box is lo = +∞, hi = −∞, the identities of min and max (±1e30 gave a mesh
// lying wholly past x = −1e30 an hi.x of −1e30).
struct Bounds {
    glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
    glm::vec3 center() const { return (lo + hi) * 0.5f; }
};

// Bad input is refused with rg::Error naming `what` (a file or object name) and the
// problem: empty mesh, index out of range, NaN/Inf position, count mismatches, and two
// geometric ones (docs/scene-format.md, "What is rejected"):
//
//  - an extent that is not finite in float arithmetic: over all positions, hi − lo on an
//    axis, or the length of the diagonal |hi − lo| = sqrt(dx² + dy² + dz²), is infinite
//    (Accel sizes its ray offsets by that length);
//  - a part (the whole mesh when it has no parts) without a triangle of non-zero area. A
//    triangle (p0, p1, p2) has non-zero area when n = (p1 − p0) × (p2 − p0) and its length
//    |n| = sqrt(n·n), every operation in float as Accel's face normal and completeMesh's
//    vertex normals compute them, give 0 < |n| < ∞; where |n| is 0 or ∞ the normal cannot
//    be normalised. Degenerate triangles among good ones are kept, as before: meshes carry
//    a few (the teapot's patches meet in points at the top of the lid and the middle of
//    the bottom: 152 of its 40,000 triangles), and dropping them would renumber the
//    triangles that parts and hits refer to.
void validateMesh(const Mesh& mesh, const std::string& what);

// validateMesh, then its two geometric rules again on the mesh as `transform` places it
// (positions m · (p, 1), as transformMesh and Accel compute them): a scene object scaled to
// nothing or past float's range. The transform's entries must be finite. Returns the
// placed mesh's bounds.
Bounds validatePlacedMesh(const Mesh& mesh, const glm::mat4& transform, const std::string& what);

// The extent rule above on bounds (the union of a scene's objects): rg::Error naming `what`.
void validateExtent(const Bounds& bounds, const std::string& what);

// Fills missing uvs with zeros and missing normals with area-weighted vertex normals.
void completeMesh(Mesh& mesh);

// True when every edge is shared by exactly two triangles with opposite orientations
// after welding positions that are bit-identical (a closed, oriented 2-manifold), the
// condition for a mesh to bound a volume of glass.
bool isClosedManifold(const Mesh& mesh);

// The triangles of one part as a mesh of their own (vertices renumbered, shared ones kept
// shared).
Mesh extractPart(const Mesh& mesh, uint32_t partIndex);

// Appends `other` (its parts keep their names; a mesh without parts becomes one part named
// after it).
void appendMesh(Mesh& mesh, const Mesh& other, const std::string& partName = {});

// Over all positions, unused ones included.
Bounds computeBounds(const Mesh& mesh);

// Σ area·centroid / Σ area over the triangles (of one part when part ≥ 0): 001 §4's
// environment-map origin ("an area-weighted average of the object's triangle centroids").
glm::vec3 areaWeightedCentroid(const Mesh& mesh, int part = -1);

// Applies an affine transform to positions and (by the inverse transpose) normals.
void transformMesh(Mesh& mesh, const glm::mat4& m);

}  // namespace rg::ray
