// Level of detail for a 2×2 quad (docs/hardware.md, "Level of detail"; OpenGL 1.2
// §3.8.5–3.8.8).
#include <algorithm>
#include <cmath>
#include <cstring>

#include "addressing.h"
#include "texunit/sampler.h"

namespace rg::tex {

namespace {
using detail::kLambdaZero;

int32_t fixedFromFloat(float v) { return detail::lodFixedFromFloat(v); }
}  // namespace

int32_t log2Fixed(float x) { return detail::log2FixedInline(x); }

int32_t quadLambda(const std::array<glm::vec4, 4>& c, const std::array<int, 4>& size, int dims) {
    // Differences along x (pixel 1 − pixel 0) and y (pixel 2 − pixel 0) in texels of the
    // base level: one λ per quad, as the period hardware computed it.
    float dx2 = 0.0f, dy2 = 0.0f;
    for (int d = 0; d < dims; ++d) {
        const float n = float(size[size_t(d)]);
        const float dx = (c[1][d] - c[0][d]) * n;
        const float dy = (c[2][d] - c[0][d]) * n;
        dx2 = dx2 + dx * dx;
        dy2 = dy2 + dy * dy;
    }
    const float rho2 = std::max(dx2, dy2);
    const int32_t l = log2Fixed(rho2);
    // λ = log2 ρ = ½ log2 ρ²; the arithmetic shift floors.
    return l <= kLambdaZero ? kLambdaZero : (l >> 1);
}

int32_t biasAndClampLambda(int32_t lambda, const SamplerState& s) {
    int32_t l = lambda + fixedFromFloat(s.lodBias);
    return std::clamp(l, fixedFromFloat(s.minLod), std::max(fixedFromFloat(s.minLod), fixedFromFloat(s.maxLod)));
}

LevelChoice chooseLevels(const Texture& t, const SamplerState& s, int32_t lambda) {
    return detail::chooseLevelsInline(detail::levelParams(t.levels(), s), lambda);
}

}  // namespace rg::tex
