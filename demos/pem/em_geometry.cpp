#include "em_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace rg::pem {

std::optional<float> exitEllipsoid(const glm::vec3& p, const glm::vec3& r, const glm::vec3& c,
                                   const glm::vec3& a) {
    // Scale space so the ellipsoid is the unit sphere: |q + t·d|² = 1.
    glm::vec3 q = (p - c) / a, d = r / a;
    double A = glm::dot(glm::dvec3(d), glm::dvec3(d));
    double B = glm::dot(glm::dvec3(q), glm::dvec3(d));
    double C = glm::dot(glm::dvec3(q), glm::dvec3(q)) - 1.0;
    if (A <= 0.0 || C > 0.0) return std::nullopt;  // degenerate ray or origin outside
    double disc = B * B - A * C;                     // ≥ 0 when C ≤ 0
    double t = (-B + std::sqrt(std::max(0.0, disc))) / A;
    return t > 0.0 ? std::optional<float>(float(t)) : std::nullopt;
}

std::optional<float> exitBox(const glm::vec3& p, const glm::vec3& r, const glm::vec3& lo,
                             const glm::vec3& hi) {
    float t = std::numeric_limits<float>::infinity();
    for (int i = 0; i < 3; ++i) {
        if (p[i] < lo[i] || p[i] > hi[i]) return std::nullopt;
        if (r[i] > 0.0f) t = std::min(t, (hi[i] - p[i]) / r[i]);
        if (r[i] < 0.0f) t = std::min(t, (lo[i] - p[i]) / r[i]);
    }
    return std::isfinite(t) ? std::optional<float>(t) : std::nullopt;
}

glm::vec3 EmGeometry::index(const glm::vec3& p, const glm::vec3& r, bool* escaped) const {
    std::optional<float> t;
    switch (kind) {
        case EmGeometryKind::SphereAtInfinity: return r;
        case EmGeometryKind::FiniteSphere: t = exitEllipsoid(p, r, center, glm::vec3(radii.x)); break;
        case EmGeometryKind::Ellipsoid: t = exitEllipsoid(p, r, center, radii); break;
        case EmGeometryKind::Box: t = exitBox(p, r, boxMin, boxMax); break;
    }
    if (!t) {
        if (escaped) *escaped = true;
        return r;
    }
    return p + *t * r - origin;
}

std::string EmGeometry::describe() const {
    auto v = [](const glm::vec3& x) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "(%.3f, %.3f, %.3f)", x.x, x.y, x.z);
        return std::string(buf);
    };
    switch (kind) {
        case EmGeometryKind::SphereAtInfinity: return "sphere at infinity";
        case EmGeometryKind::FiniteSphere: return "finite sphere r=" + std::to_string(radii.x) + " at " + v(center);
        case EmGeometryKind::Ellipsoid: return "ellipsoid radii " + v(radii) + " at " + v(center);
        case EmGeometryKind::Box: return "box " + v(boxMin) + "–" + v(boxMax);
    }
    return "?";
}

glm::vec3 areaWeightedCentroid(std::span<const glm::vec3> positions,
                               std::span<const uint32_t> indices) {
    glm::dvec3 sum(0.0);
    double area = 0.0;
    for (size_t i = 0; i + 2 < indices.size(); i += 3) {
        glm::dvec3 a = positions[indices[i]], b = positions[indices[i + 1]],
                   c = positions[indices[i + 2]];
        double w = 0.5 * glm::length(glm::cross(b - a, c - a));
        sum += w * (a + b + c) / 3.0;
        area += w;
    }
    if (!(area > 0.0)) throw Error("EM origin: the mesh has no triangle of positive area");
    return glm::vec3(sum / area);
}

EmGeometry fitBoundingEllipsoid(std::span<const glm::vec3> points, const glm::vec3& center,
                                const glm::vec3& origin, int steps) {
    if (points.empty()) throw Error("bounding ellipsoid of an empty point set");
    // For semi-axis ratios (1, ρy, ρz) the smallest enclosing scale s is
    // max_i sqrt(dx² + (dy/ρy)² + (dz/ρz)²); the volume is (4/3)π s³ ρy ρz.
    auto scaleFor = [&](double ry, double rz) {
        double s2 = 0.0;
        for (const glm::vec3& p : points) {
            glm::dvec3 d = glm::dvec3(p) - glm::dvec3(center);
            s2 = std::max(s2, d.x * d.x + (d.y / ry) * (d.y / ry) + (d.z / rz) * (d.z / rz));
        }
        return std::sqrt(s2);
    };
    double bestV = std::numeric_limits<double>::infinity(), bestY = 1, bestZ = 1;
    auto search = [&](double lyLo, double lyHi, double lzLo, double lzHi) {
        for (int i = 0; i < steps; ++i)
            for (int j = 0; j < steps; ++j) {
                double ry = std::exp(lyLo + (lyHi - lyLo) * i / (steps - 1));
                double rz = std::exp(lzLo + (lzHi - lzLo) * j / (steps - 1));
                double s = scaleFor(ry, rz);
                double v = s * s * s * ry * rz;
                if (v < bestV) bestV = v, bestY = ry, bestZ = rz;
            }
    };
    const double range = std::log(8.0);
    search(-range, range, -range, range);
    double cellY = 2 * range / (steps - 1);
    search(std::log(bestY) - cellY, std::log(bestY) + cellY, std::log(bestZ) - cellY,
           std::log(bestZ) + cellY);
    double s = scaleFor(bestY, bestZ) * (1.0 + 1e-5);  // strictly contain every vertex
    EmGeometry g;
    g.kind = EmGeometryKind::Ellipsoid;
    g.center = center;
    g.origin = origin;
    g.radii = glm::vec3(float(s), float(s * bestY), float(s * bestZ));
    return g;
}

}  // namespace rg::pem
