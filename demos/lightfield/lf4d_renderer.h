// The uncompressed light field as one 4D texture (Heidrich et al. 1999 §5, SGIS_texture4D):
// "With 4D texture mapping the rendering of 2-plane parameterized light fields becomes
// extremely simple. The (s, t) grid is projected down on the (u, v)-plane to compute the
// texture coordinates for the corner vertices of the (u, v)-grid. Then (u, v)-plane is
// rendered as a single polygon with the precomputed 4D texture coordinates, and the light
// field as a texture."
//
// Texel (x, y, z, w) = sample (u, v, s, t), LINEAR (quadrilinear: one rounding of the
// 16-tap sum), CLAMP_TO_EDGE, REPLACE. The reference the 4D-basis VQ passes (vq.h,
// renderVq4D) reconstruct, with the same coordinates (window4DCoords). "The disadvantage
// ... is, that the whole light field needs to fit into the texture RAM": the constructor
// refuses one that does not (rg::UnsupportedFeature naming the profile), as it refuses a
// profile without 4D textures.
#pragma once

#include <memory>

#include "light_slab.h"
#include "rasterizer/device.h"
#include "texunit/texture.h"

namespace rg::lightfield {

class LightFieldTexture4D {
  public:
    LightFieldTexture4D(std::shared_ptr<tex::TextureMemory> memory, const LightField& lf);
    std::shared_ptr<const tex::Texture> texture() const { return texture_; }

  private:
    std::shared_ptr<tex::Texture> texture_;
};

struct LightField4DStats {
    uint64_t fragments = 0;
};

// Clears to 0 and draws the window polygon; alpha 255 where it covers.
LightField4DStats renderLightField4D(raster::Device& device, const LightFieldTexture4D& texture, const LightSlab& slab,
                                     const ray::Camera& camera);

}  // namespace rg::lightfield
