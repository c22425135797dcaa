// The emulated framebuffer: an RGBA8 colour buffer and an optional 16- or 24-bit integer
// depth buffer. Row 0 is the top of the window (Direct3D convention); read-back returns
// rows top to bottom.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/color.h"
#include "rasterizer/state.h"

namespace rg::raster {

class Framebuffer {
  public:
    Framebuffer() = default;
    // Throws rg::InvalidState for a zero or negative size.
    Framebuffer(int width, int height, DepthFormat depth);

    int width() const { return width_; }
    int height() const { return height_; }
    DepthFormat depthFormat() const { return depthFormat_; }
    // Largest representable depth value: 2^16 − 1 or 2^24 − 1.
    uint32_t depthMax() const;

    std::span<Rgba8> color() { return color_; }
    std::span<const Rgba8> color() const { return color_; }
    std::span<uint32_t> depth() { return depth_; }
    std::span<const uint32_t> depth() const { return depth_; }

    Rgba8& pixel(int x, int y) { return color_[size_t(y) * width_ + x]; }
    const Rgba8& pixel(int x, int y) const { return color_[size_t(y) * width_ + x]; }

  private:
    int width_ = 0, height_ = 0;
    DepthFormat depthFormat_ = DepthFormat::None;
    std::vector<Rgba8> color_;
    std::vector<uint32_t> depth_;
};

}  // namespace rg::raster
