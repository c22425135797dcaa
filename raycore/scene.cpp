// Scene bookkeeping and validation.
#include "raycore/scene.h"

#include "core/error.h"

namespace rg::ray {

namespace {
template <class V>
int findByName(const V& v, const std::string& name) {
    for (size_t i = 0; i < v.size(); ++i)
        if (v[i].name == name) return int(i);
    return -1;
}
}  // namespace

int Scene::findObject(const std::string& n) const { return findByName(objects, n); }
int Scene::findMaterial(const std::string& n) const { return findByName(materials, n); }
int Scene::findTexture(const std::string& n) const { return findByName(textures, n); }
int Scene::findCamera(const std::string& n) const { return findByName(cameras, n); }
int Scene::findViewpointPath(const std::string& n) const { return findByName(viewpointPaths, n); }

uint32_t Scene::addMesh(Mesh m) {
    completeMesh(m);
    meshes.push_back(std::move(m));
    return uint32_t(meshes.size() - 1);
}
uint32_t Scene::addMaterial(Material m) {
    materials.push_back(std::move(m));
    return uint32_t(materials.size() - 1);
}
uint32_t Scene::addTexture(Texture t) {
    textures.push_back(std::move(t));
    return uint32_t(textures.size() - 1);
}
uint32_t Scene::addObject(std::string n, uint32_t mesh, uint32_t material, const glm::mat4& xf) {
    objects.push_back({std::move(n), mesh, material, xf});
    return uint32_t(objects.size() - 1);
}

Mesh Scene::worldMesh(uint32_t object) const {
    const Object& o = objects.at(object);
    Mesh m = meshes.at(o.mesh);
    transformMesh(m, o.transform);
    m.name = o.name;
    return m;
}

Scene subScene(const Scene& scene, const std::vector<uint32_t>& keep) {
    if (keep.empty()) throw Error("scene '" + scene.name + "': a sub-scene of no objects");
    Scene out = scene;
    out.objects.clear();
    for (uint32_t i : keep) {
        if (i >= scene.objects.size())
            throw Error("scene '" + scene.name + "': no object " + std::to_string(i));
        out.objects.push_back(scene.objects[i]);
    }
    return out;
}

std::vector<std::string> validateScene(const Scene& scene, const std::string& label) {
    std::vector<std::string> warnings;
    const std::string where = !label.empty()              ? label
                              : scene.sourceFile.empty() ? "scene '" + scene.name + "'"
                                                         : scene.sourceFile.string();
    if (scene.objects.empty()) throw Error(where + ": the scene has no objects");
    for (size_t i = 0; i < scene.materials.size(); ++i) {
        const Material& m = scene.materials[i];
        if (m.diffuseTexture >= int(scene.textures.size()))
            throw Error(where + ": material '" + m.name + "' refers to texture " +
                        std::to_string(m.diffuseTexture) + ", which does not exist");
        if (m.type == MaterialType::Glass && !(m.ior > 0.0f))
            throw Error(where + ": glass material '" + m.name + "' needs ior > 0");
    }
    std::vector<int> glassChecked(scene.meshes.size(), -1);
    Bounds all;  // of every placed object, as Accel sizes its ray offsets by them
    for (const Object& o : scene.objects) {
        if (o.mesh >= scene.meshes.size())
            throw Error(where + ": object '" + o.name + "' refers to a mesh that does not exist");
        if (o.material >= scene.materials.size())
            throw Error(where + ": object '" + o.name + "' refers to a material that does not exist");
        // The mesh as given and as its transform places it: a scale of 0 or of 1e30 turns a
        // good mesh into one of no area or of an extent past float's range.
        const Bounds b = validatePlacedMesh(scene.meshes[o.mesh], o.transform,
                                            where + ": object '" + o.name + "'");
        all.lo = glm::min(all.lo, b.lo);
        all.hi = glm::max(all.hi, b.hi);
        if (scene.materials[o.material].type == MaterialType::Glass) {
            int& c = glassChecked[o.mesh];
            if (c < 0) c = isClosedManifold(scene.meshes[o.mesh]) ? 1 : 0;
            if (c == 0)
                warnings.push_back(where + ": object '" + o.name +
                                   "' is glass but its mesh is not closed; refraction through "
                                   "it has no well-defined inside (rendered anyway)");
        }
    }
    validateExtent(all, where + ": the objects together");
    return warnings;
}

}  // namespace rg::ray
