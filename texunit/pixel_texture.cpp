// SGIX_pixel_texture (docs/hardware.md, "Pixel texture").
#include <cstdint>

#include "texunit/texture_units.h"

#include "fetch_counter.h"

namespace rg::tex {

void TextureUnits::applyPixelTransfer(std::span<Rgba8> pixels) const {
    if (!pixelTexture_.enabled) return;
    const Unit& u = units_[pixelTexture_.stage];
    if (!u.texture) return;
    const Texture& t = *u.texture;
    // A pixel rectangle has no screen-space derivatives: λ is taken as magnification, the
    // base level with the magnification filter (for 4D textures: quadrilinear).
    const int32_t lambda = -(1 << 20);
    const bool fourD = t.desc().target == TextureTarget::Texture4D;
    uint64_t fetched = 0;
    TapList taps;
    for (Rgba8& px : pixels) {
        // Colour components become coordinates: c/255 exactly as the pixel path converts
        // 8-bit components to [0, 1].
        glm::vec4 c(px.r / 255.0f, px.g / 255.0f, px.b / 255.0f,
                    pixelTexture_.mode == PixelTexGenMode::Rgba ? px.a / 255.0f : 1.0f);
        if (!fourD) {
            // 1D/2D/3D: the projective divide by q. q ≤ 0 (alpha 0) puts the coordinate at
            // infinity; we pin the result to the border colour rather than divide.
            if (!(c.w > 0.0f)) {
                Rgba8 b = u.sampler.borderColor;
                if (u.colorTable) b = applyColorTable(*u.colorTable, b);
                if (pixelTexture_.mode == PixelTexGenMode::Rgb) b.a = px.a;
                px = b;
                continue;
            }
            c = glm::vec4(c.x / c.w, c.y / c.w, c.z / c.w, 0.0f);
        }
        gatherTaps(t, u.sampler, c, lambda, taps);
        fetched += uint64_t(taps.count);
        Rgba8 v = resolveTaps(t, u.sampler, taps);
        if (u.colorTable) v = applyColorTable(*u.colorTable, v);
        if (pixelTexture_.mode == PixelTexGenMode::Rgb) v.a = px.a;
        px = v;
    }
    fetches_->add(fetched);
}

}  // namespace rg::tex
