// SGI_texture_color_table (docs/hardware.md, "Colour tables").
#include "texunit/color_table.h"

namespace rg::tex {

uint32_t colorTableIndex(uint8_t v, size_t n) {
    // round(v/255 · (N − 1)) = ⌊(2·v·(N−1) + 255) / 510⌋, half up.
    if (n <= 1) return 0;
    return uint32_t((2u * uint64_t(v) * (n - 1) + 255u) / 510u);
}

Rgba8 applyColorTable(const ColorTable& t, Rgba8 c) {
    const size_t n = t.entries.size();
    if (n == 0) return c;
    auto at = [&](uint8_t v) -> const Rgba8& { return t.entries[colorTableIndex(v, n)]; };
    Rgba8 o = c;
    switch (t.format) {
        case BaseFormat::Alpha: o.a = at(c.a).a; break;
        case BaseFormat::Luminance: o.r = at(c.r).r; o.g = at(c.g).r; o.b = at(c.b).r; break;
        case BaseFormat::LuminanceAlpha:
            o.r = at(c.r).r; o.g = at(c.g).r; o.b = at(c.b).r; o.a = at(c.a).a;
            break;
        case BaseFormat::Intensity:
            o.r = at(c.r).r; o.g = at(c.g).r; o.b = at(c.b).r; o.a = at(c.a).r;
            break;
        case BaseFormat::Rgb: o.r = at(c.r).r; o.g = at(c.g).g; o.b = at(c.b).b; break;
        case BaseFormat::Rgba:
            o.r = at(c.r).r; o.g = at(c.g).g; o.b = at(c.b).b; o.a = at(c.a).a;
            break;
    }
    return o;
}

uint32_t colorTableIndex16(uint16_t v, size_t n) {
    if (n <= 1) return 0;
    return uint32_t((2u * uint64_t(v) * (n - 1) + 65535u) / 131070u);
}

Rgba8 applyColorTable16(const ColorTable& t, uint16_t v) {
    const uint8_t e = narrow16(v);
    const size_t n = t.entries.size();
    if (n == 0) return {e, e, e, e};
    const Rgba8& T = t.entries[colorTableIndex16(v, n)];
    switch (t.format) {
        case BaseFormat::Alpha: return {e, e, e, T.a};
        case BaseFormat::Luminance: return {T.r, T.r, T.r, e};
        case BaseFormat::LuminanceAlpha: return {T.r, T.r, T.r, T.a};
        case BaseFormat::Intensity: return {T.r, T.r, T.r, T.r};
        case BaseFormat::Rgb: return {T.r, T.g, T.b, e};
        case BaseFormat::Rgba: return T;
    }
    return T;
}

BaseFormat colorTableResultFormat(BaseFormat tex, BaseFormat table) {
    // Union of the components: colour if either has colour (L/I/RGB count as colour),
    // alpha if either has alpha. A table that only has L/I and a texture with only L/I
    // keeps the texture's format.
    if (tex == table) return tex;
    const bool rgb = (tex == BaseFormat::Rgb || tex == BaseFormat::Rgba || table == BaseFormat::Rgb ||
                      table == BaseFormat::Rgba);
    const bool col = hasColor(tex) || hasColor(table);
    const bool alp = hasAlpha(tex) || hasAlpha(table);
    if (rgb) return alp ? BaseFormat::Rgba : BaseFormat::Rgb;
    if (tex == BaseFormat::Intensity || table == BaseFormat::Intensity)
        return (col && alp && !(tex == BaseFormat::Intensity && table == BaseFormat::Intensity))
                   ? BaseFormat::LuminanceAlpha
                   : BaseFormat::Intensity;
    if (col && alp) return BaseFormat::LuminanceAlpha;
    return col ? BaseFormat::Luminance : BaseFormat::Alpha;
}

}  // namespace rg::tex
