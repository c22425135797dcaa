#include "rasterizer/framebuffer.h"

#include <string>

#include "core/error.h"

namespace rg::raster {

Framebuffer::Framebuffer(int width, int height, DepthFormat depth)
    : width_(width), height_(height), depthFormat_(depth) {
    if (width <= 0 || height <= 0)
        throw InvalidState("framebuffer size " + std::to_string(width) + "x" +
                           std::to_string(height) + " is empty");
    color_.assign(size_t(width) * size_t(height), Rgba8{0, 0, 0, 0});
    if (depth != DepthFormat::None) depth_.assign(size_t(width) * size_t(height), depthMax());
}

uint32_t Framebuffer::depthMax() const {
    switch (depthFormat_) {
        case DepthFormat::D16: return (1u << 16) - 1u;
        case DepthFormat::D24: return (1u << 24) - 1u;
        case DepthFormat::None: break;
    }
    return 0;
}

}  // namespace rg::raster
