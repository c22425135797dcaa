// The second half of every frame (Heidrich et al. 1999 §4): "the framebuffer contents are
// read back to main memory and for each pixel the texture coordinates need to be used to
// look up the illumination ... before the resulting image is written back".
//
//   (a) PixelTextureRoute: drawPixels of the read-back through SGIX_pixel_texture
//       (sgi-octane-mxe): the dual-paraboloid map as a 3D texture (RGB mode: (R, G, B) →
//       (s, t, r), alpha kept), or a second light field as a 4D texture (RGBA mode:
//       (u, v, s, t));
//   (b) SoftwareLookup: the O2's way, "relatively inexpensive ... feasible even on low end
//       platforms": the same lookup on the host, then drawPixels without pixel texture.
//
// The software lookup is written out from docs/hardware.md ("Filtering", "Pixel
// texture"): coordinate c = byte/255, texel coordinate ⌊c·n·256⌋ in 8 sub-texel bits,
// LINEAR taps ⌊u − ½⌋ and the next with weights 256 − α and α, CLAMP_TO_EDGE, the integer
// sum Σ w·texel rounded once. So both routes give the same bytes
// (LightFieldRoutes.PixelTextureEqualsSoftware), which the report's claim checks.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/color.h"
#include "lf_capture.h"
#include "rasterizer/device.h"

namespace rg::lightfield {

// A texture as the host holds it for the software route: RGBA8 texels, x fastest, up to
// four dimensions (unused extents 1).
struct HostTexture {
    int dims = 2;
    std::array<int, 4> size{1, 1, 1, 1};
    std::vector<Rgba8> texels;
};
HostTexture hostParaboloidMap(const ParaboloidMap& map);  // size × size × 2 (side along r)
HostTexture hostLightField4D(const LightField& lf);        // RGB radiance, (u, v, s, t)

// Per axis and coordinate byte: the two texels and weights of LINEAR CLAMP_TO_EDGE
// filtering (built once per texture: the O2 programmer's table).
class SoftwareLookup {
  public:
    // rgbOnly: RGB mode (q = 1, alpha kept) for the 3D map; else all four bytes are
    // coordinates (4D).
    SoftwareLookup(const HostTexture& texture, bool rgbOnly);
    void apply(std::vector<Rgba8>& pixels, int threads) const;
    // One pixel (the scalar twin the tests and the plain-loop benchmark use).
    Rgba8 lookup(Rgba8 px) const;

  private:
    struct Axis {
        int32_t i0[256], i1[256];
        uint32_t w0[256], w1[256];
    };
    const HostTexture* tex_;
    bool rgbOnly_;
    std::array<Axis, 4> axis_{};
};

// The pixel-texture route on `device` (sgi-octane-mxe): the texture bound to unit 0 with
// LINEAR CLAMP_TO_EDGE filtering, pixel texture enabled in `mode`, drawPixels of `pixels`
// at (0, 0), pixel texture disabled again.
void pixelTextureLookup(raster::Device& device, std::shared_ptr<const tex::Texture> texture, tex::PixelTexGenMode mode,
                        const std::vector<Rgba8>& pixels);

}  // namespace rg::lightfield
