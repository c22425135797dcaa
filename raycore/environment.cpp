// The environment seen by rays that leave the scene, and the equirectangular images it
// can be: files, or the CC0 worlds of Debian's blender-data package by short name.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <set>

#include "core/error.h"
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
            const float pi = std::numbers::pi_v<float>;
            if (rotateDegrees != 0.0f) {
                // d turned by −a about +y, so that the image turns by +a.
                const float a = rotateDegrees * (pi / 180.0f);
                const float c = std::cos(a), s = std::sin(a);
                d = glm::vec3(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
            }
            // Equirectangular (scene.h): u = longitude from −z through +x, v = 0 at the zenith.
            float u = 0.5f + std::atan2(d.x, -d.z) / (2.0f * pi);
            float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / pi;
            return intensity * sampleBilinearWrap(*image, {u, v}, true);
        }
    }
    return color;
}

std::filesystem::path blenderWorldDir() {
    if (const char* dir = std::getenv("RETROGLASS_BLENDER_WORLDS"); dir && *dir) return dir;
    return "/usr/share/blender/datafiles/studiolights/world";
}

std::filesystem::path blenderWorldPath(const std::string& name) {
    const std::filesystem::path dir = blenderWorldDir();
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec))
        throw Error("environment 'blender:" + name + "': " + dir.string() +
                    " not found — it comes with Debian's blender-data package "
                    "(apt-get install blender-data; ./retroglass installs it)");
    const std::filesystem::path file = dir / (name + ".exr");
    if (name.find('/') == std::string::npos && std::filesystem::is_regular_file(file, ec)) return file;
    std::set<std::string> names;  // sorted, so the message does not depend on the file system
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
        if (e.path().extension() == ".exr") names.insert(e.path().stem().string());
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    throw Error("environment 'blender:" + name + "': no " + name + ".exr in " + dir.string() +
                " (known: " + (known.empty() ? "none" : known) + ")");
}

Image readEnvironmentImage(const std::filesystem::path& path) {
    Image img = readImage(path);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < img.channels; ++c) {
                float& v = img.at(x, y, c);
                if (!std::isfinite(v))
                    throw Error(path.string() + ": environment texel (" + std::to_string(x) + ", " +
                                std::to_string(y) + ") channel " + std::to_string(c) +
                                " is not a finite number");
                if (v < 0.0f) v = 0.0f;
            }
    return img;
}

}  // namespace rg::ray
