// Floating-point images and their files (OpenImageIO): PNG, EXR, HDR, anything OIIO reads.
// Values are linear; writing to an 8-bit format clamps to [0,1] and rounds v·255 to the
// nearest integer with no transfer curve, the same 8-bit mapping the emulated framebuffers
// use, so that a PNG from the ray tracer and one from the rasterizer compare byte for byte.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rg::ray {

struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels;  // row-major, top row first, channels interleaved

    Image() = default;
    Image(int w, int h, int c, float fill = 0.0f)
        : width(w), height(h), channels(c), pixels(size_t(w) * h * c, fill) {}
    float& at(int x, int y, int c) { return pixels[(size_t(y) * width + x) * channels + c]; }
    float at(int x, int y, int c) const {
        return pixels[(size_t(y) * width + x) * channels + c];
    }
    glm::vec3 rgb(int x, int y) const;  // a 1-channel image reads as grey
    void setRgb(int x, int y, glm::vec3 v);
    bool empty() const { return pixels.empty(); }
};

// Raises rg::Error naming the file when it is missing or unreadable.
Image readImage(const std::filesystem::path& path);
// The format follows the extension (.png, .exr, .hdr, .tif, ...). Raises rg::Error.
void writeImage(const std::filesystem::path& path, const Image& image);

// The 8-bit quantization writeImage uses for 8-bit formats: round(clamp(v,0,1)·255).
uint8_t quantize8(float v);
std::vector<uint8_t> toBytes8(const Image& image);

// Texel lookup with bilinear filtering (uv in [0,1] spans the image once; v = 0 is the top
// row). u always wraps around; v wraps too unless clampV (lat-long maps: the poles are
// edges, not a seam).
glm::vec3 sampleBilinearWrap(const Image& image, glm::vec2 uv, bool clampV = false);

}  // namespace rg::ray
