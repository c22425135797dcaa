// The 8-bit arithmetic shared by framebuffer blending (rasterizer/) and the texture-stage
// cascade (texunit/). Each function is the one-line definition docs/hardware.md gives for
// it; which operator uses which multiply is pinned in docs/hardware.md, "Pinned choices".
#pragma once

#include <algorithm>
#include <cstdint>

namespace rg::arith8 {

// round(a·b / 255) exactly, for a, b in [0, 255]. With t = a·b + 128,
// (t + (t >> 8)) >> 8 equals floor(a·b/255 + 1/2) for every one of the 65,536 pairs
// (Blinn, "Three Wrongs Make a Right", IEEE CG&A 1995). 1·x = x and 255·x = x hold exactly.
constexpr uint32_t mulDiv255(uint32_t a, uint32_t b) {
    uint32_t t = a * b + 128u;
    return (t + (t >> 8)) >> 8;
}

// The shift-based multiply of period hardware: a·(b + 1) >> 8. It differs from
// mulDiv255 in 18,760 of the 65,536 cases but keeps 255·x = x and 0·x = 0.
constexpr uint32_t mulShift(uint32_t a, uint32_t b) { return (a * (b + 1u)) >> 8; }

// Saturating add/subtract to [0, 255].
constexpr uint32_t addSat(uint32_t a, uint32_t b) { return std::min(a + b, 255u); }
constexpr uint32_t subSat(uint32_t a, uint32_t b) { return a > b ? a - b : 0u; }
constexpr uint32_t clamp255(int32_t v) {
    return static_cast<uint32_t>(std::clamp<int32_t>(v, 0, 255));
}

}  // namespace rg::arith8
