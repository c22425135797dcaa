// Helpers shared by the raycore tests.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "raycore/image.h"

namespace rg::ray::test {

// FNV-1a over the raw float bytes of an image: equal hashes ⇔ (practically) equal bytes.
inline uint64_t hashImage(const Image& img) {
    uint64_t h = 1469598103934665603ull;
    const auto* p = reinterpret_cast<const unsigned char*>(img.pixels.data());
    for (size_t i = 0; i < img.pixels.size() * sizeof(float); ++i) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

// A fresh folder under the system temp dir for one test.
inline std::filesystem::path tempDir(const std::string& name) {
    auto d = std::filesystem::temp_directory_path() / ("retroglass_raycore_" + name);
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

inline void writeText(const std::filesystem::path& p, const std::string& text) {
    std::ofstream(p) << text;
}

inline std::filesystem::path sourceDir() { return RETROGLASS_SOURCE_DIR; }

}  // namespace rg::ray::test
