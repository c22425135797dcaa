#include "orbit_camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rg::viewer {

namespace {
constexpr float kDeg = std::numbers::pi_v<float> / 180.0f;
}

OrbitCamera OrbitCamera::fromCamera(const ray::Camera& c) {
    OrbitCamera o;
    o.target = c.target;
    glm::vec3 d = c.eye - c.target;
    o.distance = std::max(1e-4f, glm::length(d));
    o.azimuthDegrees = std::atan2(-d.z, d.x) / kDeg;
    o.elevationDegrees = std::asin(std::clamp(d.y / o.distance, -1.0f, 1.0f)) / kDeg;
    o.fovYDegrees = c.fovYDegrees;
    return o;
}

ray::Camera OrbitCamera::camera() const {
    ray::Camera c;
    const float a = azimuthDegrees * kDeg, e = elevationDegrees * kDeg;
    c.eye = target + distance * glm::vec3(std::cos(e) * std::cos(a), std::sin(e),
                                          -std::cos(e) * std::sin(a));
    c.target = target;
    c.fovYDegrees = fovYDegrees;
    c.name = "orbit";
    return c;
}

void OrbitCamera::orbit(float dAzimuth, float dElevation) {
    azimuthDegrees = std::remainder(azimuthDegrees + dAzimuth, 360.0f);
    elevationDegrees = std::clamp(elevationDegrees + dElevation, -89.0f, 89.0f);
}

void OrbitCamera::dolly(float factor, float minDistance, float maxDistance) {
    distance = std::clamp(distance * factor, minDistance, maxDistance);
}

void OrbitCamera::pan(float dx, float dy) {
    ray::Camera c = camera();
    glm::vec3 forward = glm::normalize(c.target - c.eye);
    glm::vec3 right = glm::normalize(glm::cross(forward, glm::vec3(0, 1, 0)));
    glm::vec3 up = glm::cross(right, forward);
    target += distance * (dx * right + dy * up);
}

void OrbitCamera::raise(float d) {
    // The eye moves straight up (the PEM paper's "above the plane of the samples"),
    // still looking at the target.
    ray::Camera c = camera();
    c.eye.y += d * distance;
    OrbitCamera o = fromCamera(c);
    o.elevationDegrees = std::clamp(o.elevationDegrees, -89.0f, 89.0f);
    *this = o;
}

}  // namespace rg::viewer
