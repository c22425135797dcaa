// Internal: texel addressing shared by the reference tap list and the fast path, so the
// two cannot drift (docs/hardware.md, "Filtering").
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "texunit/sampler.h"

namespace rg::tex::detail {

// ⌊v⌋ for |v| < 2^31 without a libm call (SSE2 has no floor instruction): truncate, then
// step down for negative non-integers; float(i) is exact wherever v has a fraction.
inline int32_t floorToInt(float v) {
    int32_t i = int32_t(v);
    if (float(i) > v) --i;
    return i;
}

// ⌊c·n·2^kSubTexelBits⌋ with c·n rounded once to float and clamped to ±2^22 texels so
// that the fixed-point value fits comfortably in 64 bits; NaN counts as 0.
inline int64_t toSubTexel(float c, int n) {
    float u = c * float(n);
    if (!(u == u)) u = 0.0f;
    u = std::clamp(u, -4194304.0f, 4194304.0f);
    return floorToInt(u * float(1 << kSubTexelBits));  // |u·256| ≤ 2^30
}

// An integer texel coordinate under an address mode: the index inside [0, n) or -1 for
// the border colour.
inline int32_t addressTexel(int64_t i, int n, AddressMode m) {
    switch (m) {
        case AddressMode::Wrap: {
            // Power-of-two extents (every texture on the fixed-function profiles): the
            // two's-complement mask is the non-negative remainder, without a division.
            if ((n & (n - 1)) == 0) return int32_t(i & (n - 1));
            int64_t r = i % n;
            return int32_t(r < 0 ? r + n : r);
        }
        case AddressMode::Mirror: {
            int64_t p = 2 * int64_t(n), r;
            if ((n & (n - 1)) == 0) {
                r = i & (p - 1);
            } else {
                r = i % p;
                if (r < 0) r += p;
            }
            return int32_t(r < n ? r : p - 1 - r);
        }
        case AddressMode::ClampToEdge: return int32_t(std::clamp<int64_t>(i, 0, n - 1));
        case AddressMode::Clamp:
        case AddressMode::Border: return (i < 0 || i >= n) ? -1 : int32_t(i);
    }
    return 0;
}

// A float LOD parameter (bias, MIN_LOD, MAX_LOD) in kLodFracBits fixed point: clamped to
// ±4096, rounded half up; NaN counts as 0 (biasAndClampLambda and the compiled samplers).
inline int32_t lodFixedFromFloat(float v) {
    if (!(v == v)) return 0;
    v = std::clamp(v, -4096.0f, 4096.0f);
    return floorToInt(v * float(kLodOne) + 0.5f);
}

// λ for ρ = 0 (all four pixels on one texel coordinate): deep magnification, far from
// any int32 overflow after bias.
constexpr int32_t kLambdaZero = -(1 << 20);

// log2Fixed (sampler.h) inline, for the per-quad paths.
inline int32_t log2FixedInline(float x) {
    if (!(x > 0.0f)) return kLambdaZero;
    if (std::isinf(x) || std::isnan(x)) return 255 << kLodFracBits;
    // The float's bits read as a fixed-point number are (e + 127)·2^23 + (m − 1)·2^23:
    // minus the bias this is e + (m − 1), the piecewise-linear log2 hardware used (exact
    // at powers of two, at most 0.0861 low in between). Keep kLodFracBits of fraction.
    uint32_t bits;
    std::memcpy(&bits, &x, 4);
    int32_t l = int32_t(bits) - (127 << 23);
    return l >> (23 - kLodFracBits);  // arithmetic shift: floor
}

// quadLambda (sampler.h) inline for 1 or 2 dimensions: (s, t) of pixels 0, 1 (x
// neighbour) and 2 (y neighbour), n0/n1 the level-base extents as floats. Scalars rather
// than an array, so the per-quad callers keep them in registers.
inline int32_t quadLambdaInline(float s0, float s1, float s2, float t0, float t1, float t2,
                                float n0, float n1, int dims) {
    float dx2 = 0.0f, dy2 = 0.0f;
    {
        const float dx = (s1 - s0) * n0;
        const float dy = (s2 - s0) * n0;
        dx2 = dx2 + dx * dx;
        dy2 = dy2 + dy * dy;
    }
    if (dims > 1) {
        const float dx = (t1 - t0) * n1;
        const float dy = (t2 - t0) * n1;
        dx2 = dx2 + dx * dx;
        dy2 = dy2 + dy * dy;
    }
    const float rho2 = std::max(dx2, dy2);
    const int32_t l = log2FixedInline(rho2);
    // λ = log2 ρ = ½ log2 ρ²; the arithmetic shift floors.
    return l <= kLambdaZero ? kLambdaZero : (l >> 1);
}

// What chooseLevels needs of the texture and sampler, derived once per state.
struct LevelParams {
    int base, q;  // level base and the last level the chain may reach
    int32_t c;    // magnification threshold
    FilterMode mag, min;
    MipMode mip;
};
inline LevelParams levelParams(int levels, const SamplerState& s) {
    const int last = levels - 1;
    const int base = std::clamp(s.baseLevel, 0, last);
    const int q = std::max(base, std::min(last, s.maxLevel));
    // GL 1.2 §3.8.8: c = 0.5 when magnifying LINEAR against a NEAREST_MIPMAP_* min filter,
    // so that the switch-over is continuous; 0 otherwise.
    const int32_t c = (s.magFilter == FilterMode::Linear && s.minFilter == FilterMode::Nearest &&
                       s.mipFilter != MipMode::None)
                          ? kLodOne / 2
                          : 0;
    return {base, q, c, s.magFilter, s.minFilter, s.mipFilter};
}
// chooseLevels (sampler.h) inline: GL 1.2 §3.8.8.
// Always inlined: the per-quad kernels keep the choice in registers (called out of line,
// GCC returned it through memory and the kernel's wider reload of it missed store
// forwarding: 9% of tex_cube_trilinear's sampler).
[[gnu::always_inline]] inline LevelChoice chooseLevelsInline(const LevelParams& p, int32_t lambda) {
    const int base = p.base, q = p.q;
    if (lambda <= p.c) return {p.mag, base, base, 0, false};
    switch (p.mip) {
        case MipMode::None: return {p.min, base, base, 0, false};
        case MipMode::Nearest: {
            // d = ceil(λ + ½) − 1: half-integer λ rounds down.
            int64_t d = int64_t(base) + ((int64_t(lambda) + (kLodOne / 2 - 1)) >> kLodFracBits);
            int lvl = int(std::min<int64_t>(d, q));
            return {p.min, lvl, lvl, 0, false};
        }
        case MipMode::Linear: {
            if (int64_t(lambda) >= int64_t(q - base) * kLodOne) return {p.min, q, q, 0, false};
            int d1 = base + (lambda >> kLodFracBits);
            return {p.min, d1, d1 + 1, lambda & (kLodOne - 1), true};
        }
    }
    return {p.mag, base, base, 0, false};
}

// One axis of a filter footprint: 1 tap (nearest, weight 1) or 2 taps (linear, weights
// out of 2^kSubTexelBits).
struct AxisFootprint {
    int32_t index[2];   // -1: border
    uint32_t weight[2];
    int count;
};

inline AxisFootprint axisFootprint(float c, int n, AddressMode m, FilterMode f) {
    AxisFootprint a{};
    // OpenGL 1.2 CLAMP clamps the coordinate to [0, 1] before the texel is computed.
    if (m == AddressMode::Clamp) c = std::clamp(c, 0.0f, 1.0f);
    if (!(c == c)) c = 0.0f;
    if (f == FilterMode::Nearest) {
        // i = ⌊u⌋; under CLAMP the only outside value is u = n (c = 1), which GL 1.2 maps
        // to n − 1.
        int64_t i = toSubTexel(c, n) >> kSubTexelBits;
        if (m == AddressMode::Clamp) i = std::min<int64_t>(i, n - 1);
        a.index[0] = addressTexel(i, n, m);
        a.weight[0] = 1;
        a.count = 1;
    } else {
        // i0 = ⌊u − ½⌋, i1 = i0 + 1, α = frac(u − ½) in kSubTexelBits bits.
        int64_t u = toSubTexel(c, n) - (1 << (kSubTexelBits - 1));
        int64_t i0 = u >> kSubTexelBits;
        uint32_t frac = uint32_t(u & ((1 << kSubTexelBits) - 1));
        a.index[0] = addressTexel(i0, n, m);
        a.index[1] = addressTexel(i0 + 1, n, m);
        a.weight[0] = (1u << kSubTexelBits) - frac;
        a.weight[1] = frac;
        a.count = 2;
    }
    return a;
}

}  // namespace rg::tex::detail
