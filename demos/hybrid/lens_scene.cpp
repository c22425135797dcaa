#include "lens_scene.h"

#include <cmath>
#include <cstring>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "core/error.h"

namespace rg::hybrid {

const ray::Material& LensObject::material() const {
    return localScene->materials.at(localScene->objects.at(0).material);
}

void weldPositions(const std::vector<glm::vec3>& positions, std::vector<uint32_t>& remap,
                   std::vector<glm::vec3>& welded) {
    struct Key {
        uint32_t b[3];
        bool operator==(const Key& o) const { return std::memcmp(b, o.b, sizeof b) == 0; }
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = k.b[0] * 0x9E3779B97F4A7C15ull;
            h ^= (k.b[1] + 0x632BE59BD9B4E019ull) + (h << 6) + (h >> 2);
            h ^= (k.b[2] + 0x8CB92BA72F3D8DD7ull) + (h << 6) + (h >> 2);
            return size_t(h);
        }
    };
    std::unordered_map<Key, uint32_t, KeyHash> index;
    index.reserve(positions.size());
    remap.resize(positions.size());
    welded.clear();
    for (size_t i = 0; i < positions.size(); ++i) {
        glm::vec3 p = positions[i];
        if (p.x == 0.0f) p.x = 0.0f;  // −0 and +0 are one position
        if (p.y == 0.0f) p.y = 0.0f;
        if (p.z == 0.0f) p.z = 0.0f;
        Key k;
        std::memcpy(k.b, &p, sizeof k.b);
        auto [it, added] = index.emplace(k, uint32_t(welded.size()));
        if (added) welded.push_back(p);
        remap[i] = it->second;
    }
}

namespace {

bool closedAfterWelding(const std::vector<uint32_t>& indices) {
    std::unordered_map<uint64_t, int> directed;
    for (size_t t = 0; t + 2 < indices.size(); t += 3) {
        uint32_t v[3] = {indices[t], indices[t + 1], indices[t + 2]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
        for (int e = 0; e < 3; ++e) ++directed[(uint64_t(v[e]) << 32) | v[(e + 1) % 3]];
    }
    if (directed.empty()) return false;
    for (const auto& [e, n] : directed) {
        if (n != 1) return false;
        auto it = directed.find((e << 32) | (e >> 32));
        if (it == directed.end() || it->second != 1) return false;
    }
    return true;
}

}  // namespace

LensScene::LensScene(ray::Scene scene, const LensSceneOptions& options) : scene_(std::move(scene)) {
    const std::string where = "hybrid: scene '" + scene_.name + "'";
    // ---- which objects are lens objects -----------------------------------------------
    std::vector<uint32_t> chosen;
    if (options.objects.empty()) {
        for (uint32_t i = 0; i < scene_.objects.size(); ++i) {
            const auto& o = scene_.objects[i];
            if (o.material < scene_.materials.size() &&
                scene_.materials[o.material].type != ray::MaterialType::Diffuse)
                chosen.push_back(i);
        }
        if (chosen.empty())
            throw Error(where + " has no glass or mirror object: hybrid rendering traces the "
                        "local geometry of reflective and refractive objects (000 §1)");
    } else {
        for (const std::string& name : options.objects) {
            int i = scene_.findObject(name);
            if (i < 0) throw Error(where + " has no object '" + name + "'");
            const auto& o = scene_.objects[size_t(i)];
            if (scene_.materials.at(o.material).type == ray::MaterialType::Diffuse)
                throw Error(where + ": object '" + name +
                            "' is diffuse; a lens object must be glass or a mirror");
            chosen.push_back(uint32_t(i));
        }
    }
    // ---- every lens object needs triangles of area (before Embree sees the scene) ----
    for (uint32_t i : chosen) {
        const auto& o = scene_.objects[i];
        const ray::Mesh& m = scene_.meshes.at(o.mesh);
        if (m.indices.size() < 3)
            throw Error(where + ": lens object '" + o.name + "' has no triangle");
    }
    for (const std::string& w : ray::validateScene(scene_)) warnings_.push_back(w);
    accel_ = std::make_unique<ray::Accel>(scene_);
    lensOnly_ = std::make_unique<ray::Scene>(ray::subScene(scene_, chosen));
    visibility_ = std::make_unique<ray::Accel>(*lensOnly_);

    for (uint32_t i : chosen) {
        LensObject L;
        const auto& o = scene_.objects[i];
        L.name = o.name;
        L.object = i;
        L.twoTerms = scene_.materials[o.material].type == ray::MaterialType::Glass;
        L.layers = L.twoTerms ? options.glassLayers : options.mirrorLayers;
        ray::Mesh world = scene_.worldMesh(i);
        std::vector<uint32_t> remap;
        std::vector<glm::vec3> welded;
        weldPositions(world.positions, remap, welded);
        L.positionCount = uint32_t(welded.size());
        // Per position, the classes of normals within the crease angle (greedy, in vertex
        // order): each class is one vertex.
        const float cosCrease = std::cos(kCreaseDegrees * 3.14159265358979f / 180.0f);
        std::vector<std::vector<uint32_t>> classes(welded.size());  // vertex ids per position
        std::vector<uint32_t> vertexOf(world.positions.size());
        for (size_t v = 0; v < world.positions.size(); ++v) {
            const uint32_t pid = remap[v];
            const glm::vec3 n = world.normals[v];
            uint32_t chosen = ~0u;
            for (uint32_t c : classes[pid])
                if (glm::dot(glm::normalize(L.normals[c]), n) >= cosCrease) {
                    chosen = c;
                    break;
                }
            if (chosen == ~0u) {
                chosen = uint32_t(L.positions.size());
                L.positions.push_back(welded[pid]);
                L.normals.push_back(glm::vec3(0.0f));
                L.positionId.push_back(pid);
                classes[pid].push_back(chosen);
            }
            L.normals[chosen] += n;
            vertexOf[v] = chosen;
        }
        for (glm::vec3& n : L.normals) {
            float len = glm::length(n);
            n = len > 0.0f ? n / len : glm::vec3(0.0f, 1.0f, 0.0f);
        }
        for (uint32_t idx : world.indices) L.indices.push_back(vertexOf[idx]);
        std::vector<uint32_t> byPosition;
        for (uint32_t v : L.indices) byPosition.push_back(L.positionId[v]);
        L.closedManifold = closedAfterWelding(byPosition);
        // Only refraction needs an inside: a mirror's paths reflect off its surface, open
        // or not.
        if (!L.closedManifold && L.twoTerms)
            warnings_.push_back(where + ": lens object '" + L.name +
                                "' is glass but its mesh is open or not a 2-manifold even after "
                                "welding (refracted paths may leave through holes; rendered anyway)");
        L.origin = ray::areaWeightedCentroid(world);
        for (const glm::vec3& p : L.positions)
            L.boundingRadius = std::max(L.boundingRadius, glm::length(p - L.origin));
        L.localScene = std::make_unique<ray::Scene>(ray::subScene(scene_, {i}));
        L.local = std::make_unique<ray::Accel>(*L.localScene);
        objects_.push_back(std::move(L));
    }
    if (options.countingTwins) {
        countingAccel();
        countingVisibility();
        for (size_t l = 0; l < objects_.size(); ++l) countingLocal(l);
    }
}

const ray::Accel& LensScene::countingAccel() {
    if (!countingAccel_)
        countingAccel_ = std::make_unique<ray::Accel>(scene_, ray::AccelOptions{true});
    return *countingAccel_;
}

const ray::Accel& LensScene::countingVisibility() {
    if (!countingVisibility_)
        countingVisibility_ = std::make_unique<ray::Accel>(*lensOnly_, ray::AccelOptions{true});
    return *countingVisibility_;
}

const ray::Accel& LensScene::countingLocal(size_t lens) {
    if (countingLocal_.size() < objects_.size()) countingLocal_.resize(objects_.size());
    if (!countingLocal_[lens])
        countingLocal_[lens] =
            std::make_unique<ray::Accel>(*objects_[lens].localScene, ray::AccelOptions{true});
    return *countingLocal_[lens];
}

}  // namespace rg::hybrid
