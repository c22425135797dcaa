// The geometry of an EM layer (000 §4, §4.2 "Layer Quads", §6): a nested series of shells
// sharing the lens object's EM origin. A sphere, a cylinder (vertical axis through the
// origin, capped) or a quadrilateral impostor (a plane fitted to the layer's intersection
// points, its extent the bounding rectangle of the layer's outgoing rays on it).
//
// The texture index of an exit ray (p, d) is where it meets the shell, minus the EM origin:
// an unnormalised cube-map vector (000 §5, "doesn't require normalization"), or for a quad
// its (s, t) on the rectangle (a 2D texture: the memory the impostor saves, our choice).
#pragma once

#include <span>
#include <string>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace rg::hybrid {

enum class ShellKind { Sphere, Cylinder, Quad };
const char* shellKindName(ShellKind kind);
ShellKind shellKindByName(const std::string& name);  // rg::Error for others

struct Shell {
    ShellKind kind = ShellKind::Sphere;
    glm::vec3 origin{0.0f};      // the EM origin (the lens object's centroid)
    float radius = 1.0f;         // sphere; cylinder (horizontal)
    float yMin = -1.0f, yMax = 1.0f;  // cylinder caps (world y)
    // Quad: plane through `center` with unit `normal` (facing the origin), rectangle
    // axes u, v and extent [uMin, uMax] × [vMin, vMax] in those coordinates.
    glm::vec3 center{0.0f}, normal{0.0f, 0.0f, 1.0f}, u{1.0f, 0.0f, 0.0f}, v{0.0f, 1.0f, 0.0f};
    float uMin = -1, uMax = 1, vMin = -1, vMax = 1;

    bool cube() const { return kind != ShellKind::Quad; }
    // Where the ray from p along unit d meets the shell. `forced` is set when it does not:
    //  - sphere, cylinder: p outside and the ray missing or leaving it behind: the point
    //    at the shell's distance along d (as if p were the origin);
    //  - quad: a ray parallel to the plane or travelling away from it: 000 §4.2's forced
    //    intersection, the tangential part of d scaled to kQuadFar rectangle sizes from
    //    the centre.
    glm::vec3 intersect(const glm::vec3& p, const glm::vec3& d, bool* forced = nullptr) const;
    // The texture coordinate set of an exit ray: (hit − origin, 1) for cube shells,
    // (s, t, 0, 1) in [0, 1]² on the rectangle for a quad (outside for forced rays; the
    // sampler clamps them to the edge).
    glm::vec4 texCoord(const glm::vec3& p, const glm::vec3& d, bool* forced = nullptr) const;
    std::string describe() const;
    static constexpr float kQuadFar = 1000.0f;
};

Shell sphereShell(const glm::vec3& origin, float radius);
Shell cylinderShell(const glm::vec3& origin, float radius, float yMin, float yMax);
// 000 §4.2: the plane is the least-squares fit to `points` (normal: the eigenvector of the
// smallest eigenvalue of their covariance), turned to face the origin; when the points
// are (nearly) collinear, the simpler plane through their centroid with normal from the
// centroid to the origin. u is horizontal (⊥ world y, or world x for a horizontal plane),
// v = n × u. The extent bounds where the outgoing rays (rayOrigins[i], rayDirs[i]) meet
// the plane (rays that do not are skipped), trimmed to the central 1 − 2·kQuadExtentTrim
// of them along each axis (grazing rays meet a plane arbitrarily far off).
constexpr double kQuadExtentTrim = 0.02;
Shell fitQuad(const glm::vec3& origin, std::span<const glm::vec3> points,
              std::span<const glm::vec3> rayOrigins, std::span<const glm::vec3> rayDirs);

}  // namespace rg::hybrid
