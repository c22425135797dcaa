// Pinhole camera rays and viewpoint paths.
#include "raycore/camera.h"

#include <cmath>
#include <numbers>

namespace rg::ray {

Ray primaryRay(const Camera& cam, int width, int height, float px, float py) {
    glm::vec3 w = glm::normalize(cam.eye - cam.target);
    glm::vec3 u = glm::normalize(glm::cross(cam.up, w));
    glm::vec3 v = glm::cross(w, u);
    float tanHalf = std::tan(cam.fovYDegrees * std::numbers::pi_v<float> / 360.0f);
    float aspect = float(width) / float(height);
    float sx = (2.0f * px / float(width) - 1.0f) * tanHalf * aspect;
    float sy = (1.0f - 2.0f * py / float(height)) * tanHalf;
    Ray r;
    r.origin = cam.eye;
    r.dir = glm::normalize(sx * u + sy * v - w);
    return r;
}

Camera cameraOnCircle(glm::vec3 center, float radius, float height, float angleDegrees,
                      float fovYDegrees) {
    float a = angleDegrees * std::numbers::pi_v<float> / 180.0f;
    Camera c;
    c.eye = center + glm::vec3(radius * std::cos(a), height, -radius * std::sin(a));
    c.target = center;
    c.fovYDegrees = fovYDegrees;
    return c;
}

Camera ViewpointPath::at(uint32_t i) const {
    Camera c = cameraOnCircle(center, radius, height, startDegrees + stepDegrees * float(i),
                              fovYDegrees);
    c.name = name + ":" + std::to_string(i);
    return c;
}

}  // namespace rg::ray
