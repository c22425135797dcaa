// Materials of the papers' scenes: diffuse (textured), mirror (constant reflectance or
// Schlick Fresnel) and glass (index of refraction, exact dielectric Fresnel, and 000 §3's
// transparency attenuation: a per-channel constant raised to the thickness traversed).
#pragma once

#include <glm/glm.hpp>

#include <string>

namespace rg::ray {

enum class MaterialType { Diffuse, Mirror, Glass };
enum class MirrorFresnel { Constant, Schlick };

struct Material {
    std::string name;
    MaterialType type = MaterialType::Diffuse;
    // Diffuse reflectance (any type may carry a diffuse part; a pure mirror has 0), times
    // the texture when diffuseTexture ≥ 0.
    glm::vec3 diffuse{0.8f};
    int diffuseTexture = -1;  // index into Scene::textures
    // Mirror: reflectance (Constant) or F0 (Schlick).
    glm::vec3 reflectance{0.9f};
    MirrorFresnel fresnel = MirrorFresnel::Constant;
    // Glass.
    float ior = 1.5f;
    glm::vec3 transmittance{1.0f};  // fraction kept per unit length of glass traversed
    friend bool operator==(const Material&, const Material&) = default;
};

const char* materialTypeName(MaterialType t);
// Raises rg::Error for an unknown name.
MaterialType materialTypeFromName(const std::string& name);

// Mirror reflectance at the cosine of incidence (Constant or Schlick, per channel).
glm::vec3 mirrorReflectance(const Material& m, float cosTheta);

// 000 §3's G for one straight segment inside glass: transmittance^thickness per channel.
glm::vec3 transparencyAttenuation(glm::vec3 transmittance, float thickness);

}  // namespace rg::ray
