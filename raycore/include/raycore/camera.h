// Pinhole cameras, primary rays, and the viewpoint paths the papers pre-render along
// (001 §6: a 1D viewspace circling the teapot at 1° per view).
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <string>

namespace rg::ray {

struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 dir{0.0f, 0.0f, -1.0f};  // unit length
    float tnear = 0.0f;
    float tfar = 1e30f;
};

struct Camera {
    std::string name;
    glm::vec3 eye{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovYDegrees = 45.0f;
    friend bool operator==(const Camera&, const Camera&) = default;
};

// The ray through film position (px, py) in pixels, (0,0) the top-left corner of the
// image, x right, y down; pixel (i, j) covers [i, i+1)×[j, j+1).
Ray primaryRay(const Camera& cam, int width, int height, float px, float py);

// Film position of sample (sx, sy) of an n×n supersampling grid in pixel (x, y): the
// centre of the sample's stratum. Keyed only by (pixel, sample) — never by thread — so
// images are identical for any thread count.
inline glm::vec2 samplePosition(int x, int y, int sx, int sy, int n) {
    return {float(x) + (float(sx) + 0.5f) / float(n), float(y) + (float(sy) + 0.5f) / float(n)};
}

// A named viewpoint path: `count` viewpoints on a horizontal circle around `center` at
// `radius`, `height` above it, starting at `startDegrees` (0 = +x, counter-clockwise seen
// from above, i.e. towards −z) in steps of `stepDegrees`, all looking at `center`.
struct ViewpointPath {
    std::string name;
    glm::vec3 center{0.0f};
    float radius = 8.0f;
    float height = 2.0f;
    float startDegrees = 0.0f;
    float stepDegrees = 1.0f;
    uint32_t count = 100;
    float fovYDegrees = 40.0f;
    Camera at(uint32_t i) const;
    friend bool operator==(const ViewpointPath&, const ViewpointPath&) = default;
};

Camera cameraOnCircle(glm::vec3 center, float radius, float height, float angleDegrees,
                      float fovYDegrees = 40.0f);

}  // namespace rg::ray
