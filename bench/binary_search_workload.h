// The `binary_search` workload (issue 4, item 6): a per-pixel 8-step binary search along
// a ray through a depth texture — the inner loop of relief mapping and of the image-space
// refraction papers' intersection step — run as a geforce8800 fragment program on our
// side and as a GLSL shader on Mesa llvmpipe on the other, fragments/s compared in one
// run.
//
// This header is the one definition both sides implement, plus its plain scalar reference
// (no GL, no retroglass types, so any module or test can include it).
//
// Depth image D    512×512, one 32-bit float channel:
//                      D[j][i] = float(0.5 + 0.25·sin(0.05·i)·cos(0.07·j))
//                  computed in double, then rounded to float; i is the column, j the row,
//                  row 0 the first row uploaded (GL: t ∈ [0, 1/512)). Values in
//                  [0.25, 0.75], so every ray (z from 0 to 1) crosses the surface.
// Target           512×512 RGBA8, one full-screen quad drawn as two triangles, no clear
//                  (the quad covers every pixel). The varying uv is the window pixel
//                  centre over 512: u = (x + ½)/512, v = (y + ½)/512, y counting rows in
//                  the order of D's rows; images here list rows in that order.
// Per fragment     A = (u, v, 0), B = (u + 1/8, v + 1/16, 1); lo = 0, hi = 1; 8 times:
//                      mid = ½(lo + hi);  p = A + (B − A)·mid;
//                      d = D at p.xy, NEAREST, REPEAT, level 0 (texel
//                          floor(p·512) mod 512; GLSL textureLod(tex, p.xy, 0.0).r);
//                      if p.z > d then hi = mid else lo = mid
//                  colour = (½(lo + hi), d of the last step, 0, 1), stored as
//                  round(clamp(c, 0, 1)·255) per channel.
// Items            512·512 fragments per frame.
//
// Why the arithmetic is exact (so both sides must agree bit for bit on the search): u, v
// have at most 10 significant bits, B − A is (1/8, 1/16, 1) and mid = k/2ⁿ (n ≤ 8), so p
// and p·512 are exact in binary32 whatever the evaluation order or FMA contraction. Step
// 7 lands on an exact texel boundary in x and step 6 in y (64·mid and 32·mid are odd
// halves there): an implementation whose u, v or p is one ulp low picks the texel before
// it in x or y, and the search goes elsewhere — shifting uv by 1e-7 relative in the GLSL
// shader changes 109,253 of the 262,144 pixels (by up to 86), and rows in the opposite
// order differ at 244,036. Compute uv as exactly (x + ½)/512. Only the final float →
// 8-bit conversion is left to the implementation: round() takes halves away from zero,
// llvmpipe to even, which differs at the one pixel whose d·255 is a binary32 tie
// ((389, 420): d·255 = 156.5, llvmpipe 156, reference 157).
//
// Benchmarks (bench/harness.h naming): `binary_search/<impl>/threads:N` for each N of
// `--threads` (default 1 and all cores), both sides with UseManualTime() (wall-clock
// seconds per frame, which also gives both the `/manual_time` suffix the harness pairs on) and
// SetItemsProcessed(iterations · kFragmentsPerFrame). The llvmpipe side is
// bench/bench_binary_search_mesa.cpp; its GL code and a one-frame readback are in
// bench/binary_search_mesa.h. tests/peer/ checks llvmpipe's image against
// referenceImage().
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rg::bench::binary_search {

constexpr int kDepthSize = 512;             // D is kDepthSize × kDepthSize texels
constexpr int kWidth = 512, kHeight = 512;  // the target
constexpr int kSteps = 8;                   // bisection steps per fragment
constexpr float kRayDx = 0.125f;            // B − A in x
constexpr float kRayDy = 0.0625f;           // B − A in y (and 1 in z)
constexpr int64_t kFragmentsPerFrame = int64_t(kWidth) * kHeight;

// D, row-major: D[j][i] at depth[j·kDepthSize + i].
inline std::vector<float> depthImage() {
    std::vector<float> depth(size_t(kDepthSize) * kDepthSize);
    for (int j = 0; j < kDepthSize; ++j)
        for (int i = 0; i < kDepthSize; ++i)
            // Double, then one rounding to float: the float is the same on any libm
            // within an ulp of sin and cos (a double ulp moves 0.5 + 0.25·s·c by 2⁻⁵⁴).
            depth[size_t(j) * kDepthSize + size_t(i)] =
                float(0.5 + 0.25 * std::sin(0.05 * i) * std::cos(0.07 * j));
    return depth;
}

// NEAREST, REPEAT, level 0: texel floor(c·size) mod size, in binary32 as GL specifies.
inline int nearestRepeat(float c, int size) {
    const int k = int(std::floor(c * float(size)));
    return ((k % size) + size) % size;
}

// The result of one fragment's search before conversion: ½(lo + hi) and the last d.
struct Hit {
    float t = 0.0f;
    float d = 0.0f;
};

// The per-fragment algorithm, step by step as in the header comment. `depth` is a
// kDepthSize² image laid out as depthImage() returns it.
inline Hit shadeFragment(const float* depth, float u, float v) {
    const float a[3] = {u, v, 0.0f};
    const float b[3] = {u + kRayDx, v + kRayDy, 1.0f};
    float lo = 0.0f, hi = 1.0f, d = 0.0f;
    for (int step = 0; step < kSteps; ++step) {
        const float mid = 0.5f * (lo + hi);
        float p[3];
        for (int c = 0; c < 3; ++c) p[c] = a[c] + (b[c] - a[c]) * mid;
        const int i = nearestRepeat(p[0], kDepthSize),
                  j = nearestRepeat(p[1], kDepthSize);
        d = depth[size_t(j) * kDepthSize + size_t(i)];
        if (p[2] > d)
            hi = mid;
        else
            lo = mid;
    }
    return {0.5f * (lo + hi), d};
}

// round(clamp(c, 0, 1)·255), halves away from zero.
inline uint8_t toUnorm8(float c) {
    return uint8_t(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f));
}

inline std::array<uint8_t, 4> toRgba8(const Hit& h) {
    return {toUnorm8(h.t), toUnorm8(h.d), 0, 255};
}

// Window pixel centre over the target size: the varying uv of pixel (x, y).
inline float pixelCentre(int x, int size) { return (float(x) + 0.5f) / float(size); }

// The whole frame, RGBA8, kWidth·kHeight·4 bytes, row y at offset y·kWidth·4 with y in
// the row order of D (see the header comment).
inline std::vector<uint8_t> referenceImage(const std::vector<float>& depth) {
    std::vector<uint8_t> rgba(size_t(kWidth) * kHeight * 4);
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const auto px = toRgba8(shadeFragment(depth.data(), pixelCentre(x, kWidth),
                                                  pixelCentre(y, kHeight)));
            std::copy(px.begin(), px.end(),
                      rgba.begin() + (ptrdiff_t(y) * kWidth + x) * 4);
        }
    return rgba;
}

inline std::vector<uint8_t> referenceImage() { return referenceImage(depthImage()); }

}  // namespace rg::bench::binary_search
