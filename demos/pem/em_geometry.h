// EM geometry (Hakura, Snyder & Lengyel 2001, §4 "EM Representations"): the shape an
// environment map assumes its environment has. A reflected ray leaving a vertex is
// intersected with that shape; the hit point minus the EM origin is the (unnormalized)
// cube-map index handed to the hardware.
#pragma once

#include <optional>
#include <span>
#include <string>

#include <glm/vec3.hpp>

namespace rg::pem {

enum class EmGeometryKind { SphereAtInfinity, FiniteSphere, Ellipsoid, Box };

// One EM shell. The ray origin is expected inside the shell (vertices of the reflector lie
// inside the local ellipsoid and the distant box by construction).
struct EmGeometry {
    EmGeometryKind kind = EmGeometryKind::SphereAtInfinity;
    glm::vec3 origin{0.0f};   // EM origin: area-weighted mean of triangle centroids
    glm::vec3 center{0.0f};   // sphere/ellipsoid centre
    glm::vec3 radii{1.0f};    // sphere (x only) / ellipsoid semi-axes
    glm::vec3 boxMin{-1.0f}, boxMax{1.0f};

    // The cube-map index for a reflected ray (p, r): hit − origin for finite shells,
    // r itself for the sphere at infinity. A ray that does not leave the shell (origin
    // outside it) falls back to the direction r, and is counted by the caller.
    glm::vec3 index(const glm::vec3& p, const glm::vec3& r, bool* escaped = nullptr) const;

    std::string describe() const;
};

// Distance t > 0 along r from p to the boundary of the axis-aligned ellipsoid (centre c,
// semi-axes a) when p is inside; nullopt otherwise.
std::optional<float> exitEllipsoid(const glm::vec3& p, const glm::vec3& r, const glm::vec3& c,
                                   const glm::vec3& a);
// Distance t > 0 along r from p (inside) to the boundary of the box.
std::optional<float> exitBox(const glm::vec3& p, const glm::vec3& r, const glm::vec3& lo,
                             const glm::vec3& hi);

// Area-weighted mean of triangle centroids (§4: "The EM origin is chosen as an
// area-weighted average of the object's triangle centroids").
glm::vec3 areaWeightedCentroid(std::span<const glm::vec3> positions,
                               std::span<const uint32_t> indices);

// Axis-aligned bounding ellipsoid centred at `center` with the axis scales that minimise
// the volume, by brute force over the ratios of the semi-axes (§4 "Layered EMs").
// `steps` ratio samples per axis over [1/8, 8] on a logarithmic grid, then a refinement.
EmGeometry fitBoundingEllipsoid(std::span<const glm::vec3> points, const glm::vec3& center,
                                const glm::vec3& origin, int steps = 64);

}  // namespace rg::pem
