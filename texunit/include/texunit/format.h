// Texel formats: how uploaded bytes are laid out and how a texel expands to the RGBA the
// filters and stages see (docs/hardware.md, "Texel formats").
//
// 8-bit formats expand once, at upload, to Rgba8 (storage keeps the expanded texels and
// counts memory in the format's packed size). Float and depth formats (geforce8800) keep
// a glm::vec4 per texel and are converted to 8 bits only after filtering.
#pragma once

#include <cstdint>
#include <string_view>

#include <glm/vec4.hpp>

#include "core/color.h"

namespace rg::tex {

enum class TexelFormat : uint8_t {
    L8,        // GL_LUMINANCE8 / D3DFMT_L8
    A8,        // GL_ALPHA8 / D3DFMT_A8
    L8A8,      // GL_LUMINANCE8_ALPHA8 / D3DFMT_A8L8; bytes L, A
    I8,        // GL_INTENSITY8 (no D3D7 twin): also the VQ index texture of Heidrich et al.
    RGB565,    // 16-bit little-endian word, R in bits 15..11, G 10..5, B 4..0
    RGBA4444,  // 16-bit little-endian word, R in bits 15..12, G 11..8, B 7..4, A 3..0
    RGB8,      // bytes R, G, B
    RGBA8,     // bytes R, G, B, A
    R16F,      // IEEE half, little-endian (geforce8800)
    RGBA16F,
    R32F,      // IEEE float
    RGBA32F,
    Depth16,   // 16-bit unsigned normalized depth
    Depth24,   // 32-bit little-endian word, depth in bits 23..0
    Depth32F,  // IEEE float depth
    // GL_INTENSITY16: a 16-bit little-endian index, the 2-byte VQ index texture of Heidrich
    // et al. 1999 §5 (sgi-octane-mxe). Filtered at 16 bits; through a colour table the
    // filtered value indexes it at 16-bit precision (colorTableIndex16), without one it
    // expands to (I, I, I, I) with I = round(v·255/65535). Appended last so that the trace
    // format's enumerator values of the older formats stay as they were.
    I16,
    Count
};

// The OpenGL 1.2 base internal formats (Table 3.15): which components a texel carries.
// The texture environments and the colour-table rules are written per base format.
enum class BaseFormat : uint8_t { Alpha, Luminance, LuminanceAlpha, Intensity, Rgb, Rgba };

struct FormatInfo {
    std::string_view name;
    int bytesPerTexel;    // packed size in emulated texture memory
    BaseFormat base;
    bool isFloat;         // stored as vec4 (float and depth formats)
    bool isDepth;
};

const FormatInfo& formatInfo(TexelFormat f);
std::string_view baseFormatName(BaseFormat b);
bool hasColor(BaseFormat b);  // carries R, G, B (L, LA, I, RGB, RGBA)
bool hasAlpha(BaseFormat b);  // carries A (A, LA, I, RGBA)

// One packed texel → RGBA8 (8-bit formats only). The OpenGL 1.2 expansion (Table 3.15):
// L → (L, L, L, 255), A → (0, 0, 0, A), LA → (L, L, L, A), I → (I, I, I, I),
// RGB → (R, G, B, 255). 5/6/4-bit fields widen by bit replication (x5 → x<<3 | x>>2),
// as the period texture units did: exact x·17 for n = 4; for 5 and 6 bits within one
// step of x·255/(2^n−1), off its rounding in 4 of 32 and 10 of 64 values.
Rgba8 expandTexel8(TexelFormat f, const uint8_t* bytes);
// A 16-bit intensity as the 8-bit stages see it without a colour table:
// round(v·255/65535) = ⌊(v·255 + 32767)/65535⌋.
inline uint8_t narrow16(uint32_t v) { return uint8_t((v * 255u + 32767u) / 65535u); }
// One packed texel → float RGBA (float and depth formats; depth d → (d, d, d, 1)).
glm::vec4 expandTexelFloat(TexelFormat f, const uint8_t* bytes);
float halfToFloat(uint16_t h);

// Filtered float colour → 8 bits for the fixed-function stages: round(clamp(v)·255).
Rgba8 floatToRgba8(const glm::vec4& v);

}  // namespace rg::tex
