// Scene bookkeeping and validation.
#include "raycore/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.h"

namespace rg::ray {

namespace {
template <class V>
int findByName(const V& v, const std::string& name) {
    for (size_t i = 0; i < v.size(); ++i)
        if (v[i].name == name) return int(i);
    return -1;
}
// A glass object's flat face in the plane of another object's face that faces it (glass
// resting on a table, pushed against a wall): a ray inside the glass meets both faces at one
// distance, and the tracer's closest hit takes either, pixel by pixel — the glass comes out
// black and speckled (raycore's chess pieces on their board did, until 2026-11-28). Looked
// for where it happens: on the six faces of the glass object's box, each face's triangles
// within the tracer's origin offset of that plane (Accel: 1e-5 of the scene's diagonal times
// 1 + the largest coordinate there; anything nearer the tracer cannot separate) against
// the other objects' triangles in the same plane facing the other way, their extents in the
// plane overlapping; faces under 1 % of the box's face are let be (a point or a thin rim
// touching shows in a few pixels at most). One warning per pair of objects.
void warnGlassInContact(const Scene& scene, const std::vector<Bounds>& placed, const Bounds& all,
                        const std::string& where, std::vector<std::string>& warnings) {
    const float unit = 1e-5f * std::max(glm::length(all.hi - all.lo), 1.0f);
    // Each object's positions in world space, made once and only for the objects a glass
    // object's box meets.
    std::vector<std::vector<glm::vec3>> world(scene.objects.size());
    auto worldOf = [&](size_t i) -> const std::vector<glm::vec3>& {
        std::vector<glm::vec3>& w = world[i];
        if (w.empty()) {
            const Object& o = scene.objects[i];
            w.reserve(scene.meshes[o.mesh].positions.size());
            for (const glm::vec3& p : scene.meshes[o.mesh].positions)
                w.push_back(glm::vec3(o.transform * glm::vec4(p, 1.0f)));
        }
        return w;
    };
    // A glass object's flat face on one side of its box: its triangles within `tol` of the
    // plane `c` facing out of the box, their extent in the plane and their area.
    struct Face {
        float c = 0.0f, tol = 0.0f;
        glm::vec2 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
        double area = 0.0;
        bool shows = false;  // a face, at least 1 % of the box's
    };
    auto inPlane = [](const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2, int axis, float c, float t) {
        return std::fabs(p0[axis] - c) <= t && std::fabs(p1[axis] - c) <= t && std::fabs(p2[axis] - c) <= t;
    };
    static const char* kAxis = "xyz";
    for (size_t g = 0; g < scene.objects.size(); ++g) {
        if (scene.materials[scene.objects[g].material].type != MaterialType::Glass) continue;
        const Mesh& gm = scene.meshes[scene.objects[g].mesh];
        const Bounds& a = placed[g];
        const float pad = unit * (1.0f + std::max({glm::abs(a.lo).x, glm::abs(a.lo).y, glm::abs(a.lo).z,
                                                   glm::abs(a.hi).x, glm::abs(a.hi).y, glm::abs(a.hi).z}));
        Face faces[3][2];
        bool facesMade = false;  // on the first object whose box meets this one's
        for (size_t o = 0; o < scene.objects.size(); ++o) {
            if (o == g) continue;
            const Bounds& b = placed[o];
            if (glm::any(glm::greaterThan(a.lo - pad, b.hi)) || glm::any(glm::greaterThan(b.lo - pad, a.hi))) continue;
            if (!facesMade) {
                facesMade = true;
                const std::vector<glm::vec3>& gw = worldOf(g);
                for (int axis = 0; axis < 3; ++axis)
                    for (int side = 0; side < 2; ++side) {
                        Face& f = faces[axis][side];
                        f.c = side == 0 ? a.lo[axis] : a.hi[axis];
                        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                        for (size_t t = 0; t + 2 < gm.indices.size(); t += 3) {
                            const glm::vec3 &p0 = gw[gm.indices[t]], &p1 = gw[gm.indices[t + 1]], &p2 = gw[gm.indices[t + 2]];
                            const float local = unit * (1.0f + std::max({glm::abs(p0)[u], glm::abs(p0)[v], std::fabs(f.c)}));
                            if (!inPlane(p0, p1, p2, axis, f.c, local)) continue;
                            const float n = glm::cross(p1 - p0, p2 - p0)[axis];
                            if (side == 0 ? !(n < 0.0f) : !(n > 0.0f)) continue;
                            for (const glm::vec3* p : {&p0, &p1, &p2}) {
                                f.lo = glm::min(f.lo, glm::vec2((*p)[u], (*p)[v]));
                                f.hi = glm::max(f.hi, glm::vec2((*p)[u], (*p)[v]));
                            }
                            f.tol = std::max(f.tol, local);
                            f.area += 0.5 * double(std::fabs(n));
                        }
                        // Too small to show: under 1 % of the box's face (a sphere's pole, the
                        // Newell teapot's rim on the floor: 0.4 %).
                        const double boxFace = double(a.hi[u] - a.lo[u]) * double(a.hi[v] - a.lo[v]);
                        f.shows = f.lo.x <= f.hi.x && f.area >= 0.01 * boxFace;
                    }
            }
            const std::vector<glm::vec3>& ow = worldOf(o);
            const Mesh& om = scene.meshes[scene.objects[o].mesh];
            bool warned = false;
            for (int axis = 0; axis < 3 && !warned; ++axis)
                for (int side = 0; side < 2 && !warned; ++side) {
                    const Face& f = faces[axis][side];
                    if (!f.shows) continue;
                    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                    // The other object's triangles in the same plane, facing the glass.
                    for (size_t t = 0; t + 2 < om.indices.size(); t += 3) {
                        const glm::vec3 &p0 = ow[om.indices[t]], &p1 = ow[om.indices[t + 1]], &p2 = ow[om.indices[t + 2]];
                        if (!inPlane(p0, p1, p2, axis, f.c, f.tol)) continue;
                        const float n = glm::cross(p1 - p0, p2 - p0)[axis];
                        if (side == 0 ? !(n > 0.0f) : !(n < 0.0f)) continue;
                        const glm::vec2 tlo = glm::min(glm::min(glm::vec2(p0[u], p0[v]), glm::vec2(p1[u], p1[v])), glm::vec2(p2[u], p2[v]));
                        const glm::vec2 thi = glm::max(glm::max(glm::vec2(p0[u], p0[v]), glm::vec2(p1[u], p1[v])), glm::vec2(p2[u], p2[v]));
                        if (tlo.x >= f.hi.x || tlo.y >= f.hi.y || f.lo.x >= thi.x || f.lo.y >= thi.y) continue;
                        char plane[64], gap[32], areaText[32];
                        std::snprintf(plane, sizeof plane, "%c = %g", kAxis[axis], double(f.c));
                        std::snprintf(gap, sizeof gap, "%.2g", double(f.tol));
                        std::snprintf(areaText, sizeof areaText, "%.3g", f.area);
                        warnings.push_back(where + ": glass object '" + scene.objects[g].name + "' has a flat face of area " +
                                           areaText + " in the plane of '" + scene.objects[o].name + "' (" + plane +
                                           ", within the tracer's ray offset " + gap +
                                           "): a ray inside the glass that reaches it meets both faces at the same distance, "
                                           "and the tracer takes either, pixel by pixel (a glass chess piece on its board "
                                           "came out black and speckled); leave a gap of a few times " + gap +
                                           " (docs/scene-format.md)");
                        warned = true;
                        break;
                    }
                }
        }
    }
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
    std::vector<Bounds> placed;
    placed.reserve(scene.objects.size());
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
        placed.push_back(b);
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
    warnGlassInContact(scene, placed, all, where, warnings);
    return warnings;
}

}  // namespace rg::ray
