// Fixed-function pipeline state: small values, compared and hashed bytewise.
//
// As in SwiftShader, the state that selects a specialised inner loop (PipelineState) is
// kept apart from per-draw values. Every enum is one byte and the struct has no padding,
// so `==` and hashing over the bytes are safe (checked by the static_asserts below).
#pragma once

#include <cstdint>
#include <type_traits>

#include "core/color.h"

namespace rg::raster {

// D3DCMPFUNC order (NEVER=1 … ALWAYS=8, minus one); GL's compare functions map 1:1.
enum class CompareFunc : uint8_t { Never, Less, Equal, LessEqual, Greater, NotEqual, GreaterEqual, Always };

// D3DBLEND, in the order of the Direct3D 7 enumeration.
enum class BlendFactor : uint8_t {
    Zero, One, SrcColor, InvSrcColor, SrcAlpha, InvSrcAlpha, DestAlpha, InvDestAlpha,
    DestColor, InvDestColor, SrcAlphaSat, BothSrcAlpha, BothInvSrcAlpha
};

// D3DBLENDOP (Direct3D 8) / EXT_blend_subtract, EXT_blend_minmax.
enum class BlendOp : uint8_t { Add, Subtract, RevSubtract, Min, Max };

// D3DCULL: CW culls clockwise-wound triangles (in window space, y down), CCW the others.
enum class CullMode : uint8_t { None, CW, CCW };

enum class ShadeMode : uint8_t { Flat, Gouraud };

enum class DepthFormat : uint8_t { None, D16, D24 };

// Colour write mask bits (D3DRS_COLORWRITEENABLE / glColorMask).
enum : uint8_t { kWriteR = 1, kWriteG = 2, kWriteB = 4, kWriteA = 8, kWriteRGBA = 15 };

struct PipelineState {
    CullMode cull = CullMode::CCW;         // D3D7 default D3DCULL_CCW
    ShadeMode shade = ShadeMode::Gouraud;
    uint8_t depthTest = 1;                 // D3DRS_ZENABLE
    uint8_t depthWrite = 1;                // D3DRS_ZWRITEENABLE
    CompareFunc depthFunc = CompareFunc::LessEqual;
    uint8_t alphaTest = 0;                 // D3DRS_ALPHATESTENABLE
    CompareFunc alphaFunc = CompareFunc::Always;
    uint8_t alphaRef = 0;
    uint8_t blend = 0;                     // D3DRS_ALPHABLENDENABLE
    BlendFactor srcBlend = BlendFactor::One;
    BlendFactor dstBlend = BlendFactor::Zero;
    BlendOp blendOp = BlendOp::Add;
    uint8_t colorWriteMask = kWriteRGBA;
    uint8_t scissorTest = 0;
    uint8_t specularEnable = 0;            // D3DRS_SPECULARENABLE: add specular after stages
    uint8_t perspectiveColor = 1;          // perspective-correct colours (pinned choice)
    friend bool operator==(const PipelineState&, const PipelineState&) = default;
};
static_assert(std::has_unique_object_representations_v<PipelineState>,
              "PipelineState must have no padding: it is compared and hashed bytewise");

struct Rect {
    int32_t x = 0, y = 0, width = 0, height = 0;
    friend bool operator==(const Rect&, const Rect&) = default;
};

// D3DVIEWPORT7: window rectangle and depth range.
struct Viewport {
    int32_t x = 0, y = 0, width = 0, height = 0;
    float minZ = 0.0f, maxZ = 1.0f;
};

}  // namespace rg::raster
