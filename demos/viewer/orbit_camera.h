// The viewer's camera: an orbit around a target (azimuth, elevation, distance), the way
// the PEM paper's viewpoints circle the teapot. Azimuth follows ray::cameraOnCircle
// (0° = +x, counter-clockwise seen from above), so a demo's viewpoint samples are
// reached exactly.
#pragma once

#include "raycore/camera.h"

namespace rg::viewer {

struct OrbitCamera {
    glm::vec3 target{0.0f};
    float azimuthDegrees = 0.0f;
    float elevationDegrees = 0.0f;  // above the target's horizontal plane
    float distance = 1.0f;
    float fovYDegrees = 40.0f;

    static OrbitCamera fromCamera(const ray::Camera& camera);
    ray::Camera camera() const;

    void orbit(float dAzimuth, float dElevation);   // degrees; elevation kept in (−89°, 89°)
    void dolly(float factor, float minDistance, float maxDistance);
    // Moves target and eye together in the image plane, in units of the distance.
    void pan(float dx, float dy);
    // Raises the eye by `d` (in units of the distance), still looking at the target.
    void raise(float d);
    friend bool operator==(const OrbitCamera&, const OrbitCamera&) = default;
};

}  // namespace rg::viewer
