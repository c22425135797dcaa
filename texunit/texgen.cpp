// Texture-coordinate generation (docs/hardware.md, "Coordinate generation").
#include <cmath>

#include <glm/geometric.hpp>

#include "texunit/texgen.h"
#include "texunit/texture_units.h"

namespace rg::tex {

glm::vec3 eyeReflectionVector(const VertexEye& v) {
    // GL 1.2 §2.10.4 / ARB_texture_cube_map: u = unit vector from the eye to the vertex,
    // r = u − 2 n (n·u). Direct3D 7's CAMERASPACEREFLECTIONVECTOR, R = 2(E·N)N − E with E
    // pointing to the eye, is the same vector.
    glm::vec3 p(v.eyePosition);
    float len = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    glm::vec3 u = len > 0.0f ? p / len : glm::vec3(0.0f, 0.0f, -1.0f);
    const glm::vec3& n = v.eyeNormal;
    float nu = n.x * u.x + n.y * u.y + n.z * u.z;
    return u - (2.0f * nu) * n;
}

glm::vec4 generateTexCoord(const TexGenState& g, const VertexEye& v, const glm::vec4& in) {
    glm::vec4 c = in;
    switch (g.mode) {
        case TexGenMode::PassThru: break;
        case TexGenMode::CameraSpaceNormal:
        case TexGenMode::NormalMap: c = glm::vec4(v.eyeNormal, 1.0f); break;
        case TexGenMode::CameraSpacePosition: c = glm::vec4(glm::vec3(v.eyePosition), 1.0f); break;
        case TexGenMode::CameraSpaceReflectionVector:
        case TexGenMode::ReflectionMap: c = glm::vec4(eyeReflectionVector(v), 1.0f); break;
        case TexGenMode::ObjectLinear:
            for (int i = 0; i < 4; ++i) c[i] = glm::dot(g.planes[size_t(i)], v.objectPosition);
            break;
        case TexGenMode::EyeLinear:
            for (int i = 0; i < 4; ++i) c[i] = glm::dot(g.planes[size_t(i)], v.eyePosition);
            break;
        case TexGenMode::SphereMap: {
            // GL 1.2 §2.10.4: m = 2·sqrt(rx² + ry² + (rz + 1)²), s = rx/m + ½, t = ry/m + ½.
            glm::vec3 r = eyeReflectionVector(v);
            float m = 2.0f * std::sqrt(r.x * r.x + r.y * r.y + (r.z + 1.0f) * (r.z + 1.0f));
            if (m > 0.0f)
                c = glm::vec4(r.x / m + 0.5f, r.y / m + 0.5f, 0.0f, 1.0f);
            else
                c = glm::vec4(0.5f, 0.5f, 0.0f, 1.0f);
            break;
        }
    }
    if (g.matrixEnabled) c = g.matrix * c;
    return c;
}

}  // namespace rg::tex
