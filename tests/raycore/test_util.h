// Helpers shared by the raycore tests.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>

#include "core/error.h"
#include "raycore/image.h"
#include "scratch_dir.h"

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

// A fresh folder of the running test and process alone (tests/scratch_dir.h): a fixed
// folder under /tmp was shared by parallel tests and by checkouts, and deleted under them.
inline std::filesystem::path tempDir(const std::string& name) { return rg::test::scratchDir(name); }

// Runs f, expects an rg::Error whose message contains every one of `parts`.
template <class F>
void expectError(F f, std::initializer_list<std::string> parts) {
    try {
        f();
        ADD_FAILURE() << "no error raised";
    } catch (const Error& e) {
        for (const std::string& p : parts)
            EXPECT_NE(std::string(e.what()).find(p), std::string::npos)
                << "message '" << e.what() << "' lacks '" << p << "'";
    }
}

inline void writeText(const std::filesystem::path& p, const std::string& text) {
    std::ofstream(p) << text;
}

inline std::filesystem::path sourceDir() { return RETROGLASS_SOURCE_DIR; }

}  // namespace rg::ray::test
