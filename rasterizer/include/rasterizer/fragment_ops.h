// The per-fragment operations after the texture stages, in Direct3D 7 order:
//   specular add ─▶ alpha test ─▶ depth test (and write) ─▶ blend ─▶ colour write mask
// Each is a one-line function that reads like docs/hardware.md ("Alpha test", "Depth",
// "Blending"). The reference path and the fast path both call exactly these functions,
// so the two agree on every fragment by construction; tests/rasterizer/ checks each one
// against an independent double-precision definition, exhaustively where it is 8-bit.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "core/arith8.h"
#include "core/color.h"
#include "rasterizer/state.h"

namespace rg::raster {

// ---- compare functions (D3DCMPFUNC), shared by the alpha and depth tests --------------
// `incoming FUNC stored`: LESS passes when the fragment's value is below the reference.
// One definition for integer values (alpha, fixed-point depth) and for the programmable
// profile's float depth: T comes from `incoming`, `reference` converts to it.
template <class T>
constexpr bool comparePasses(CompareFunc f, T incoming, std::type_identity_t<T> reference) {
    switch (f) {
        case CompareFunc::Never: return false;
        case CompareFunc::Less: return incoming < reference;
        case CompareFunc::Equal: return incoming == reference;
        case CompareFunc::LessEqual: return incoming <= reference;
        case CompareFunc::Greater: return incoming > reference;
        case CompareFunc::NotEqual: return incoming != reference;
        case CompareFunc::GreaterEqual: return incoming >= reference;
        case CompareFunc::Always: return true;
    }
    return false;
}

// ---- specular add (D3DRS_SPECULARENABLE) -----------------------------------------------
// After the texture stages: rgb = min(rgb + specular.rgb, 255); alpha is untouched
// (the D3D7 specular colour has no alpha contribution; its alpha carries fog).
constexpr Rgba8 addSpecular(Rgba8 c, Rgba8 s) {
    return Rgba8{uint8_t(arith8::addSat(c.r, s.r)), uint8_t(arith8::addSat(c.g, s.g)),
                 uint8_t(arith8::addSat(c.b, s.b)), c.a};
}

// ---- depth (docs/hardware.md, "Depth") -------------------------------------------------
// Window z in [0, 1] → unsigned integer of the buffer's width: floor(z·(2^n − 1) + 1/2)
// in double precision, after clamping z to [0, 1]; NaN counts as 0.
inline uint32_t quantizeDepth(double z, uint32_t depthMax) {
    if (!(z > 0.0)) return 0;
    if (z >= 1.0) return depthMax;
    return uint32_t(std::floor(z * double(depthMax) + 0.5));
}

// ---- blending (docs/hardware.md, "Blending") ------------------------------------------
// The 8-bit value of blend factor `f` for channel `c` (0 r, 1 g, 2 b, 3 a), given the
// incoming colour `s` and the stored colour `d`. Values are k/255 fixed point.
constexpr uint32_t channel(Rgba8 v, int c) {
    return c == 0 ? v.r : c == 1 ? v.g : c == 2 ? v.b : v.a;
}

constexpr uint32_t blendFactorValue(BlendFactor f, int c, Rgba8 s, Rgba8 d) {
    switch (f) {
        case BlendFactor::Zero: return 0;
        case BlendFactor::One: return 255;
        case BlendFactor::SrcColor: return channel(s, c);
        case BlendFactor::InvSrcColor: return 255 - channel(s, c);
        case BlendFactor::SrcAlpha: return s.a;
        case BlendFactor::InvSrcAlpha: return 255u - s.a;
        case BlendFactor::DestAlpha: return d.a;
        case BlendFactor::InvDestAlpha: return 255u - d.a;
        case BlendFactor::DestColor: return channel(d, c);
        case BlendFactor::InvDestColor: return 255 - channel(d, c);
        // (f, f, f, 1) with f = min(As, 1 − Ad)
        case BlendFactor::SrcAlphaSat: return c == 3 ? 255u : std::min<uint32_t>(s.a, 255u - d.a);
        // As a source factor BOTHSRCALPHA is As and BOTHINVSRCALPHA is 1 − As; the
        // destination factor they force is applied by effectiveDestFactor().
        case BlendFactor::BothSrcAlpha: return s.a;
        case BlendFactor::BothInvSrcAlpha: return 255u - s.a;
    }
    return 0;
}

// D3DBLEND_BOTHSRCALPHA / BOTHINVSRCALPHA set the destination factor too, overriding
// D3DRS_DESTBLEND: the Direct3D 7 documentation describes them as SRCALPHA/INVSRCALPHA
// (and the inverse pair) in one setting. Every other source factor leaves it alone.
constexpr BlendFactor effectiveDestFactor(BlendFactor src, BlendFactor dst) {
    if (src == BlendFactor::BothSrcAlpha) return BlendFactor::InvSrcAlpha;
    if (src == BlendFactor::BothInvSrcAlpha) return BlendFactor::SrcAlpha;
    return dst;
}

// One channel: s·fs op d·fd. Products use arith8::mulDiv255 (exact rounding of k/255
// fixed point); add saturates; MIN and MAX ignore the factors (EXT_blend_minmax,
// D3DBLENDOP_MIN/MAX).
constexpr uint32_t blendChannel(BlendOp op, uint32_t s, uint32_t fs, uint32_t d, uint32_t fd) {
    switch (op) {
        case BlendOp::Add: return arith8::addSat(arith8::mulDiv255(s, fs), arith8::mulDiv255(d, fd));
        case BlendOp::Subtract: return arith8::subSat(arith8::mulDiv255(s, fs), arith8::mulDiv255(d, fd));
        case BlendOp::RevSubtract: return arith8::subSat(arith8::mulDiv255(d, fd), arith8::mulDiv255(s, fs));
        case BlendOp::Min: return std::min(s, d);
        case BlendOp::Max: return std::max(s, d);
    }
    return 0;
}

constexpr Rgba8 blendPixel(BlendFactor srcF, BlendFactor dstF, BlendOp op, Rgba8 s, Rgba8 d) {
    BlendFactor df = effectiveDestFactor(srcF, dstF);
    uint32_t out[4];
    for (int c = 0; c < 4; ++c)
        out[c] = blendChannel(op, channel(s, c), blendFactorValue(srcF, c, s, d), channel(d, c),
                              blendFactorValue(df, c, s, d));
    return Rgba8{uint8_t(out[0]), uint8_t(out[1]), uint8_t(out[2]), uint8_t(out[3])};
}

// ---- colour write mask (D3DRS_COLORWRITEENABLE) ---------------------------------------
constexpr Rgba8 applyWriteMask(uint8_t mask, Rgba8 incoming, Rgba8 stored) {
    return Rgba8{(mask & kWriteR) ? incoming.r : stored.r, (mask & kWriteG) ? incoming.g : stored.g,
                 (mask & kWriteB) ? incoming.b : stored.b, (mask & kWriteA) ? incoming.a : stored.a};
}

// ---- interpolated colour to 8 bits (docs/hardware.md, "Interpolation") ----------------
// v is on the 0..255 scale. Clamp (NaN → 0), then round half up: floor(v + 0.5).
inline uint8_t colorToByte(float v) {
    v = v > 0.0f ? v : 0.0f;
    v = v < 255.0f ? v : 255.0f;
    return uint8_t(int(v + 0.5f));
}

}  // namespace rg::raster
