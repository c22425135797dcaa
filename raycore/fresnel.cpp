// Fresnel equations and interface directions.
#include "raycore/fresnel.h"

#include <algorithm>
#include <cmath>

namespace rg::ray {

float FresnelDielectric(float cosThetaI, float etaI, float etaT) {
    cosThetaI = std::clamp(cosThetaI, 0.0f, 1.0f);
    // Snell: sinθt = ηi/ηt · sinθi.
    float sinThetaI = std::sqrt(std::max(0.0f, 1.0f - cosThetaI * cosThetaI));
    float sinThetaT = etaI / etaT * sinThetaI;
    if (sinThetaT >= 1.0f) return 1.0f;  // total internal reflection
    float cosThetaT = std::sqrt(std::max(0.0f, 1.0f - sinThetaT * sinThetaT));
    // Amplitude reflection coefficients for light polarized perpendicular (s) and parallel
    // (p) to the plane of incidence; unpolarized reflectance is their mean square.
    float rs = (etaI * cosThetaI - etaT * cosThetaT) / (etaI * cosThetaI + etaT * cosThetaT);
    float rp = (etaT * cosThetaI - etaI * cosThetaT) / (etaT * cosThetaI + etaI * cosThetaT);
    return 0.5f * (rs * rs + rp * rp);
}

float FresnelSchlick(float cosTheta, float F0) {
    float m = 1.0f - std::clamp(cosTheta, 0.0f, 1.0f);
    float m2 = m * m;
    return F0 + (1.0f - F0) * (m2 * m2 * m);
}

glm::vec3 FresnelSchlick(float cosTheta, glm::vec3 F0) {
    return {FresnelSchlick(cosTheta, F0.x), FresnelSchlick(cosTheta, F0.y),
            FresnelSchlick(cosTheta, F0.z)};
}

glm::vec3 reflectDir(glm::vec3 d, glm::vec3 n) { return d - 2.0f * glm::dot(d, n) * n; }

bool refractDir(glm::vec3 d, glm::vec3 n, float eta, glm::vec3* t) {
    float cosI = -glm::dot(d, n);
    float k = 1.0f - eta * eta * (1.0f - cosI * cosI);
    if (k < 0.0f) return false;
    *t = glm::normalize(eta * d + (eta * cosI - std::sqrt(k)) * n);
    return true;
}

}  // namespace rg::ray
