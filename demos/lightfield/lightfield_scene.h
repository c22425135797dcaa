// The scenes of the lightfield reproduction and its viewer demo: the object the light
// fields are built around, its two environments, the slab and the cameras.
#pragma once

#include <string>

#include "lf_capture.h"
#include "light_slab.h"
#include "raycore/camera.h"
#include "raycore/scene.h"

namespace rg::lightfield {

// A glass torus (the paper's Fig. 4 object; Fig. 3's is not named), tilted 60° towards the
// viewer, at the origin, IOR 1.5, lit by blender:interior (standing in for the café of
// [7]) and blender:courtyard. Or a user's first glass or mirror object (--scene), centred
// and scaled to the torus' size, its environment as A.
struct LfScene {
    ray::Scene scene;
    uint32_t object = 0;
    Interaction mode = Interaction::Refract;
    float ior = 1.5f;
    ray::Bounds bounds;
    ray::Environment envA, envB;
    std::string envAName, envBName;
    std::string description;
};
LfScene makeScene(const std::string& file);

// Exposure mapping an environment's mean luminance to 0.3 (clipped at 1 in 8 bits).
float autoExposure(const ray::Environment& env);

// The slab of the geometry light fields: eye points at z = 6 over [−1, 1]², the window at
// z = 0 over [−2, 2]² (it holds the object's shadow from every eye point: validateSlab).
LightSlab geometrySlab(int S, int U);

// Evaluation cameras inside the slab's cone: 0 between eye points, 1 off-axis.
ray::Camera evalCamera(int k);

}  // namespace rg::lightfield
