// The fast filter for 1D, 2D and cube 8-bit textures: the reference's weighted sum
// computed straight from the footprints, without materialising the tap list. Shares the
// addressing and level choice with the reference (addressing.h, lod.cpp), so only the
// accumulation is duplicated; tests/texunit compare the two under random states.
//
// With at most 2 linear dimensions and 2 levels the weights total 2^24, so Σ w·texel ≤
// 255·2^24 fits in uint32: the sums run in 32 bits here (64 in the reference), same value.
#include "addressing.h"
#include "texunit/sampler.h"

namespace rg::tex {

namespace {

bool fastEligible(const Texture& t) {
    const TextureTarget target = t.desc().target;
    return !t.isFloat() && (target == TextureTarget::Texture2D || target == TextureTarget::CubeMap ||
                            target == TextureTarget::Texture1D);
}

template <bool kLinear, bool kTwoD>
inline void accumulateLevel(const Texture& t, int level, int face, const glm::vec4& c,
                            AddressMode ms, AddressMode mt, uint32_t lw, Rgba8 border,
                            uint32_t acc[4]) {
    constexpr FilterMode f = kLinear ? FilterMode::Linear : FilterMode::Nearest;
    const auto& size = t.levelSize(level);
    const Rgba8* base = t.data8(level, face);
    const auto fx = detail::axisFootprint(c.x, size[0], ms, f);
    const auto fy = kTwoD ? detail::axisFootprint(c.y, size[1], mt, f)
                          : detail::AxisFootprint{{0, 0}, {1, 0}, 1};
    constexpr int nx = kLinear ? 2 : 1;
    constexpr int ny = (kLinear && kTwoD) ? 2 : 1;
    for (int iy = 0; iy < ny; ++iy) {
        const uint32_t wy = lw * fy.weight[iy];
        const Rgba8* row = fy.index[iy] < 0 ? nullptr : base + size_t(fy.index[iy]) * size_t(size[0]);
        for (int ix = 0; ix < nx; ++ix) {
            const uint32_t w = wy * fx.weight[ix];
            const Rgba8 v = (row && fx.index[ix] >= 0) ? row[fx.index[ix]] : border;
            acc[0] += w * v.r;
            acc[1] += w * v.g;
            acc[2] += w * v.b;
            acc[3] += w * v.a;
        }
    }
}

template <bool kLinear, bool kTwoD>
inline Rgba8 sampleChoice(const Texture& t, const SamplerState& s, const LevelChoice& ch,
                          const glm::vec4& c) {
    const bool cube = t.desc().target == TextureTarget::CubeMap;
    const int face = cube ? std::clamp(int(c.z), 0, 5) : 0;
    const AddressMode ms = cube ? AddressMode::ClampToEdge : s.address[0];
    const AddressMode mt = cube ? AddressMode::ClampToEdge : s.address[1];
    constexpr int linearBits = kLinear ? (kTwoD ? 2 : 1) * kSubTexelBits : 0;
    uint32_t acc[4] = {0, 0, 0, 0};
    int bits = linearBits;
    if (ch.blend) {
        bits += kLodFracBits;
        accumulateLevel<kLinear, kTwoD>(t, ch.level0, face, c, ms, mt, uint32_t(kLodOne - ch.frac),
                                        s.borderColor, acc);
        accumulateLevel<kLinear, kTwoD>(t, ch.level1, face, c, ms, mt, uint32_t(ch.frac),
                                        s.borderColor, acc);
    } else {
        accumulateLevel<kLinear, kTwoD>(t, ch.level0, face, c, ms, mt, 1u, s.borderColor, acc);
    }
    const uint32_t half = bits > 0 ? 1u << (bits - 1) : 0u;
    return {uint8_t((acc[0] + half) >> bits), uint8_t((acc[1] + half) >> bits),
            uint8_t((acc[2] + half) >> bits), uint8_t((acc[3] + half) >> bits)};
}

Rgba8 sampleChoiceAny(const Texture& t, const SamplerState& s, const LevelChoice& ch,
                      const glm::vec4& c) {
    const bool twoD = t.dims() == 2;
    if (ch.filter == FilterMode::Linear)
        return twoD ? sampleChoice<true, true>(t, s, ch, c) : sampleChoice<true, false>(t, s, ch, c);
    return twoD ? sampleChoice<false, true>(t, s, ch, c) : sampleChoice<false, false>(t, s, ch, c);
}

}  // namespace

Rgba8 sampleFast(const Texture& t, const SamplerState& s, const glm::vec4& coord, int32_t lambda) {
    if (!fastEligible(t)) {
        TapList taps;
        gatherTaps(t, s, coord, lambda, taps);
        return resolveTaps(t, s, taps);
    }
    return sampleChoiceAny(t, s, chooseLevels(t, s, lambda), coord);
}

uint64_t sampleQuadFast(const Texture& t, const SamplerState& s,
                        const std::array<glm::vec4, 4>& coords, int32_t lambda,
                        std::array<Rgba8, 4>& out) {
    const LevelChoice ch = chooseLevels(t, s, lambda);
    if (!fastEligible(t)) {
        uint64_t n = 0;
        for (int p = 0; p < 4; ++p) {
            TapList taps;
            gatherTaps(t, s, coords[size_t(p)], lambda, taps);
            out[size_t(p)] = resolveTaps(t, s, taps);
            n += uint64_t(taps.count);
        }
        return n;
    }
    const bool twoD = t.dims() == 2;
    if (ch.filter == FilterMode::Linear) {
        for (int p = 0; p < 4; ++p)
            out[size_t(p)] = twoD ? sampleChoice<true, true>(t, s, ch, coords[size_t(p)])
                                  : sampleChoice<true, false>(t, s, ch, coords[size_t(p)]);
    } else {
        for (int p = 0; p < 4; ++p)
            out[size_t(p)] = twoD ? sampleChoice<false, true>(t, s, ch, coords[size_t(p)])
                                  : sampleChoice<false, false>(t, s, ch, coords[size_t(p)]);
    }
    const uint64_t per = uint64_t(ch.filter == FilterMode::Linear ? (twoD ? 4 : 2) : 1) * (ch.blend ? 2 : 1);
    return per * 4;
}

}  // namespace rg::tex
