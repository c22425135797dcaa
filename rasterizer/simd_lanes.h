// Internal to rasterizer/: the lane vectors of the fast path's vertex pass and setup
// (transform_clip.cpp, setup_simd.cpp).
//
// GCC/Clang vector extensions: lane-wise IEEE operations, lowered to one AVX register in
// a function compiled for AVX2 and to two SSE2 registers otherwise, so one body serves
// both instantiations of a runtime-dispatched loop. Every function taking or returning
// one is always inlined, so the ABI of 32-byte vector arguments without AVX (GCC's
// -Wpsabi note) never comes into play; rasterizer/CMakeLists.txt silences the note for the
// files that include this header.
#pragma once

#include <cstdint>
#include <cstring>

namespace rg::raster::detail::lanes {

using F64x4 = double __attribute__((vector_size(32)));
using I64x4 = int64_t __attribute__((vector_size(32)));
using F32x4 = float __attribute__((vector_size(16)));
using I32x4 = int32_t __attribute__((vector_size(16)));
using F32x8 = float __attribute__((vector_size(32)));
using I32x8 = int32_t __attribute__((vector_size(32)));

// 2^52 + 2^51: for an integer |v| < 2^51, v + kMagic lies in [2^52, 2^53), where a double's
// low mantissa bits are the integer itself, so the conversions are one add and one sub.
constexpr double kMagic = 6755399441055744.0;

#define RG_LANES [[gnu::always_inline]] inline

RG_LANES F64x4 splat(double v) { return F64x4{v, v, v, v}; }
RG_LANES F32x8 splat8(float v) { return F32x8{v, v, v, v, v, v, v, v}; }
// Exact for |v| < 2^51.
RG_LANES F64x4 toDouble(I64x4 v) { return (F64x4)(v + (I64x4)splat(kMagic)) - kMagic; }
// v integral, |v| < 2^51.
RG_LANES I64x4 toInt64(F64x4 v) { return (I64x4)(v + kMagic) - (I64x4)splat(kMagic); }
RG_LANES F64x4 floorLanes(F64x4 v) {  // |v| < 2^51
    const F64x4 r = (v + kMagic) - kMagic;  // round to nearest
    return r > v ? r - 1.0 : r;
}
RG_LANES F64x4 minLanes(F64x4 a, F64x4 b) { return a < b ? a : b; }
RG_LANES F64x4 maxLanes(F64x4 a, F64x4 b) { return a > b ? a : b; }
// All ones in the lanes holding a finite value: v − v is +0 for those, NaN for ±∞ and NaN.
RG_LANES I32x8 finiteLanes(F32x8 v) { return (I32x8)((v - v) == 0.0f); }
RG_LANES F32x4 lowHalf(F32x8 v) {
    F32x4 r;
    std::memcpy(&r, &v, sizeof r);
    return r;
}
RG_LANES F32x4 highHalf(F32x8 v) {
    F32x4 r;
    std::memcpy(&r, reinterpret_cast<const char*>(&v) + sizeof r, sizeof r);
    return r;
}

}  // namespace rg::raster::detail::lanes
