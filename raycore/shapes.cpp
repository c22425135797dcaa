// Procedural shapes. Seams repeat vertices with bit-identical positions (ring tables are
// computed once and the last column copies the first), so isClosedManifold() welds them.
#include "raycore/shapes.h"

#include <cmath>
#include <numbers>

#include "core/error.h"

namespace rg::ray {

namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

// cos/sin of k·2π/n for k = 0..n, the last equal to the first bit for bit.
void ringTable(int n, std::vector<float>& c, std::vector<float>& s) {
    c.resize(n + 1);
    s.resize(n + 1);
    for (int k = 0; k < n; ++k) {
        c[k] = std::cos(kTwoPi * float(k) / float(n));
        s[k] = std::sin(kTwoPi * float(k) / float(n));
    }
    c[n] = c[0];
    s[n] = s[0];
}

void addQuad(Mesh& m, uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
    m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
}

}  // namespace

Mesh makeLathe(const std::vector<glm::vec2>& profile, int segments, float creaseDegrees) {
    if (profile.size() < 2 || segments < 3) throw Error("lathe: needs ≥ 2 profile points, ≥ 3 segments");
    Mesh m;
    m.name = "lathe";
    std::vector<float> c, s;
    ringTable(segments, c, s);
    const size_t nseg = profile.size() - 1;
    // Outward 2D normal of each profile segment: (dy, −dr) for a profile going upwards.
    std::vector<glm::vec2> segN(nseg);
    std::vector<float> arc(profile.size(), 0.0f);
    for (size_t i = 0; i < nseg; ++i) {
        glm::vec2 d = profile[i + 1] - profile[i];
        float len = glm::length(d);
        segN[i] = len > 0.0f ? glm::vec2(d.y, -d.x) / len : glm::vec2(1, 0);
        arc[i + 1] = arc[i] + len;
    }
    const float total = arc.back() > 0.0f ? arc.back() : 1.0f;
    const float cosCrease = std::cos(creaseDegrees * std::numbers::pi_v<float> / 180.0f);
    auto endNormal = [&](size_t seg, size_t neighbour, bool hasNeighbour) {
        if (!hasNeighbour) return segN[seg];
        if (glm::dot(segN[seg], segN[neighbour]) < cosCrease) return segN[seg];
        glm::vec2 n = segN[seg] + segN[neighbour];
        return glm::length(n) > 0.0f ? glm::normalize(n) : segN[seg];
    };
    auto ringPos = [&](glm::vec2 p, int k) {
        // On the axis write exact +0 so that the pole vertices weld (0·cos may be −0).
        if (p.x == 0.0f) return glm::vec3(0.0f, p.y, 0.0f);
        return glm::vec3(p.x * c[k], p.y, -p.x * s[k]);
    };
    for (size_t i = 0; i < nseg; ++i) {
        glm::vec2 p0 = profile[i], p1 = profile[i + 1];
        if (p0 == p1) continue;
        glm::vec2 n0 = endNormal(i, i - 1, i > 0);
        glm::vec2 n1 = endNormal(i, i + 1, i + 1 < nseg);
        uint32_t base = uint32_t(m.positions.size());
        for (int k = 0; k <= segments; ++k) {
            float u = float(k) / float(segments);
            m.positions.push_back(ringPos(p0, k));
            m.normals.push_back(glm::normalize(glm::vec3(n0.x * c[k], n0.y, -n0.x * s[k])));
            m.uvs.push_back({u, arc[i] / total});
            m.positions.push_back(ringPos(p1, k));
            m.normals.push_back(glm::normalize(glm::vec3(n1.x * c[k], n1.y, -n1.x * s[k])));
            m.uvs.push_back({u, arc[i + 1] / total});
        }
        for (int k = 0; k < segments; ++k) {
            uint32_t a = base + 2 * k, b = base + 2 * (k + 1), cc = b + 1, d = a + 1;
            // Skip the triangle that collapses on the axis.
            if (p0.x != 0.0f) m.indices.insert(m.indices.end(), {a, b, cc});
            if (p1.x != 0.0f) m.indices.insert(m.indices.end(), {a, cc, d});
        }
    }
    return m;
}

Mesh makeSphere(float radius, int slices, int stacks) {
    std::vector<glm::vec2> profile;
    for (int j = 0; j <= stacks; ++j) {
        float phi = std::numbers::pi_v<float> * float(j) / float(stacks);  // from the south pole
        float r = (j == 0 || j == stacks) ? 0.0f : radius * std::sin(phi);
        profile.push_back({r, -radius * std::cos(phi)});
    }
    Mesh m = makeLathe(profile, slices, 90.0f);
    // The exact normals of a sphere.
    for (size_t i = 0; i < m.positions.size(); ++i) m.normals[i] = glm::normalize(m.positions[i]);
    m.name = "sphere";
    m.source = {"sphere", "", {{"radius", radius}, {"slices", slices}, {"stacks", stacks}}};
    return m;
}

Mesh makeCylinder(float radius, float height, int segments) {
    Mesh m = makeLathe({{0, 0}, {radius, 0}, {radius, height}, {0, height}}, segments);
    m.name = "cylinder";
    m.source = {"cylinder", "", {{"radius", radius}, {"height", height}, {"segments", segments}}};
    return m;
}

Mesh makeCube(float h) {
    Mesh m;
    m.name = "cube";
    // For each face: outward normal n and two in-plane axes (u, v) with u × v = n.
    const glm::vec3 faces[6][3] = {
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
    };
    for (const auto& f : faces) {
        uint32_t base = uint32_t(m.positions.size());
        const glm::vec2 corners[4] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (const glm::vec2& q : corners) {
            m.positions.push_back(h * (f[0] + q.x * f[1] + q.y * f[2]));
            m.normals.push_back(f[0]);
            m.uvs.push_back({(q.x + 1) * 0.5f, (1 - q.y) * 0.5f});
        }
        addQuad(m, base, base + 1, base + 2, base + 3);
    }
    m.source = {"cube", "", {{"half_size", h}}};
    return m;
}

Mesh makeTorus(float R, float r, int majorSegments, int minorSegments) {
    Mesh m;
    m.name = "torus";
    std::vector<float> cu, su, cv, sv;
    ringTable(majorSegments, cu, su);
    ringTable(minorSegments, cv, sv);
    for (int i = 0; i <= majorSegments; ++i)
        for (int j = 0; j <= minorSegments; ++j) {
            glm::vec3 dir(cu[i], 0.0f, -su[i]);  // around y, same sense as the lathe
            glm::vec3 n = cv[j] * dir + sv[j] * glm::vec3(0, 1, 0);
            m.positions.push_back(R * dir + r * n);
            m.normals.push_back(glm::normalize(n));
            m.uvs.push_back({float(i) / majorSegments, float(j) / minorSegments});
        }
    const uint32_t row = uint32_t(minorSegments + 1);
    for (int i = 0; i < majorSegments; ++i)
        for (int j = 0; j < minorSegments; ++j) {
            uint32_t a = i * row + j, b = (i + 1) * row + j;
            addQuad(m, a, b, b + 1, a + 1);
        }
    m.source = {"torus", "",
                {{"major_radius", R}, {"minor_radius", r}, {"major_segments", majorSegments},
                 {"minor_segments", minorSegments}}};
    return m;
}

Mesh makeExtrusion(const std::vector<glm::vec2>& poly, float depth) {
    if (poly.size() < 3) throw Error("extrusion: polygon needs ≥ 3 points");
    Mesh m;
    m.name = "extrusion";
    const float z0 = -depth * 0.5f, z1 = depth * 0.5f;
    glm::vec2 centroid(0.0f);
    for (const glm::vec2& p : poly) centroid += p;
    centroid /= float(poly.size());
    // Caps: fan from the centroid.
    for (int side = 0; side < 2; ++side) {
        float z = side ? z1 : z0;
        glm::vec3 n(0, 0, side ? 1.0f : -1.0f);
        uint32_t base = uint32_t(m.positions.size());
        m.positions.push_back({centroid, z});
        for (const glm::vec2& p : poly) m.positions.push_back({p, z});
        for (size_t i = 0; i <= poly.size(); ++i) {
            m.normals.push_back(n);
            m.uvs.push_back({0.5f, 0.5f});
        }
        for (uint32_t i = 0; i < poly.size(); ++i) {
            uint32_t a = base + 1 + i, b = base + 1 + uint32_t((i + 1) % poly.size());
            if (side) m.indices.insert(m.indices.end(), {base, a, b});
            else m.indices.insert(m.indices.end(), {base, b, a});
        }
    }
    // Sides: one flat quad per edge.
    for (size_t i = 0; i < poly.size(); ++i) {
        glm::vec2 p = poly[i], q = poly[(i + 1) % poly.size()];
        glm::vec2 e = q - p;
        glm::vec3 n = glm::normalize(glm::vec3(e.y, -e.x, 0.0f));
        uint32_t base = uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {{p, z0}, {q, z0}, {q, z1}, {p, z1}});
        for (int k = 0; k < 4; ++k) m.normals.push_back(n);
        m.uvs.insert(m.uvs.end(), {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
        addQuad(m, base, base + 1, base + 2, base + 3);
    }
    return m;
}

Mesh makeRoom(glm::vec3 lo, glm::vec3 hi, float uvScale) {
    Mesh m;
    m.name = "room";
    // Each face seen from inside: corners counter-clockwise as seen from the room's interior.
    struct Face {
        const char* name;
        glm::vec3 n;  // inward
        glm::vec3 corner[4];
    };
    const Face faces[6] = {
        {"floor", {0, 1, 0}, {{lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, lo.y, lo.z}, {lo.x, lo.y, lo.z}}},
        {"ceiling", {0, -1, 0}, {{lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}}},
        {"wall_-x", {1, 0, 0}, {{lo.x, lo.y, hi.z}, {lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}}},
        {"wall_+x", {-1, 0, 0}, {{hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z}}},
        {"wall_-z", {0, 0, 1}, {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}}},
        {"wall_+z", {0, 0, -1}, {{hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}}},
    };
    for (const Face& f : faces) {
        uint32_t base = uint32_t(m.positions.size());
        uint32_t firstTri = uint32_t(m.triangleCount());
        glm::vec3 eu = f.corner[1] - f.corner[0], ev = f.corner[3] - f.corner[0];
        float lu = glm::length(eu) / uvScale, lv = glm::length(ev) / uvScale;
        const glm::vec2 uv[4] = {{0, lv}, {lu, lv}, {lu, 0}, {0, 0}};
        for (int k = 0; k < 4; ++k) {
            m.positions.push_back(f.corner[k]);
            m.normals.push_back(f.n);
            m.uvs.push_back(uv[k]);
        }
        addQuad(m, base, base + 1, base + 2, base + 3);
        m.parts.push_back({f.name, firstTri, 2});
    }
    m.source = {"room", "", {{"lo_x", lo.x}, {"lo_y", lo.y}, {"lo_z", lo.z},
                             {"hi_x", hi.x}, {"hi_y", hi.y}, {"hi_z", hi.z}, {"uv_scale", uvScale}}};
    return m;
}

}  // namespace rg::ray
