// Texture fetches of fragment programs (geforce8800): λ, then the filtered texel
// (docs/hardware.md, "Programmable profile: texture fetches").
#include "texunit/program_fetch.h"

#include <algorithm>

#include "addressing.h"
#include "core/error.h"
#include "cube_select.h"

namespace rg::tex {

namespace {

bool isCube(const Texture& t) { return t.desc().target == TextureTarget::CubeMap; }

// The sampler's coordinate for gatherTaps: (s, t, r, q) for 1D/2D/3D, (s, t, face, 0) on
// the selected face for cube maps.
glm::vec4 mapCoord(const Texture& t, const glm::vec4& c) {
    if (!isCube(t)) return c;
    const CubeCoord cc = detail::selectCubeFace(glm::vec3(c));
    return glm::vec4(cc.s, cc.t, float(int(cc.face)), 0.0f);
}

int baseLevel(const Texture& t, const SamplerState& s) {
    return std::clamp(s.baseLevel, 0, t.levels() - 1);
}

[[gnu::always_inline]] inline glm::vec4 texelAsFloat(const Texture& t, int level, int face, int x, int y, int z) {
    if (t.isFloat()) return t.texelFloat(level, face, x, y, z, 0);
    const Rgba8 v = t.texel8(level, face, x, y, z, 0);
    return glm::vec4(v.r, v.g, v.b, v.a) / 255.0f;
}

glm::vec4 borderAsFloat(const SamplerState& s) {
    return glm::vec4(s.borderColor.r, s.borderColor.g, s.borderColor.b, s.borderColor.a) / 255.0f;
}

// The fast path's taps of one level of a 1D, 2D or cube texture, added into `acc`: the taps
// of gatherTaps in its order (x fastest, then y), each of weight levelWeight·wx·wy (the same
// integer gatherTaps forms) times `scale` = 2^−weightBits, applied in double as
// resolveTapsFloat does, without building the list. Called for level0 and then level1 of a
// blend, it adds the list's taps in the list's order: the same sums, bit for bit.
[[gnu::always_inline]] inline void accumulateLevel(const Texture& t, const SamplerState& s,
                                                   const glm::vec4& c, int level,
                                                   FilterMode filter, uint64_t levelWeight,
                                                   double scale, double (&acc)[4],
                                                   uint32_t& fetches) {
    const bool cube = isCube(t);
    const int dims = t.dims();
    const int face = cube ? std::clamp(int(c.z), 0, 5) : 0;
    const auto& size = t.levelSize(level);
    const AddressMode ms = cube ? AddressMode::ClampToEdge : s.address[0];
    const AddressMode mt = cube ? AddressMode::ClampToEdge : s.address[1];
    const detail::AxisFootprint ax = detail::axisFootprint(c.x, size[0], ms, filter);
    const detail::AxisFootprint ay = dims > 1 ? detail::axisFootprint(c.y, size[1], mt, filter)
                                              : detail::AxisFootprint{{0, 0}, {1, 0}, 1};
    const glm::vec4 border = borderAsFloat(s);
    double a[4] = {acc[0], acc[1], acc[2], acc[3]};  // in registers through the loop
    for (int iy = 0; iy < ay.count; ++iy)
        for (int ix = 0; ix < ax.count; ++ix) {
            const int x = ax.index[ix], y = ay.index[iy];
            const glm::vec4 v = (x < 0 || y < 0) ? border : texelAsFloat(t, level, face, x, y, 0);
            const double w = double(levelWeight * ax.weight[ix] * ay.weight[iy]) * scale;
            for (int k = 0; k < 4; ++k) a[k] += w * double(v[k]);
        }
    for (int k = 0; k < 4; ++k) acc[k] = a[k];
    fetches += uint32_t(ax.count * ay.count);
}

}  // namespace

int32_t programLambdaQuad(const Texture& t, const SamplerState& s,
                          const std::array<glm::vec4, 4>& quad) {
    const auto& size = t.levelSize(baseLevel(t, s));
    int32_t lambda;
    if (isCube(t)) {
        std::array<glm::vec4, 4> onFace{};
        const CubeFace f0 = detail::selectCubeFace(glm::vec3(quad[0])).face;
        for (int p = 0; p < 3; ++p) {
            const CubeCoord cc = detail::projectOntoCubeFace(f0, glm::vec3(quad[size_t(p)]));
            onFace[size_t(p)] = glm::vec4(cc.s, cc.t, 0.0f, 0.0f);
        }
        lambda = quadLambda(onFace, size, 2);
    } else {
        lambda = quadLambda(quad, size, t.dims());
    }
    return biasAndClampLambda(lambda, s);
}

int32_t programLambdaGrad(const Texture& t, const SamplerState& s, const glm::vec4& c,
                          const glm::vec4& ddx, const glm::vec4& ddy) {
    return programLambdaQuad(t, s, {c, c + ddx, c + ddy, c + ddx + ddy});
}

int32_t programLambdaLod(const SamplerState& s, float lod) {
    return biasAndClampLambda(detail::lodFixedFromFloat(lod), s);
}

glm::vec4 programFetch(const Texture& t, const SamplerState& s, const glm::vec4& c,
                       int32_t lambda, Path path, uint32_t& fetches) {
    const glm::vec4 mc = mapCoord(t, c);
    if (path == Path::Fast && t.dims() <= 2) {
        // gatherTaps' weight bits: kSubTexelBits per linearly filtered dimension, kLodFracBits
        // when two levels are blended (trilinear: the board's mipmapped albedo in impostors).
        const LevelChoice ch = detail::chooseLevelsInline(detail::levelParams(t.levels(), s), lambda);
        const int bits = (ch.filter == FilterMode::Linear ? t.dims() : 0) * kSubTexelBits +
                         (ch.blend ? kLodFracBits : 0);
        const double scale = 1.0 / double(uint64_t(1) << bits);
        double acc[4] = {0, 0, 0, 0};
        accumulateLevel(t, s, mc, ch.level0, ch.filter, ch.blend ? uint64_t(kLodOne - ch.frac) : 1u,
                        scale, acc, fetches);
        if (ch.blend)
            accumulateLevel(t, s, mc, ch.level1, ch.filter, uint64_t(ch.frac), scale, acc, fetches);
        return glm::vec4(float(acc[0]), float(acc[1]), float(acc[2]), float(acc[3]));
    }
    TapList taps;
    gatherTaps(t, s, mc, lambda, taps);
    fetches += uint32_t(taps.count);
    return resolveTapsFloat(t, s, taps);
}

float programFetchCompare(const Texture& t, const SamplerState& s, const glm::vec4& c,
                          float ref, int32_t lambda, Path path, uint32_t& fetches) {
    if (!t.format().isDepth)
        throw InvalidState("depth-compare fetch from a " + std::string(t.format().name) +
                           " texture; compare fetches need a depth texture");
    (void)path;  // one path: the compare is per tap, the list is the definition
    TapList taps;
    gatherTaps(t, s, mapCoord(t, c), lambda, taps);
    fetches += uint32_t(taps.count);
    // Σ weight·(ref ≤ depth) over the taps, in integers: exact whatever the order.
    uint64_t pass = 0;
    for (int i = 0; i < taps.count; ++i) {
        const TexelTap& tp = taps.taps[size_t(i)];
        const float d = tp.border ? float(s.borderColor.r) / 255.0f
                                  : t.texelFloat(tp.level, tp.face, tp.xyzw[0], tp.xyzw[1],
                                                 tp.xyzw[2], tp.xyzw[3]).x;
        if (ref <= d) pass += tp.weight;
    }
    return float(double(pass) / double(uint64_t(1) << taps.weightBits));
}

}  // namespace rg::tex
