// SGIX_pixel_texture: during a pixel transfer each pixel's colour becomes the texture
// coordinate of a lookup whose texel replaces the pixel (docs/hardware.md, "Pixel
// texture").
#pragma once

#include <cstdint>

namespace rg::tex {

enum class PixelTexGenMode : uint8_t {
    Rgba,  // (R, G, B, A)/255 → (s, t, r, q); the texel replaces R, G, B and A
    Rgb,   // (R, G, B)/255 → (s, t, r), q = 1; the texel replaces R, G, B, A is kept
};

struct PixelTextureState {
    bool enabled = false;
    PixelTexGenMode mode = PixelTexGenMode::Rgba;
    uint8_t stage = 0;  // the unit whose texture, sampler and colour table are used
    friend bool operator==(const PixelTextureState&, const PixelTextureState&) = default;
};

}  // namespace rg::tex
