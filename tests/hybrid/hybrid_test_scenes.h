// Small scenes with closed lens objects for the hybrid tests: a glass ball and a mirror
// box in a room, seen from a camera in front.
#pragma once

#include <glm/gtc/matrix_transform.hpp>

#include "raycore/builtin_scenes.h"
#include "raycore/scene.h"
#include "raycore/shapes.h"

namespace rg::hybrid::test {

inline ray::Material glass(float transmittance = 0.95f) {
    ray::Material m;
    m.name = "glass";
    m.type = ray::MaterialType::Glass;
    m.diffuse = glm::vec3(0.0f);
    m.ior = 1.5f;
    m.transmittance = glm::vec3(transmittance);
    return m;
}

inline ray::Material mirror(float reflectance) {
    ray::Material m;
    m.name = "mirror";
    m.type = ray::MaterialType::Mirror;
    m.diffuse = glm::vec3(0.0f);
    m.reflectance = glm::vec3(reflectance);
    m.fresnel = ray::MirrorFresnel::Constant;
    return m;
}

// A glass ball (radius 1 at (0, 1, 0)) and a mirror box (half size 0.5 at (2.2, 0.5, 0))
// in a 20-unit room; a viewpoint circle of radius 6 around the ball.
inline ray::Scene ballAndBox(int slices = 24, int stacks = 12, bool withBox = true) {
    ray::Scene s;
    s.name = "ball-and-box";
    const uint32_t g = s.addMaterial(glass());
    s.addObject("ball", s.addMesh(ray::makeSphere(1.0f, slices, stacks)), g,
                glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f)));
    if (withBox) {
        const uint32_t m = s.addMaterial(mirror(0.9f));
        s.addObject("box", s.addMesh(ray::makeCube(0.5f)), m,
                    glm::translate(glm::mat4(1.0f), glm::vec3(2.2f, 0.5f, 0.0f)));
    }
    ray::addRoom(s, {-10.0f, 0.0f, -10.0f}, {10.0f, 8.0f, 10.0f});
    s.lights.push_back({"ceiling", {0.0f, 7.0f, 0.0f}, glm::vec3(0.6f)});
    s.ambient = glm::vec3(0.3f);
    ray::ViewpointPath path;
    path.name = "circle";
    path.center = {0.0f, 1.0f, 0.0f};
    path.radius = 6.0f;
    path.height = 1.5f;
    path.stepDegrees = 8.0f;
    path.count = 45;
    s.viewpointPaths.push_back(path);
    ray::Camera c = path.at(0);
    c.name = "default";
    s.cameras.push_back(c);
    return s;
}

}  // namespace rg::hybrid::test
