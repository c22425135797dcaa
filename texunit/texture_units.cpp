// Placeholder cascade: no stages yet (issue 3 builds the texture units). Behaves as a
// Direct3D 7 device with stage 0 disabled: the fragment colour is the diffuse colour.
#include "texunit/texture_units.h"

namespace rg::tex {

void TextureUnits::validate(const Profile&) const {}
bool TextureUnits::passThrough() const { return true; }
uint32_t TextureUnits::texCoordSetsUsed() const { return 0; }
glm::vec4 TextureUnits::processVertexTexCoord(int, const VertexEye&, const glm::vec4& in) const {
    return in;
}
void TextureUnits::shadeQuad(const FragmentQuad& quad, std::array<Rgba8, 4>& out, Path) const {
    out = quad.diffuse;
}
void TextureUnits::applyPixelTransfer(std::span<Rgba8>) const {}

}  // namespace rg::tex
