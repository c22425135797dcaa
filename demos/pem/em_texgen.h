// Per-vertex EM texture-coordinate generation in software (001 §4 "To index such maps"):
// bounce the view ray off the vertex about its normal, intersect the reflected ray with
// the EM geometry, subtract the EM origin, and hand the unnormalized vector to the
// cube-map unit. Also the per-vertex Schlick shader's coordinate for the 1D Fresnel
// texture (001 §5): u = cos θ = −v·n.
#pragma once

#include <memory>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "pem_scene.h"
#include "texunit/texture.h"

namespace rg::pem {

struct EmTexCoords {
    std::vector<glm::vec4> local, distant, infinite;  // (x, y, z, 1) cube-map indices
    std::vector<glm::vec4> fresnel;                   // (cos θ, 0, 0, 1)
    int escaped = 0;  // reflected rays that did not leave a finite shell (origin outside)
};

// For every vertex of `part` seen from `eye`.
void generateEmTexCoords(const PemPart& part, const glm::vec3& eye, EmTexCoords& out);

// The 1D Schlick texture: texel i holds F(cos θ = (i + ½)/size) =
// F0 + (1 − F0)(1 − cos θ)^5 per channel, RGBA8 (alpha 255), linear filtering.
std::shared_ptr<tex::Texture> makeFresnelTexture(tex::TextureMemory& memory, const glm::vec3& f0,
                                                 int size = 256);

}  // namespace rg::pem
