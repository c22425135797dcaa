// SGI_texture_color_table: a per-unit RGBA lookup applied after filtering and before the
// texture environment (docs/hardware.md, "Colour tables").
#pragma once

#include <cstdint>
#include <vector>

#include "core/color.h"
#include "texunit/format.h"

namespace rg::tex {

// A table of N entries with its own base format, as SGI_color_table's glColorTableSGI
// defines it. Entries are stored expanded to RGBA8: Luminance and Intensity tables keep
// their value in r, Alpha tables in a.
struct ColorTable {
    BaseFormat format = BaseFormat::Rgba;
    std::vector<Rgba8> entries;
};

// Entry index for an 8-bit component: round(clamp(c)·(N−1)) with c = v/255, computed
// exactly in integers as ⌊(2·v·(N−1) + 255) / 510⌋.
uint32_t colorTableIndex(uint8_t v, size_t n);

// The lookup (SGI_color_table, "Color Table Lookup", applied to the filtered texel):
//   table Alpha:           A ← T[A].a
//   table Luminance:       R ← T[R].l, G ← T[G].l, B ← T[B].l
//   table LuminanceAlpha:  R, G, B ← T[·].l, A ← T[A].a
//   table Intensity:       R, G, B, A ← T[·].i
//   table Rgb:             R ← T[R].r, G ← T[G].g, B ← T[B].b
//   table Rgba:            R ← T[R].r, G ← T[G].g, B ← T[B].b, A ← T[A].a
// Components the table does not carry pass unchanged. The texel's base format then
// becomes the union of the texture's and the table's (an I8 index texture through an
// RGBA table is an RGBA texel: VQ codebook decoding).
Rgba8 applyColorTable(const ColorTable& table, Rgba8 texel);

// The 16-bit index path (I16 textures; Heidrich et al. 1999 §5's 2-byte indices into a
// 2^16-entry codebook): round(c·(N − 1)) of the 16-bit filtered intensity c = v/65535,
// ⌊(2·v·(N − 1) + 65535)/131070⌋ exactly; for N = 65536 the index is v itself.
uint32_t colorTableIndex16(uint16_t v, size_t n);
// The lookup of an I16 texel v: every component is v, so one index i serves all the
// table's components (the rows of applyColorTable with T[i]); components the table does
// not replace keep the 8-bit expansion narrow16(v).
Rgba8 applyColorTable16(const ColorTable& table, uint16_t v);
BaseFormat colorTableResultFormat(BaseFormat texture, BaseFormat table);

}  // namespace rg::tex
