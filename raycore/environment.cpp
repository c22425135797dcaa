// The environment seen by rays that leave the scene.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "raycore/scene.h"

namespace rg::ray {

glm::vec3 Environment::lookup(glm::vec3 d) const {
    switch (kind) {
        case EnvironmentKind::Constant: return color;
        case EnvironmentKind::Gradient: {
            // Horizon to zenith above, horizon to ground below, blended in elevation.
            float y = d.y;
            return y >= 0.0f ? glm::mix(horizon, zenith, std::sqrt(y))
                             : glm::mix(horizon, ground, std::sqrt(-y));
        }
        case EnvironmentKind::Image: {
            if (!image) return color;
            // Equirectangular: u = longitude from −z through +x, v = 0 at the zenith.
            const float pi = std::numbers::pi_v<float>;
            float u = 0.5f + std::atan2(d.x, -d.z) / (2.0f * pi);
            float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / pi;
            return intensity * sampleBilinearWrap(*image, {u, v}, true);
        }
    }
    return color;
}

}  // namespace rg::ray
