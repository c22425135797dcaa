#include "impostor_height_maps.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "raycore/accel.h"
#include "raycore/scene.h"

namespace rg::impostors {

HeightMap buildHeightMap(const ray::Mesh& mesh, const glm::vec3& centre, int size, int steps) {
    if (size < 4) throw Error("impostors: a refractor height map of " + std::to_string(size) + "² texels is too small");
    const ray::Bounds b = ray::computeBounds(mesh);
    // The billboard's axis (model x, z) and the reach of the mesh from it.
    glm::vec2 axis(0.0f);
    if (!(b.lo.x <= 0.0f && b.hi.x >= 0.0f && b.lo.z <= 0.0f && b.hi.z >= 0.0f))
        axis = glm::vec2(0.5f * (b.lo.x + b.hi.x), 0.5f * (b.lo.z + b.hi.z));
    float reach = 0.0f;
    for (const glm::vec3& p : mesh.positions) reach = std::max(reach, std::hypot(p.x - axis.x, p.z - axis.y));
    // Two texels of padding each side: n texels cover the domain plus 4 texels.
    const float sHalf = reach * float(size) / float(size - 4);
    const float tPad = (b.hi.y - b.lo.y) * 2.0f / float(size - 4);
    HeightMap m;
    m.size = size;
    m.texels.assign(size_t(size) * size_t(size), glm::vec4(0.0f));
    HeightFrame& f = m.frame;
    f.axis[0] = axis.x - centre.x;
    f.axis[1] = axis.y - centre.z;
    f.sLo = -sHalf;
    f.sHi = sHalf;
    f.tLo = b.lo.y - tPad - centre.y;
    f.tHi = b.hi.y + tPad - centre.y;
    f.steps = steps;
    // The picture: per texel centre (s, t) a ray from beyond the mesh down −z to the plane
    // z = 0 (in the model frame, the plane through the axis); the first surface it meets is
    // the height, its shading normal turned outwards the normal. Nothing met above the plane:
    // an empty texel.
    ray::Scene one;
    one.name = "height map";
    ray::Material glass;
    glass.type = ray::MaterialType::Glass;
    one.addObject("piece", one.addMesh(mesh), one.addMaterial(glass));
    ray::Accel accel(one);
    const float zTop = b.hi.z + 1.0f;  // the camera's plane, beyond the mesh
    float hHigh = 0.0f;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float s = f.sLo + (float(x) + 0.5f) / float(size) * (f.sHi - f.sLo);
            const float t = f.tHi - (float(y) + 0.5f) / float(size) * (f.tHi - f.tLo);
            ray::Ray r;
            r.origin = glm::vec3(axis.x + s, t + centre.y, zTop);
            r.dir = glm::vec3(0.0f, 0.0f, -1.0f);
            r.tfar = zTop - axis.y;  // down to the plane of symmetry (model z = the axis's z)
            const ray::Hit hit = accel.intersect(r);
            if (!hit.valid()) continue;
            const ray::SurfacePoint sp = accel.surface(r, hit);
            const float h = sp.p.z - axis.y;
            if (!(h >= 0.0f)) continue;
            glm::vec3 n = sp.frontFace ? sp.ns : -sp.ns;
            m.texels[size_t(y) * size_t(size) + size_t(x)] = glm::vec4(n.x, n.y, n.z, h);
            hHigh = std::max(hHigh, h);
            ++m.coveredTexels;
        }
    f.hMax = std::max(hHigh, reach) * 1.01f + 1e-4f;
    return m;
}

}  // namespace rg::impostors
