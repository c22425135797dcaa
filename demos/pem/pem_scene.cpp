#include "pem_scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "raycore/accel.h"
#include "raycore/mesh.h"

namespace rg::pem {

std::vector<uint8_t> classifyHullTriangles(const std::vector<glm::vec3>& points,
                                           const std::vector<glm::vec3>& positions,
                                           const std::vector<uint32_t>& indices, float epsilon) {
    size_t n = indices.size() / 3;
    std::vector<uint8_t> out(n, 0);
    tbb::parallel_for(size_t(0), n, [&](size_t t) {
        glm::vec3 a = positions[indices[3 * t]], b = positions[indices[3 * t + 1]],
                  c = positions[indices[3 * t + 2]];
        glm::vec3 nrm = glm::cross(b - a, c - a);
        float len = glm::length(nrm);
        if (!(len > 0.0f)) return;  // degenerate: not on the hull
        nrm /= len;
        float hmax = -INFINITY;
        for (const glm::vec3& q : points) hmax = std::max(hmax, glm::dot(nrm, q - a));
        out[t] = hmax <= epsilon ? 1 : 0;
    });
    return out;
}

std::vector<int> connectedComponents(size_t vertexCount, const std::vector<uint32_t>& indices,
                                     int* count) {
    std::vector<uint32_t> parent(vertexCount);
    for (size_t i = 0; i < vertexCount; ++i) parent[i] = uint32_t(i);
    auto find = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (size_t i = 0; i + 2 < indices.size(); i += 3)
        for (int k = 1; k < 3; ++k) {
            uint32_t a = find(indices[i]), b = find(indices[i + k]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    std::vector<int> label(vertexCount, -1), comp(vertexCount, -1);
    int n = 0;
    for (size_t v = 0; v < vertexCount; ++v) {
        uint32_t r = find(uint32_t(v));
        if (label[r] < 0) label[r] = n++;
        comp[v] = label[r];
    }
    if (count) *count = n;
    return comp;
}

namespace {

// Atlas coordinates: component c occupies tile (c mod g, c div g) of a g×g grid, its uv
// bounding box mapped into the tile inset by 4% so filtering never reaches a neighbour.
void buildAtlas(PemPart& part, const std::vector<glm::vec2>& uvs) {
    int count = 0;
    std::vector<int> comp = connectedComponents(part.positions.size(), part.indices, &count);
    int g = 1;
    while (g * g < count) ++g;
    part.atlasTiles = g;
    std::vector<glm::vec2> lo(size_t(count), glm::vec2(1e30f)), hi(size_t(count), glm::vec2(-1e30f));
    for (size_t v = 0; v < uvs.size(); ++v) {
        lo[size_t(comp[v])] = glm::min(lo[size_t(comp[v])], uvs[v]);
        hi[size_t(comp[v])] = glm::max(hi[size_t(comp[v])], uvs[v]);
    }
    part.atlasUv.resize(uvs.size());
    const float inset = 0.04f;
    for (size_t v = 0; v < uvs.size(); ++v) {
        int c = comp[v];
        glm::vec2 ext = glm::max(hi[size_t(c)] - lo[size_t(c)], glm::vec2(1e-6f));
        glm::vec2 local = (uvs[v] - lo[size_t(c)]) / ext;
        local = inset + (1.0f - 2.0f * inset) * local;
        part.atlasUv[v] = (glm::vec2(float(c % g), float(c / g)) + local) / float(g);
    }
}

// Mean distance from `origin` to the environment (everything but `object`) over rays
// around each box axis: ±x, +y, ±z. Rays that hit the reflector are continued through it.
struct AxisDistances {
    float d[6] = {0, 0, 0, 0, 0, 0};  // +x −x +y −y +z −z
};

AxisDistances meanEnvironmentDistances(const ray::Scene& scene, int object,
                                       const glm::vec3& origin, int rays) {
    ray::Accel accel(scene);
    double sum[6] = {}, count[6] = {};
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < rays; ++i) {
        // Fibonacci sphere: deterministic, even coverage.
        double z = 1.0 - 2.0 * (i + 0.5) / rays, r = std::sqrt(1.0 - z * z), phi = golden * i;
        glm::vec3 dir(float(r * std::cos(phi)), float(z), float(r * std::sin(phi)));
        ray::Ray ray{origin, dir, 0.0f, 1e30f};
        ray::Hit hit;
        for (int k = 0; k < 64; ++k) {
            hit = accel.intersect(ray);
            if (!hit.valid() || hit.object != uint32_t(object)) break;
            ray.tnear = hit.t + accel.epsilon();
        }
        if (!hit.valid()) continue;
        glm::vec3 p = origin + hit.t * dir;
        glm::vec3 d = p - origin;
        int axis = 0;
        for (int a = 1; a < 3; ++a)
            if (std::abs(dir[a]) > std::abs(dir[axis])) axis = a;
        int side = 2 * axis + (dir[axis] < 0 ? 1 : 0);
        sum[side] += std::abs(d[axis]);
        count[side] += 1;
    }
    AxisDistances out;
    for (int s = 0; s < 6; ++s) out.d[s] = count[s] > 0 ? float(sum[s] / count[s]) : 1e3f;
    return out;
}

}  // namespace

PemSceneOptions reflectorOptionsFor(const ray::Scene& scene) {
    PemSceneOptions pso;
    pso.object.clear();
    for (const auto& o : scene.objects)
        if (scene.materials.at(o.material).type == ray::MaterialType::Mirror) {
            pso.object = o.name;
            break;
        }
    if (pso.object.empty())
        throw Error("PEM: scene '" + scene.name + "' has no mirror object to infer PEMs for");
    const ray::Mesh& m = scene.meshes.at(scene.objects.at(size_t(scene.findObject(pso.object))).mesh);
    pso.parts.clear();
    if (m.findPart("body") >= 0 && m.findPart("lid") >= 0) pso.parts = {"body", "lid"};
    return pso;
}

PemScene makePemScene(ray::Scene scene, const PemSceneOptions& options) {
    PemScene ps;
    ps.object = scene.findObject(options.object);
    if (ps.object < 0)
        throw Error("PEM: scene '" + scene.name + "' has no object '" + options.object + "'");
    const ray::Object& obj = scene.objects[size_t(ps.object)];
    if (scene.materials.at(obj.material).type != ray::MaterialType::Mirror)
        throw Error("PEM: object '" + options.object + "' is not a mirror (the PEM paper infers "
                    "the incident specular layer of mirror-like reflectors)");
    ray::Mesh world = scene.worldMesh(uint32_t(ps.object));
    ps.triangles = world.triangleCount();

    // The whole reflector's vertices decide the convex hull and the support plane.
    ray::Bounds bounds = ray::computeBounds(world);
    ps.supportPlaneY = bounds.lo.y;
    float extent = glm::length(bounds.hi - bounds.lo);
    std::vector<uint8_t> hull =
        classifyHullTriangles(world.positions, world.positions, world.indices, 1e-4f * extent);
    for (uint8_t h : hull) ps.hullTriangles += h;

    std::vector<std::string> partNames = options.parts;
    if (partNames.empty()) partNames.push_back("");
    for (const std::string& partName : partNames) {
        PemPart part;
        part.name = partName.empty() ? options.object : partName;
        part.segment = ray::findSegment(scene, partName.empty() ? options.object
                                                                 : options.object + "/" + partName);
        uint32_t first = 0, count = uint32_t(world.triangleCount());
        if (part.segment.part >= 0) {
            first = world.parts.at(size_t(part.segment.part)).firstTriangle;
            count = world.parts.at(size_t(part.segment.part)).triangleCount;
        }
        std::vector<int64_t> remap(world.positions.size(), -1);
        std::vector<glm::vec2> uvs;
        for (uint32_t t = first; t < first + count; ++t) {
            for (int k = 0; k < 3; ++k) {
                uint32_t v = world.indices[3 * size_t(t) + k];
                if (remap[v] < 0) {
                    remap[v] = int64_t(part.positions.size());
                    part.positions.push_back(world.positions[v]);
                    part.normals.push_back(world.normals[v]);
                    uvs.push_back(world.uvs.empty() ? glm::vec2(0.0f) : world.uvs[v]);
                }
                part.indices.push_back(uint32_t(remap[v]));
            }
            part.onHull.push_back(hull[t]);
        }
        if (part.indices.empty()) throw Error("PEM: part '" + part.name + "' has no triangles");

        buildAtlas(part, uvs);
        // EM geometries (001 §4).
        part.emOrigin = areaWeightedCentroid(part.positions, part.indices);
        part.infinite.kind = EmGeometryKind::SphereAtInfinity;
        part.infinite.origin = part.emOrigin;
        part.local = fitBoundingEllipsoid(part.positions, part.emOrigin, part.emOrigin);
        AxisDistances ad = meanEnvironmentDistances(scene, ps.object, part.emOrigin, options.boxRays);
        part.distant.kind = EmGeometryKind::Box;
        part.distant.origin = part.emOrigin;
        part.distant.boxMin = {part.emOrigin.x - ad.d[1], ps.supportPlaneY,
                               part.emOrigin.z - ad.d[5]};
        part.distant.boxMax = {part.emOrigin.x + ad.d[0], part.emOrigin.y + ad.d[2],
                               part.emOrigin.z + ad.d[4]};
        // The box must contain the reflector so that every reflected ray leaves through it.
        ray::Bounds pb;
        for (const glm::vec3& p : part.positions) {
            pb.lo = glm::min(pb.lo, p);
            pb.hi = glm::max(pb.hi, p);
        }
        part.distant.boxMin = glm::min(part.distant.boxMin, pb.lo - 1e-3f);
        part.distant.boxMax = glm::max(part.distant.boxMax, pb.hi + 1e-3f);
        ps.parts.push_back(std::move(part));
    }
    ps.scene = std::move(scene);
    return ps;
}

}  // namespace rg::pem
