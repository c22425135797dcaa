// Fresnel reflectance and the ray directions at an interface (000 §3: the coefficients
// F̂_R and F̂_T = 1 − F̂_R that weight the two children of a ray striking glass).
#pragma once

#include <glm/glm.hpp>

namespace rg::ray {

// Exact reflectance of unpolarized light at a dielectric interface, the mean of the s and
// p Fresnel equations. cosThetaI > 0 is the cosine between the incident direction
// (reversed) and the normal on the incident side; etaI, etaT the refractive indices of the
// incident and transmitting media. Returns 1 under total internal reflection.
float FresnelDielectric(float cosThetaI, float etaI, float etaT);

// Schlick's approximation F0 + (1 − F0)(1 − cosθ)^5 (Schlick 1993; 001 §5 uses it for the
// Fresnel modulation layer).
float FresnelSchlick(float cosTheta, float F0);
glm::vec3 FresnelSchlick(float cosTheta, glm::vec3 F0);

// Reflectance at normal incidence of an interface of relative index n: ((n−1)/(n+1))².
inline float FresnelNormalIncidence(float n) { return ((n - 1) / (n + 1)) * ((n - 1) / (n + 1)); }

// Mirror direction of d about n (d towards the surface, n unit).
glm::vec3 reflectDir(glm::vec3 d, glm::vec3 n);
// Refracted direction of unit d through a surface with unit normal n on the incident side
// (dot(d, n) < 0) and eta = etaI/etaT. Returns false on total internal reflection.
bool refractDir(glm::vec3 d, glm::vec3 n, float eta, glm::vec3* t);

}  // namespace rg::ray
