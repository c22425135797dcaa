// Texel formats: packed layouts and their expansion (docs/hardware.md, "Texel formats").
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "texunit/format.h"

namespace rg::tex {

namespace {

constexpr std::array<FormatInfo, size_t(TexelFormat::Count)> kFormats = {{
    {"L8", 1, BaseFormat::Luminance, false, false},
    {"A8", 1, BaseFormat::Alpha, false, false},
    {"L8A8", 2, BaseFormat::LuminanceAlpha, false, false},
    {"I8", 1, BaseFormat::Intensity, false, false},
    {"RGB565", 2, BaseFormat::Rgb, false, false},
    {"RGBA4444", 2, BaseFormat::Rgba, false, false},
    {"RGB8", 3, BaseFormat::Rgb, false, false},
    {"RGBA8", 4, BaseFormat::Rgba, false, false},
    {"R16F", 2, BaseFormat::Rgb, true, false},   // (r, 0, 0, 1) as ARB_texture_rg later
    {"RGBA16F", 8, BaseFormat::Rgba, true, false},
    {"R32F", 4, BaseFormat::Rgb, true, false},
    {"RGBA32F", 16, BaseFormat::Rgba, true, false},
    {"Depth16", 2, BaseFormat::Luminance, true, true},
    {"Depth24", 4, BaseFormat::Luminance, true, true},
    {"Depth32F", 4, BaseFormat::Luminance, true, true},
    {"I16", 2, BaseFormat::Intensity, false, false},
}};

uint16_t load16(const uint8_t* p) { return uint16_t(p[0] | (p[1] << 8)); }
uint32_t load32(const uint8_t* p) {
    return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
}
float loadFloat(const uint8_t* p) {
    uint32_t u = load32(p);
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

// Bit replication widens an n-bit field to 8 bits: x5 → x<<3 | x>>2 etc.
constexpr uint8_t widen5(uint32_t x) { return uint8_t((x << 3) | (x >> 2)); }
constexpr uint8_t widen6(uint32_t x) { return uint8_t((x << 2) | (x >> 4)); }
constexpr uint8_t widen4(uint32_t x) { return uint8_t(x * 17u); }

}  // namespace

const FormatInfo& formatInfo(TexelFormat f) { return kFormats.at(size_t(f)); }

std::string_view baseFormatName(BaseFormat b) {
    constexpr std::array<std::string_view, 6> names = {"ALPHA", "LUMINANCE", "LUMINANCE_ALPHA",
                                                       "INTENSITY", "RGB", "RGBA"};
    return names.at(size_t(b));
}

bool hasColor(BaseFormat b) { return b != BaseFormat::Alpha; }
bool hasAlpha(BaseFormat b) {
    return b == BaseFormat::Alpha || b == BaseFormat::LuminanceAlpha ||
           b == BaseFormat::Intensity || b == BaseFormat::Rgba;
}

Rgba8 expandTexel8(TexelFormat f, const uint8_t* p) {
    switch (f) {
        case TexelFormat::L8: return {p[0], p[0], p[0], 255};
        case TexelFormat::A8: return {0, 0, 0, p[0]};
        case TexelFormat::L8A8: return {p[0], p[0], p[0], p[1]};
        case TexelFormat::I8: return {p[0], p[0], p[0], p[0]};
        case TexelFormat::RGB565: {
            uint32_t w = load16(p);
            return {widen5(w >> 11), widen6((w >> 5) & 63), widen5(w & 31), 255};
        }
        case TexelFormat::RGBA4444: {
            uint32_t w = load16(p);
            return {widen4(w >> 12), widen4((w >> 8) & 15), widen4((w >> 4) & 15), widen4(w & 15)};
        }
        case TexelFormat::RGB8: return {p[0], p[1], p[2], 255};
        case TexelFormat::RGBA8: return {p[0], p[1], p[2], p[3]};
        case TexelFormat::I16: {
            const uint8_t i = narrow16(load16(p));
            return {i, i, i, i};
        }
        default: return {};
    }
}

float halfToFloat(uint16_t h) {
    uint32_t sign = uint32_t(h >> 15) << 31, exp = (h >> 10) & 31, man = h & 1023;
    uint32_t bits;
    if (exp == 0) {
        if (man == 0) {
            bits = sign;
        } else {  // subnormal half: renormalize
            int e = -1;
            do { ++e; man <<= 1; } while (!(man & 1024));
            bits = sign | (uint32_t(127 - 15 - e) << 23) | ((man & 1023) << 13);
        }
    } else if (exp == 31) {
        bits = sign | 0x7f800000u | (man << 13);
    } else {
        bits = sign | ((exp + 127 - 15) << 23) | (man << 13);
    }
    float f;
    std::memcpy(&f, &bits, 4);
    return f;
}

glm::vec4 expandTexelFloat(TexelFormat f, const uint8_t* p) {
    switch (f) {
        case TexelFormat::R16F: return {halfToFloat(load16(p)), 0.0f, 0.0f, 1.0f};
        case TexelFormat::RGBA16F:
            return {halfToFloat(load16(p)), halfToFloat(load16(p + 2)), halfToFloat(load16(p + 4)),
                    halfToFloat(load16(p + 6))};
        case TexelFormat::R32F: return {loadFloat(p), 0.0f, 0.0f, 1.0f};
        case TexelFormat::RGBA32F:
            return {loadFloat(p), loadFloat(p + 4), loadFloat(p + 8), loadFloat(p + 12)};
        case TexelFormat::Depth16: {
            float d = float(load16(p)) / 65535.0f;
            return {d, d, d, 1.0f};
        }
        case TexelFormat::Depth24: {
            float d = float(load32(p) & 0xffffffu) / 16777215.0f;
            return {d, d, d, 1.0f};
        }
        case TexelFormat::Depth32F: {
            float d = loadFloat(p);
            return {d, d, d, 1.0f};
        }
        default: return {};
    }
}

Rgba8 floatToRgba8(const glm::vec4& v) {
    auto c = [](float x) {
        if (!(x > 0.0f)) return uint8_t(0);  // NaN → 0
        if (x >= 1.0f) return uint8_t(255);
        return uint8_t(std::floor(x * 255.0f + 0.5f));
    };
    return {c(v.x), c(v.y), c(v.z), c(v.w)};
}

}  // namespace rg::tex
