// The reference filter: a sample as an explicit list of weighted texel taps, then their
// rounded weighted sum (docs/hardware.md, "Filtering").
#include "addressing.h"
#include "texunit/sampler.h"

namespace rg::tex {

using detail::AxisFootprint;
using detail::axisFootprint;

void gatherTaps(const Texture& t, const SamplerState& s, const glm::vec4& coord, int32_t lambda,
                TapList& out) {
    out.count = 0;
    const bool cube = t.desc().target == TextureTarget::CubeMap;
    const int dims = t.dims();
    const int face = cube ? std::clamp(int(coord.z), 0, 5) : 0;
    const LevelChoice ch = chooseLevels(t, s, lambda);

    // Weight bits: kSubTexelBits per linearly filtered dimension, kLodFracBits when two
    // levels are blended. The taps' weights always sum to exactly 2^weightBits.
    const int linearDims = ch.filter == FilterMode::Linear ? dims : 0;
    out.weightBits = linearDims * kSubTexelBits + (ch.blend ? kLodFracBits : 0);

    const int nLevels = ch.blend ? 2 : 1;
    for (int li = 0; li < nLevels; ++li) {
        const int level = li == 0 ? ch.level0 : ch.level1;
        const uint64_t levelWeight =
            !ch.blend ? 1u : (li == 0 ? uint64_t(kLodOne - ch.frac) : uint64_t(ch.frac));
        const auto& size = t.levelSize(level);
        std::array<AxisFootprint, 4> ax{};
        for (int d = 0; d < 4; ++d) {
            if (d < dims) {
                // Cube faces address ClampToEdge whatever the sampler says: no seamless
                // filtering across faces before Direct3D 10 hardware.
                AddressMode m = cube ? AddressMode::ClampToEdge : s.address[size_t(d)];
                ax[size_t(d)] = axisFootprint(coord[d], size[size_t(d)], m, ch.filter);
            } else {
                ax[size_t(d)] = AxisFootprint{{0, 0}, {1, 0}, 1};
            }
        }
        // Taps in order x fastest, then y, z, w.
        for (int iw = 0; iw < ax[3].count; ++iw)
            for (int iz = 0; iz < ax[2].count; ++iz)
                for (int iy = 0; iy < ax[1].count; ++iy)
                    for (int ix = 0; ix < ax[0].count; ++ix) {
                        TexelTap& tap = out.taps[size_t(out.count++)];
                        tap.level = uint8_t(level);
                        tap.face = uint8_t(face);
                        tap.xyzw = {ax[0].index[ix], ax[1].index[iy], ax[2].index[iz],
                                    ax[3].index[iw]};
                        tap.border = (tap.xyzw[0] < 0 || tap.xyzw[1] < 0 || tap.xyzw[2] < 0 ||
                                      tap.xyzw[3] < 0);
                        if (tap.border) tap.xyzw = {0, 0, 0, 0};
                        tap.weight = levelWeight * ax[0].weight[ix] * ax[1].weight[iy] *
                                     ax[2].weight[iz] * ax[3].weight[iw];
                    }
    }
}

glm::vec4 resolveTapsFloat(const Texture& t, const SamplerState& s, const TapList& taps) {
    double acc[4] = {0, 0, 0, 0};
    const double scale = 1.0 / double(uint64_t(1) << taps.weightBits);
    const glm::vec4 border = glm::vec4(s.borderColor.r, s.borderColor.g, s.borderColor.b,
                                       s.borderColor.a) / 255.0f;
    for (int i = 0; i < taps.count; ++i) {
        const TexelTap& tp = taps.taps[size_t(i)];
        glm::vec4 c;
        if (tp.border) {
            c = border;
        } else if (t.isFloat()) {
            c = t.texelFloat(tp.level, tp.face, tp.xyzw[0], tp.xyzw[1], tp.xyzw[2], tp.xyzw[3]);
        } else {
            const Rgba8 v = t.texel8(tp.level, tp.face, tp.xyzw[0], tp.xyzw[1], tp.xyzw[2], tp.xyzw[3]);
            c = glm::vec4(v.r, v.g, v.b, v.a) / 255.0f;
        }
        const double w = double(tp.weight) * scale;
        for (int k = 0; k < 4; ++k) acc[k] += w * double(c[k]);
    }
    return glm::vec4(float(acc[0]), float(acc[1]), float(acc[2]), float(acc[3]));
}

uint16_t resolveTaps16(const Texture& t, const SamplerState& s, const TapList& taps) {
    // The 8-bit rule at 16 bits: Σ weight·v exactly in 64 bits, one rounding half up.
    uint64_t acc = 0;
    for (int i = 0; i < taps.count; ++i) {
        const TexelTap& tp = taps.taps[size_t(i)];
        const uint32_t v = tp.border ? 257u * s.borderColor.r
                                     : t.texel16(tp.level, tp.face, tp.xyzw[0], tp.xyzw[1],
                                                 tp.xyzw[2], tp.xyzw[3]);
        acc += tp.weight * v;
    }
    const int b = taps.weightBits;
    const uint64_t half = b > 0 ? uint64_t(1) << (b - 1) : 0;
    return uint16_t((acc + half) >> b);
}

Rgba8 resolveTaps(const Texture& t, const SamplerState& s, const TapList& taps) {
    // Float formats: the same weights, accumulated in double in tap order, converted once.
    if (t.isFloat()) return floatToRgba8(resolveTapsFloat(t, s, taps));
    // 8-bit formats: Σ weight·texel exactly in 64 bits, one rounding (half up) at the end.
    uint64_t acc[4] = {0, 0, 0, 0};
    for (int i = 0; i < taps.count; ++i) {
        const TexelTap& tp = taps.taps[size_t(i)];
        const Rgba8 c = tp.border ? s.borderColor
                                  : t.texel8(tp.level, tp.face, tp.xyzw[0], tp.xyzw[1],
                                             tp.xyzw[2], tp.xyzw[3]);
        acc[0] += tp.weight * c.r;
        acc[1] += tp.weight * c.g;
        acc[2] += tp.weight * c.b;
        acc[3] += tp.weight * c.a;
    }
    const int b = taps.weightBits;
    const uint64_t half = b > 0 ? uint64_t(1) << (b - 1) : 0;
    return {uint8_t((acc[0] + half) >> b), uint8_t((acc[1] + half) >> b),
            uint8_t((acc[2] + half) >> b), uint8_t((acc[3] + half) >> b)};
}

}  // namespace rg::tex
