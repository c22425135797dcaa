// The procedural patterns, as plain functions of uv so that tests and the rasterizer demos
// can call them directly. Each is band-limited only by the sampling that calls it.
#pragma once

#include <glm/glm.hpp>

namespace rg::ray {

// Squares alternate a/b; `scale` squares per uv unit.
glm::vec3 checkerPattern(glm::vec2 uv, float scale, glm::vec3 a, glm::vec3 b);
// Running bond: bricks 2:1, rows offset by half a brick, mortar lines 8% of a row.
glm::vec3 bricksPattern(glm::vec2 uv, float scale, glm::vec3 brick, glm::vec3 mortar);
// Concentric rings around the uv centre with a sinusoidal wobble, like end grain.
glm::vec3 woodRingsPattern(glm::vec2 uv, float scale, glm::vec3 light, glm::vec3 dark);
// Linear blend from a (v = 0) to b (v = 1).
glm::vec3 gradientPattern(glm::vec2 uv, glm::vec3 a, glm::vec3 b);

}  // namespace rg::ray
