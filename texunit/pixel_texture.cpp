// SGIX_pixel_texture (docs/hardware.md, "Pixel texture").
//
// Two paths, the same bytes and fetch counts (TextureUnits.PixelTransferFastMatchesReference):
//   - the reference: per pixel the coordinate, the tap list (gatherTaps) and its rounded
//     sum (resolveTaps), the colour table: the document's words one by one;
//   - the fast path: for states where every coordinate comes straight from a byte (RGB mode
//     with q = 1, or a 4D texture, whose q is a coordinate), each axis' footprint is a
//     function of that byte alone, so it is looked up in a 256-entry table built once per
//     state (PixelTransferLut, the same axisFootprint the tap list calls) and the taps are
//     summed in place, without the list. Other states (RGBA mode on 1D/2D/3D textures, which
//     divide by q; float formats; I16 through a colour table) take the reference per pixel.
#include <cstdint>

#include "texunit/texture_units.h"

#include "addressing.h"
#include "fetch_counter.h"

namespace rg::tex {

namespace detail {

struct PixelTransferLut {
    const Texture* texture = nullptr;
    int dims = 2;
    int level = 0;
    int weightBits = 0;               // 8 per linearly filtered dimension, 0 for NEAREST
    uint32_t tapsPerPixel = 1;        // what the reference's list counts
    std::array<int32_t, 4> size{1, 1, 1, 1};
    std::array<std::array<AxisFootprint, 256>, 4> axis{};
};

}  // namespace detail

namespace {

constexpr int32_t kPixelLambda = -(1 << 20);  // no derivatives: magnification

// The reference: one pixel through the tap list.
Rgba8 pixelReference(const Texture& t, const SamplerState& sampler, const ColorTable* table,
                     PixelTexGenMode mode, Rgba8 px, TapList& taps, uint64_t& fetched) {
    // Colour components become coordinates: c/255 exactly as the pixel path converts
    // 8-bit components to [0, 1].
    glm::vec4 c(px.r / 255.0f, px.g / 255.0f, px.b / 255.0f,
                mode == PixelTexGenMode::Rgba ? px.a / 255.0f : 1.0f);
    if (t.desc().target != TextureTarget::Texture4D) {
        // 1D/2D/3D: the projective divide by q. q ≤ 0 (alpha 0) puts the coordinate at
        // infinity; we pin the result to the border colour rather than divide.
        if (!(c.w > 0.0f)) {
            Rgba8 b = sampler.borderColor;
            if (table) b = t.is16() ? applyColorTable16(*table, uint16_t(257u * b.r)) : applyColorTable(*table, b);
            if (mode == PixelTexGenMode::Rgb) b.a = px.a;
            return b;
        }
        c = glm::vec4(c.x / c.w, c.y / c.w, c.z / c.w, 0.0f);
    }
    gatherTaps(t, sampler, c, kPixelLambda, taps);
    fetched += uint64_t(taps.count);
    Rgba8 v;
    if (table && t.is16())
        v = applyColorTable16(*table, resolveTaps16(t, sampler, taps));
    else {
        v = resolveTaps(t, sampler, taps);
        if (table) v = applyColorTable(*table, v);
    }
    if (mode == PixelTexGenMode::Rgb) v.a = px.a;
    return v;
}

}  // namespace

std::shared_ptr<const detail::PixelTransferLut> TextureUnits::compilePixelTransfer() const {
    if (!pixelTexture_.enabled) return nullptr;
    const Unit& u = units_[pixelTexture_.stage];
    if (!u.texture) return nullptr;
    const Texture& t = *u.texture;
    const TextureTarget target = t.desc().target;
    if (t.isFloat() || target == TextureTarget::CubeMap || (t.is16() && u.colorTable)) return nullptr;
    // Coordinates must come from the bytes alone: q = 1 (RGB mode) or a 4D texture.
    if (pixelTexture_.mode == PixelTexGenMode::Rgba && target != TextureTarget::Texture4D) return nullptr;
    auto lut = std::make_shared<detail::PixelTransferLut>();
    lut->texture = &t;
    lut->dims = t.dims();
    const LevelChoice ch = chooseLevels(t, u.sampler, kPixelLambda);
    if (ch.blend) return nullptr;  // magnification never blends levels; kept for safety
    lut->level = ch.level0;
    lut->size = t.levelSize(ch.level0);
    lut->weightBits = ch.filter == FilterMode::Linear ? lut->dims * kSubTexelBits : 0;
    lut->tapsPerPixel = ch.filter == FilterMode::Linear ? (1u << lut->dims) : 1u;
    for (int d = 0; d < lut->dims; ++d)
        for (int v = 0; v < 256; ++v)
            lut->axis[size_t(d)][size_t(v)] = detail::axisFootprint(
                float(v) / 255.0f, lut->size[size_t(d)], u.sampler.address[size_t(d)], ch.filter);
    return lut;
}

void TextureUnits::applyPixelTransfer(std::span<Rgba8> pixels) const {
    applyPixelTransfer(pixels, Path::Reference);
}

void TextureUnits::applyPixelTransfer(std::span<Rgba8> pixels, Path path) const {
    if (!pixelTexture_.enabled) return;
    const Unit& u = units_[pixelTexture_.stage];
    if (!u.texture) return;
    const Texture& t = *u.texture;
    const ColorTable* table = u.colorTable.get();
    const PixelTexGenMode mode = pixelTexture_.mode;
    uint64_t fetched = 0;
    const detail::PixelTransferLut* lut = path == Path::Fast ? pixelLut_.get() : nullptr;
    if (!lut) {
        TapList taps;
        for (Rgba8& px : pixels) px = pixelReference(t, u.sampler, table, mode, px, taps, fetched);
        fetches_->add(fetched);
        return;
    }
    // The fast path: footprints from the tables, the integer sum of the reference.
    const Rgba8* data = t.data8(lut->level, 0);
    const auto& n = lut->size;
    const Rgba8 border = u.sampler.borderColor;
    const int b = lut->weightBits;
    const uint64_t half = b > 0 ? uint64_t(1) << (b - 1) : 0;
    const int dims = lut->dims;
    static const detail::AxisFootprint kUnused{{0, 0}, {1, 0}, 1};
    for (Rgba8& px : pixels) {
        // RGB mode: q = 1 = 255/255, which a 4D texture reads as its fourth coordinate.
        const uint8_t bytes[4] = {px.r, px.g, px.b, mode == PixelTexGenMode::Rgb ? uint8_t(255) : px.a};
        const detail::AxisFootprint* ax[4];
        for (int d = 0; d < 4; ++d) ax[d] = d < dims ? &lut->axis[size_t(d)][bytes[d]] : &kUnused;
        uint64_t acc[4] = {0, 0, 0, 0};
        for (int iw = 0; iw < ax[3]->count; ++iw) {
            const int32_t w = ax[3]->index[iw];
            for (int iz = 0; iz < ax[2]->count; ++iz) {
                const int32_t z = ax[2]->index[iz];
                const uint64_t wzw = uint64_t(ax[3]->weight[iw]) * ax[2]->weight[iz];
                for (int iy = 0; iy < ax[1]->count; ++iy) {
                    const int32_t y = ax[1]->index[iy];
                    const uint64_t wyzw = wzw * ax[1]->weight[iy];
                    const bool outYzw = (w | z | y) < 0;
                    const size_t row = ((size_t(w) * size_t(n[2]) + size_t(z)) * size_t(n[1]) + size_t(y)) * size_t(n[0]);
                    for (int ix = 0; ix < ax[0]->count; ++ix) {
                        const int32_t x = ax[0]->index[ix];
                        const uint64_t wt = wyzw * ax[0]->weight[ix];
                        const Rgba8 c = (outYzw || x < 0) ? border : data[row + size_t(x)];
                        acc[0] += wt * c.r;
                        acc[1] += wt * c.g;
                        acc[2] += wt * c.b;
                        acc[3] += wt * c.a;
                    }
                }
            }
        }
        Rgba8 v{uint8_t((acc[0] + half) >> b), uint8_t((acc[1] + half) >> b),
                uint8_t((acc[2] + half) >> b), uint8_t((acc[3] + half) >> b)};
        if (table) v = applyColorTable(*table, v);
        if (mode == PixelTexGenMode::Rgb) v.a = px.a;
        px = v;
    }
    fetches_->add(uint64_t(pixels.size()) * lut->tapsPerPixel);
}

}  // namespace rg::tex
