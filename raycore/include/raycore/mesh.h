// Plain triangle meshes shared by the rasterizer and the ray tracer: positions, per-vertex
// normals, uvs and indices, with named parts (triangle ranges) so that a demo can select
// e.g. the teapot's lid apart from its body (001 §6 decomposes the teapot that way).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
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

// Bad input is refused with rg::Error naming `what` (a file or object name) and the
// problem: empty mesh, index out of range, NaN/Inf position, count mismatches.
void validateMesh(const Mesh& mesh, const std::string& what);

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

struct Bounds {
    glm::vec3 lo{1e30f}, hi{-1e30f};
    glm::vec3 center() const { return (lo + hi) * 0.5f; }
};
Bounds computeBounds(const Mesh& mesh);

// Σ area·centroid / Σ area over the triangles (of one part when part ≥ 0): 001 §4's
// environment-map origin ("an area-weighted average of the object's triangle centroids").
glm::vec3 areaWeightedCentroid(const Mesh& mesh, int part = -1);

// Applies an affine transform to positions and (by the inverse transpose) normals.
void transformMesh(Mesh& mesh, const glm::mat4& m);

}  // namespace rg::ray
