#include "shells.h"

#include <algorithm>
#include <vector>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Eigenvalues>
#include <glm/geometric.hpp>

#include "core/error.h"

namespace rg::hybrid {

const char* shellKindName(ShellKind k) {
    switch (k) {
        case ShellKind::Sphere: return "sphere";
        case ShellKind::Cylinder: return "cylinder";
        case ShellKind::Quad: return "quad";
    }
    return "?";
}

ShellKind shellKindByName(const std::string& name) {
    for (ShellKind k : {ShellKind::Sphere, ShellKind::Cylinder, ShellKind::Quad})
        if (name == shellKindName(k)) return k;
    throw Error("hybrid: unknown shell '" + name + "' (sphere, cylinder or quad)");
}

Shell sphereShell(const glm::vec3& origin, float radius) {
    Shell s;
    s.kind = ShellKind::Sphere;
    s.origin = origin;
    s.radius = radius;
    return s;
}

Shell cylinderShell(const glm::vec3& origin, float radius, float yMin, float yMax) {
    Shell s = sphereShell(origin, radius);
    s.kind = ShellKind::Cylinder;
    s.yMin = yMin;
    s.yMax = yMax;
    return s;
}

namespace {

// The larger root t of |q + t·d|² = r² (q = p − centre), or NaN.
float farRoot(const glm::vec3& q, const glm::vec3& d, float r) {
    const float a = glm::dot(d, d);
    if (!(a > 0.0f)) return std::numeric_limits<float>::quiet_NaN();
    const float b = glm::dot(q, d), c = glm::dot(q, q) - r * r;
    const float disc = b * b - a * c;
    if (disc < 0.0f) return std::numeric_limits<float>::quiet_NaN();
    return (-b + std::sqrt(disc)) / a;
}

}  // namespace

glm::vec3 Shell::intersect(const glm::vec3& p, const glm::vec3& d, bool* forced) const {
    if (forced) *forced = false;
    switch (kind) {
        case ShellKind::Sphere: {
            const float t = farRoot(p - origin, d, radius);
            if (t > 0.0f) return p + t * d;
            break;
        }
        case ShellKind::Cylinder: {
            // The side: the far root in the horizontal plane; then the cap the ray reaches
            // first if it leaves through one.
            const glm::vec3 q = p - origin;
            float t = farRoot({q.x, 0.0f, q.z}, {d.x, 0.0f, d.z}, radius);
            if (!(t > 0.0f)) t = std::numeric_limits<float>::infinity();  // vertical ray
            if (d.y > 0.0f) t = std::min(t, (yMax - p.y) / d.y);
            if (d.y < 0.0f) t = std::min(t, (yMin - p.y) / d.y);
            if (t > 0.0f && std::isfinite(t)) return p + t * d;
            break;
        }
        case ShellKind::Quad: {
            const float dn = glm::dot(d, normal);  // normal faces the origin: rays towards
                                                    // the plane have dn < 0
            const float t = glm::dot(center - p, normal) / dn;
            if (dn < 0.0f && t > 0.0f && std::isfinite(t)) return p + t * d;
            // 000 §4.2: keep the tangential part of d, scaled very far from the centre.
            if (forced) *forced = true;
            glm::vec3 tangential = d - dn * normal;
            const float len = glm::length(tangential);
            tangential = len > 1e-6f ? tangential / len : u;
            const float size = std::max(uMax - uMin, vMax - vMin);
            return center + kQuadFar * size * tangential;
        }
    }
    if (forced) *forced = true;
    return origin + radius * d;
}

glm::vec4 Shell::texCoord(const glm::vec3& p, const glm::vec3& d, bool* forced) const {
    const glm::vec3 h = intersect(p, d, forced);
    if (kind != ShellKind::Quad) return glm::vec4(h - origin, 1.0f);
    const glm::vec3 r = h - center;
    return {(glm::dot(r, u) - uMin) / (uMax - uMin), (glm::dot(r, v) - vMin) / (vMax - vMin),
            0.0f, 1.0f};
}

std::string Shell::describe() const {
    std::ostringstream o;
    o.precision(3);
    o << shellKindName(kind);
    if (kind == ShellKind::Sphere) o << " r " << radius;
    if (kind == ShellKind::Cylinder) o << " r " << radius << ", y " << yMin << ".." << yMax;
    if (kind == ShellKind::Quad)
        o << " at distance " << glm::length(center - origin) << ", " << (uMax - uMin) << " x "
          << (vMax - vMin);
    return o.str();
}

Shell fitQuad(const glm::vec3& origin, std::span<const glm::vec3> points,
              std::span<const glm::vec3> rayOrigins, std::span<const glm::vec3> rayDirs) {
    if (points.empty()) throw Error("hybrid: a quad layer needs intersection points to fit");
    glm::dvec3 mean(0.0);
    for (const glm::vec3& p : points) mean += glm::dvec3(p);
    mean /= double(points.size());
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    for (const glm::vec3& p : points) {
        const glm::dvec3 q = glm::dvec3(p) - mean;
        const Eigen::Vector3d e(q.x, q.y, q.z);
        cov += e * e.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Eigen::Vector3d ev = eig.eigenvalues();
    Shell s;
    s.kind = ShellKind::Quad;
    s.origin = origin;
    s.center = glm::vec3(mean);
    glm::vec3 toOrigin = origin - s.center;
    glm::vec3 n;
    // A least-squares plane needs the points to span two directions: the two larger
    // eigenvalues well above the smallest, the middle one not negligible.
    if (ev(1) > 1e-6 * std::max(ev(2), 1e-30)) {
        const Eigen::Vector3d e = eig.eigenvectors().col(0);
        n = glm::normalize(glm::vec3(float(e.x()), float(e.y()), float(e.z())));
    } else {
        n = glm::length(toOrigin) > 0.0f ? glm::normalize(toOrigin) : glm::vec3(0, 0, 1);
    }
    if (glm::dot(n, toOrigin) < 0.0f) n = -n;
    s.normal = n;
    glm::vec3 u = glm::cross(glm::vec3(0, 1, 0), n);
    if (glm::length(u) < 1e-3f) u = glm::cross(glm::vec3(1, 0, 0), n);
    s.u = glm::normalize(u);
    s.v = glm::normalize(glm::cross(n, s.u));
    // The rectangle bounding where the outgoing rays meet the plane. Rays meeting it at a
    // grazing angle land arbitrarily far away (a ray that passes over the edge of a floor
    // meets its plane kilometres off); a bounding box of every one would spread the
    // texture over all of them. So the box bounds the central 96% of the points along each
    // axis (our choice; the rays beyond it read the edge texels, as forced ones do).
    std::vector<float> us, vs;
    for (size_t i = 0; i < rayOrigins.size() && i < rayDirs.size(); ++i) {
        const float dn = glm::dot(rayDirs[i], n);
        const float t = glm::dot(s.center - rayOrigins[i], n) / dn;
        if (!(dn < 0.0f) || !(t > 0.0f) || !std::isfinite(t)) continue;
        const glm::vec3 r = rayOrigins[i] + t * rayDirs[i] - s.center;
        us.push_back(glm::dot(r, s.u));
        vs.push_back(glm::dot(r, s.v));
    }
    float uMin = std::numeric_limits<float>::infinity(), uMax = -uMin, vMin = uMin, vMax = -uMin;
    if (!us.empty()) {
        auto quantile = [](std::vector<float>& x, double q) {
            const size_t i = std::min(x.size() - 1, size_t(q * double(x.size())));
            std::nth_element(x.begin(), x.begin() + std::ptrdiff_t(i), x.end());
            return x[i];
        };
        uMin = quantile(us, kQuadExtentTrim);
        uMax = quantile(us, 1.0 - kQuadExtentTrim);
        vMin = quantile(vs, kQuadExtentTrim);
        vMax = quantile(vs, 1.0 - kQuadExtentTrim);
    }
    if (!(uMax > uMin) || !(vMax > vMin)) {
        // No ray meets it usefully: the points' own extent.
        uMin = vMin = std::numeric_limits<float>::infinity();
        uMax = vMax = -uMin;
        for (const glm::vec3& p : points) {
            const glm::vec3 r = p - s.center;
            uMin = std::min(uMin, glm::dot(r, s.u));
            uMax = std::max(uMax, glm::dot(r, s.u));
            vMin = std::min(vMin, glm::dot(r, s.v));
            vMax = std::max(vMax, glm::dot(r, s.v));
        }
        if (!(uMax > uMin)) uMin -= 0.5f, uMax += 0.5f;
        if (!(vMax > vMin)) vMin -= 0.5f, vMax += 0.5f;
    }
    s.uMin = uMin, s.uMax = uMax, s.vMin = vMin, s.vMax = vMax;
    return s;
}

}  // namespace rg::hybrid
