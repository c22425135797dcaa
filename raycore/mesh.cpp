// Mesh bookkeeping: validation, completion, the closed-manifold test, bounds, transforms.
#include "raycore/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <tuple>

#include "core/error.h"

namespace rg::ray {

uint32_t Mesh::partOfTriangle(uint32_t tri) const {
    // Parts are sorted by firstTriangle (they are appended in order); binary search.
    if (parts.empty()) return 0;
    auto it = std::upper_bound(parts.begin(), parts.end(), tri,
                               [](uint32_t t, const MeshPart& p) { return t < p.firstTriangle; });
    return it == parts.begin() ? 0 : uint32_t(it - parts.begin() - 1);
}

int Mesh::findPart(const std::string& partName) const {
    for (size_t i = 0; i < parts.size(); ++i)
        if (parts[i].name == partName) return int(i);
    return -1;
}

namespace {

std::string number(float v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", double(v));
    return buf;
}

bool finite(const glm::vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

// The triangles of each part, or of the whole mesh as one range named `what` alone.
struct TriangleRange {
    std::string label;
    size_t first, count;
};
std::vector<TriangleRange> triangleRanges(const Mesh& mesh, const std::string& what) {
    if (mesh.parts.empty()) return {{what, 0, mesh.triangleCount()}};
    std::vector<TriangleRange> out;
    for (const MeshPart& p : mesh.parts)
        out.push_back({what + ": part '" + p.name + "'", p.firstTriangle, p.triangleCount});
    return out;
}

// "no triangle of non-zero area (...)", saying what the `count` triangles of a part are:
// `zero` of them with |n| = 0, the others with |n| past float's range (mesh.h).
std::string noAreaMessage(size_t count, size_t zero) {
    const std::string n = "a float cross product (p1 − p0) × (p2 − p0)";
    const std::string zeroLength = n + " of zero length";
    const std::string tooLong = n + " whose length overflows float";
    const std::string all = count == 1 ? "its one triangle has "
                                       : "each of its " + std::to_string(count) + " triangles has ";
    if (zero == count) return "no triangle of non-zero area (" + all + zeroLength + ")";
    if (zero == 0) return "no triangle of finite, non-zero area (" + all + tooLong + ")";
    return "no triangle of finite, non-zero area (of its " + std::to_string(count) + " triangles, " +
           std::to_string(zero) + " have " + zeroLength + ", the other " +
           std::to_string(count - zero) + " " + tooLong + ")";
}

// The two geometric rules of validateMesh (mesh.h) on `positions`, the mesh's own or placed
// by a transform; the structure (indices in range, parts covering the triangles) is checked
// already. Returns the bounds of `positions`.
Bounds validateGeometry(const Mesh& mesh, const std::vector<glm::vec3>& positions,
                        const std::string& what) {
    Bounds b;
    for (const glm::vec3& p : positions) {
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    validateExtent(b, what);
    for (const TriangleRange& r : triangleRanges(mesh, what)) {
        if (r.count == 0) throw Error(r.label + ": the part has no triangles");
        bool found = false;
        size_t zero = 0;
        for (size_t t = r.first; t < r.first + r.count && !found; ++t) {
            const glm::vec3& p0 = positions[mesh.indices[3 * t]];
            const glm::vec3 n = glm::cross(positions[mesh.indices[3 * t + 1]] - p0,
                                           positions[mesh.indices[3 * t + 2]] - p0);
            const float len = glm::length(n);
            found = len > 0.0f && std::isfinite(len);
            // With finite positions and extent the edges are finite, so a NaN here is an
            // overflow too (∞ − ∞ inside the cross product).
            if (!found && len == 0.0f) ++zero;
        }
        if (!found) throw Error(r.label + ": " + noAreaMessage(r.count, zero));
    }
    return b;
}

}  // namespace

void validateMesh(const Mesh& mesh, const std::string& what) {
    if (mesh.positions.empty() || mesh.indices.empty())
        throw Error(what + ": mesh has no triangles");
    if (mesh.indices.size() % 3 != 0)
        throw Error(what + ": index count " + std::to_string(mesh.indices.size()) +
                    " is not a multiple of 3");
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        if (!finite(mesh.positions[i]))
            throw Error(what + ": vertex " + std::to_string(i) +
                        " has a non-finite (NaN or infinite) position");
    }
    for (size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= mesh.positions.size())
            throw Error(what + ": triangle " + std::to_string(i / 3) + " uses vertex " +
                        std::to_string(mesh.indices[i]) + " but the mesh has only " +
                        std::to_string(mesh.positions.size()));
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
        throw Error(what + ": " + std::to_string(mesh.normals.size()) + " normals for " +
                    std::to_string(mesh.positions.size()) + " positions");
    if (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())
        throw Error(what + ": " + std::to_string(mesh.uvs.size()) + " uvs for " +
                    std::to_string(mesh.positions.size()) + " positions");
    uint32_t next = 0;
    for (const MeshPart& p : mesh.parts) {
        if (p.firstTriangle != next)
            throw Error(what + ": part '" + p.name + "' does not follow the previous part");
        next += p.triangleCount;
    }
    if (!mesh.parts.empty() && next != mesh.triangleCount())
        throw Error(what + ": parts cover " + std::to_string(next) + " of " +
                    std::to_string(mesh.triangleCount()) + " triangles");
    validateGeometry(mesh, mesh.positions, what);
}

Bounds validatePlacedMesh(const Mesh& mesh, const glm::mat4& m, const std::string& what) {
    validateMesh(mesh, what);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!std::isfinite(m[c][r]))
                throw Error(what + ": its transform has a non-finite entry (row " + std::to_string(r) +
                            ", column " + std::to_string(c) + ")");
    if (m == glm::mat4(1.0f)) return computeBounds(mesh);  // 1·p + 0 is p: checked above
    const std::string placed = what + " as placed by its transform";
    std::vector<glm::vec3> positions;
    positions.reserve(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        positions.push_back(glm::vec3(m * glm::vec4(mesh.positions[i], 1.0f)));  // as transformMesh
        if (!finite(positions.back()))
            throw Error(placed + ": vertex " + std::to_string(i) +
                        " has a non-finite (NaN or infinite) position");
    }
    return validateGeometry(mesh, positions, placed);
}

void validateExtent(const Bounds& b, const std::string& what) {
    const glm::vec3 d = b.hi - b.lo;
    const char* const axis[3] = {"x", "y", "z"};
    for (int k = 0; k < 3; ++k)
        if (!std::isfinite(d[k]))
            throw Error(what + ": extent not finite in float arithmetic (" + axis[k] + " from " +
                        number(b.lo[k]) + " to " + number(b.hi[k]) + ")");
    if (!std::isfinite(glm::length(d)))
        throw Error(what + ": extent not finite in float arithmetic (the length of the diagonal of " +
                    "its bounds, from (" + number(b.lo.x) + ", " + number(b.lo.y) + ", " +
                    number(b.lo.z) + ") to (" + number(b.hi.x) + ", " + number(b.hi.y) + ", " +
                    number(b.hi.z) + "), overflows float)");
}

void completeMesh(Mesh& mesh) {
    if (mesh.uvs.size() != mesh.positions.size()) mesh.uvs.assign(mesh.positions.size(), {0, 0});
    if (mesh.normals.size() == mesh.positions.size()) return;
    // Area-weighted: the unnormalized cross product is twice the triangle's area.
    mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
        glm::vec3 n = glm::cross(mesh.positions[b] - mesh.positions[a],
                                 mesh.positions[c] - mesh.positions[a]);
        mesh.normals[a] += n;
        mesh.normals[b] += n;
        mesh.normals[c] += n;
    }
    for (glm::vec3& n : mesh.normals) {
        float len = glm::length(n);
        n = len > 0.0f ? n / len : glm::vec3(0, 1, 0);
    }
}

bool isClosedManifold(const Mesh& mesh) {
    // Weld by exact position bits: generators emit seams with identical coordinates.
    auto key = [](const glm::vec3& p) {
        uint32_t k[3];
        std::memcpy(k, &p, sizeof k);
        return std::make_tuple(k[0], k[1], k[2]);
    };
    std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> weld;
    std::vector<uint32_t> id(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        id[i] = weld.emplace(key(mesh.positions[i]), uint32_t(weld.size())).first->second;
    // Each directed edge must appear once and its reverse once.
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        uint32_t v[3] = {id[mesh.indices[t]], id[mesh.indices[t + 1]], id[mesh.indices[t + 2]]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;  // degenerate sliver
        for (int e = 0; e < 3; ++e) ++directed[{v[e], v[(e + 1) % 3]}];
    }
    if (directed.empty()) return false;
    for (const auto& [e, n] : directed) {
        if (n != 1) return false;
        auto it = directed.find({e.second, e.first});
        if (it == directed.end() || it->second != 1) return false;
    }
    return true;
}

void appendMesh(Mesh& mesh, const Mesh& otherIn, const std::string& partName) {
    Mesh other = otherIn;
    completeMesh(other);
    completeMesh(mesh);
    uint32_t base = uint32_t(mesh.positions.size());
    uint32_t firstTri = uint32_t(mesh.triangleCount());
    if (mesh.parts.empty() && firstTri > 0)
        mesh.parts.push_back({mesh.name.empty() ? "part0" : mesh.name, 0, firstTri});
    mesh.positions.insert(mesh.positions.end(), other.positions.begin(), other.positions.end());
    mesh.normals.insert(mesh.normals.end(), other.normals.begin(), other.normals.end());
    mesh.uvs.insert(mesh.uvs.end(), other.uvs.begin(), other.uvs.end());
    for (uint32_t i : other.indices) mesh.indices.push_back(i + base);
    if (other.parts.empty()) {
        mesh.parts.push_back({partName.empty() ? other.name : partName, firstTri,
                              uint32_t(other.triangleCount())});
    } else {
        for (MeshPart p : other.parts) {
            p.firstTriangle += firstTri;
            mesh.parts.push_back(p);
        }
    }
}

Mesh extractPart(const Mesh& m, uint32_t partIndex) {
    const MeshPart& p = m.parts.at(partIndex);
    Mesh out;
    out.name = p.name;
    std::vector<int> remap(m.positions.size(), -1);
    for (uint32_t t = p.firstTriangle; t < p.firstTriangle + p.triangleCount; ++t)
        for (int k = 0; k < 3; ++k) {
            uint32_t v = m.indices[size_t(t) * 3 + k];
            if (remap[v] < 0) {
                remap[v] = int(out.positions.size());
                out.positions.push_back(m.positions[v]);
                if (!m.normals.empty()) out.normals.push_back(m.normals[v]);
                if (!m.uvs.empty()) out.uvs.push_back(m.uvs[v]);
            }
            out.indices.push_back(uint32_t(remap[v]));
        }
    return out;
}

Bounds computeBounds(const Mesh& mesh) {
    Bounds b;
    for (const glm::vec3& p : mesh.positions) {
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    return b;
}

glm::vec3 areaWeightedCentroid(const Mesh& mesh, int part) {
    uint32_t first = 0, count = uint32_t(mesh.triangleCount());
    if (part >= 0) {
        first = mesh.parts.at(size_t(part)).firstTriangle;
        count = mesh.parts.at(size_t(part)).triangleCount;
    }
    // Accumulate in double: 40k small triangles in float would lose the low bits.
    glm::dvec3 sum(0.0);
    double area = 0.0;
    for (uint32_t t = first; t < first + count; ++t) {
        glm::dvec3 a = mesh.positions[mesh.indices[3 * size_t(t)]];
        glm::dvec3 b = mesh.positions[mesh.indices[3 * size_t(t) + 1]];
        glm::dvec3 c = mesh.positions[mesh.indices[3 * size_t(t) + 2]];
        double w = 0.5 * glm::length(glm::cross(b - a, c - a));
        sum += w * (a + b + c) / 3.0;
        area += w;
    }
    return area > 0.0 ? glm::vec3(sum / area) : glm::vec3(0.0f);
}

void transformMesh(Mesh& mesh, const glm::mat4& m) {
    glm::mat3 nm = glm::transpose(glm::inverse(glm::mat3(m)));
    for (glm::vec3& p : mesh.positions) p = glm::vec3(m * glm::vec4(p, 1.0f));
    for (glm::vec3& n : mesh.normals) {
        glm::vec3 t = nm * n;
        float len = glm::length(t);
        n = len > 0.0f ? t / len : n;
    }
    // A mirroring transform flips the winding; keep counter-clockwise from outside.
    if (glm::determinant(glm::mat3(m)) < 0.0f)
        for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
            std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
}

}  // namespace rg::ray
