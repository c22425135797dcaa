// Material names and the reflectance and attenuation laws of each type.
#include "raycore/material.h"

#include <cmath>

#include "core/error.h"
#include "raycore/fresnel.h"

namespace rg::ray {

const char* materialTypeName(MaterialType t) {
    switch (t) {
        case MaterialType::Diffuse: return "diffuse";
        case MaterialType::Mirror: return "mirror";
        case MaterialType::Glass: return "glass";
    }
    return "?";
}

MaterialType materialTypeFromName(const std::string& n) {
    for (MaterialType t : {MaterialType::Diffuse, MaterialType::Mirror, MaterialType::Glass})
        if (n == materialTypeName(t)) return t;
    throw Error("unknown material type '" + n + "' (diffuse, mirror, glass)");
}

glm::vec3 mirrorReflectance(const Material& m, float cosTheta) {
    return m.fresnel == MirrorFresnel::Schlick ? FresnelSchlick(cosTheta, m.reflectance)
                                               : m.reflectance;
}

glm::vec3 transparencyAttenuation(glm::vec3 transmittance, float thickness) {
    return {std::pow(transmittance.x, thickness), std::pow(transmittance.y, thickness),
            std::pow(transmittance.z, thickness)};
}

}  // namespace rg::ray
