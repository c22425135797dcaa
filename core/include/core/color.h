// Colour values as the emulated hardware stores them.
#pragma once

#include <cstdint>
#include <type_traits>

namespace rg {

// One RGBA8 pixel or texel, bytes in memory order R, G, B, A. The framebuffer and every
// 8-bit texture format expand to this after fetch (docs/hardware.md, "Texel formats").
struct Rgba8 {
    uint8_t r = 0, g = 0, b = 0, a = 0;
    friend bool operator==(const Rgba8&, const Rgba8&) = default;
};
static_assert(sizeof(Rgba8) == 4 && std::has_unique_object_representations_v<Rgba8>);

}  // namespace rg
