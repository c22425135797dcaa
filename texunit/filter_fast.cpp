// The fast filter for 1D, 2D and cube 8-bit textures: the reference's weighted sum
// computed straight from the footprints, without materialising the tap list. Shares the
// addressing and level choice with the reference (addressing.h, lod.cpp), so only the
// accumulation is duplicated; tests/texunit compare the two under random states.
#include "addressing.h"
#include "texunit/sampler.h"

namespace rg::tex {

Rgba8 sampleFast(const Texture& t, const SamplerState& s, const glm::vec4& coord, int32_t lambda) {
    const TextureTarget target = t.desc().target;
    if (t.isFloat() || !(target == TextureTarget::Texture2D || target == TextureTarget::CubeMap ||
                         target == TextureTarget::Texture1D)) {
        TapList taps;
        gatherTaps(t, s, coord, lambda, taps);
        return resolveTaps(t, s, taps);
    }
    const bool cube = target == TextureTarget::CubeMap;
    const int face = cube ? std::clamp(int(coord.z), 0, 5) : 0;
    const LevelChoice ch = chooseLevels(t, s, lambda);
    const bool twoD = t.dims() == 2;
    const AddressMode ms = cube ? AddressMode::ClampToEdge : s.address[0];
    const AddressMode mt = cube ? AddressMode::ClampToEdge : s.address[1];
    const int bits = (ch.filter == FilterMode::Linear ? t.dims() * kSubTexelBits : 0) +
                     (ch.blend ? kLodFracBits : 0);

    uint64_t r = 0, g = 0, b = 0, a = 0;
    const int nLevels = ch.blend ? 2 : 1;
    for (int li = 0; li < nLevels; ++li) {
        const int level = li == 0 ? ch.level0 : ch.level1;
        const uint64_t lw = !ch.blend ? 1u : (li == 0 ? uint64_t(kLodOne - ch.frac) : uint64_t(ch.frac));
        const auto& size = t.levelSize(level);
        const Rgba8* base = t.data8(level, face);
        const auto fx = detail::axisFootprint(coord.x, size[0], ms, ch.filter);
        const auto fy = twoD ? detail::axisFootprint(coord.y, size[1], mt, ch.filter)
                             : detail::AxisFootprint{{0, 0}, {1, 0}, 1};
        for (int iy = 0; iy < fy.count; ++iy) {
            const uint64_t wy = lw * fy.weight[iy];
            for (int ix = 0; ix < fx.count; ++ix) {
                const uint64_t w = wy * fx.weight[ix];
                const bool border = fx.index[ix] < 0 || fy.index[iy] < 0;
                const Rgba8 c = border ? s.borderColor
                                       : base[size_t(fy.index[iy]) * size_t(size[0]) + size_t(fx.index[ix])];
                r += w * c.r;
                g += w * c.g;
                b += w * c.b;
                a += w * c.a;
            }
        }
    }
    const uint64_t half = bits > 0 ? uint64_t(1) << (bits - 1) : 0;
    return {uint8_t((r + half) >> bits), uint8_t((g + half) >> bits), uint8_t((b + half) >> bits),
            uint8_t((a + half) >> bits)};
}

}  // namespace rg::tex
