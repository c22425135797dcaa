#include "core/profile.h"

#include <array>
#include <string>

#include "core/error.h"

namespace rg {

namespace {

constexpr uint64_t bit(Feature f) { return uint64_t{1} << static_cast<uint32_t>(f); }

constexpr uint64_t MiB = uint64_t{1} << 20;

// The numbers below and their sources are tabulated in docs/hardware.md, "Profiles".
// Where the period documentation is silent the value is our choice and says so there.
constexpr std::array<Profile, 5> kProfiles = {{
    {ProfileId::GeForce256, "geforce256", "NVIDIA GeForce 256 (NV10), 1999", Api::Direct3D7,
     "Direct3D 7 fixed function",
     "D3D7 caps of NV10: 2 simultaneous textures, 2048^2 textures, 512^2 cube faces; 32 MiB board",
     /*maxTextureStages*/ 2, /*maxTexCoordSets*/ 8, /*maxTextureSize*/ 2048,
     /*maxCubeMapSize*/ 512, /*max4D*/ 0, /*colorTableSize*/ 0,
     /*textureMemoryBytes*/ 32 * MiB, /*powerOfTwoOnly*/ true,
     /*maxViewport*/ 2048, /*colorBits*/ 8, /*subpixelBits*/ 4,
     bit(Feature::CubeMap) | bit(Feature::TextureStages) | bit(Feature::ProjectedTexture) |
         bit(Feature::BlendMinMax) | bit(Feature::BlendSubtract) | bit(Feature::Depth16) |
         bit(Feature::Depth24)},
    {ProfileId::GeForce3, "geforce3", "NVIDIA GeForce3 (NV20), 2001", Api::Direct3D8,
     "Direct3D 8 fixed function",
     "D3D8 caps of NV20: 4 simultaneous textures, 4096^2 textures and cube faces; 64 MiB board",
     4, 8, 4096, 4096, 0, 0, 64 * MiB, true, 4096, 8, 4,
     bit(Feature::CubeMap) | bit(Feature::TextureStages) | bit(Feature::ProjectedTexture) |
         bit(Feature::Texture3D) | bit(Feature::BlendMinMax) | bit(Feature::BlendSubtract) |
         bit(Feature::Depth16) | bit(Feature::Depth24)},
    {ProfileId::SgiOctaneMxe, "sgi-octane-mxe", "SGI Octane MXE (IMPACT graphics), 1997",
     Api::OpenGL12, "OpenGL 1.2 + SGIX_pixel_texture, SGI_texture_color_table, SGIS_texture4D",
     "IMPACT: one texture unit, 4 MiB texture RAM (TRAM); pixel texture and 4D textures "
     "as used at 15-20 fps by Heidrich et al. 1999; 16-bit index textures and 65,536-entry "
     "texture colour tables for their 2^16-entry VQ codebook (§5)",
     // colorTableSize 65,536: the 2^16-entry codebook with 2-byte indices that Heidrich
     // et al. 1999 §5 render through SGI_texture_color_table (with I16 index textures).
     1, 1, 1024, 0, 64, 65536, 4 * MiB, true, 2048, 8, 4,
     bit(Feature::TextureEnvCombine) | bit(Feature::PixelTexture) |
         bit(Feature::TextureColorTable) | bit(Feature::Texture4D) | bit(Feature::Texture3D) |
         bit(Feature::ProjectedTexture) | bit(Feature::BlendMinMax) |
         bit(Feature::BlendSubtract) | bit(Feature::Depth16) | bit(Feature::Depth24)},
    {ProfileId::SgiO2, "sgi-o2", "SGI O2 (CRM graphics, R10000 175 MHz), 1996", Api::OpenGL12,
     "OpenGL 1.2 + SGI_texture_color_table (no pixel texture: Heidrich et al. ran the "
     "lookup in software)",
     "CRM: unified memory, textures live in main memory ('almost unlimited', Heidrich et al. "
     "1999 §5); we give it 256 MiB",
     1, 1, 1024, 0, 0, 256, 256 * MiB, true, 2048, 8, 4,
     bit(Feature::TextureEnvCombine) | bit(Feature::TextureColorTable) |
         bit(Feature::ProjectedTexture) | bit(Feature::BlendMinMax) |
         bit(Feature::BlendSubtract) | bit(Feature::Depth16) | bit(Feature::Depth24)},
    {ProfileId::GeForce8800, "geforce8800", "NVIDIA GeForce 8800 GTX (G80), 2006",
     Api::Direct3D10, "Direct3D 10 / OpenGL 2.1 programmable, Cg shaders",
     "G80: 16 fragment texture units (GL_MAX_TEXTURE_IMAGE_UNITS), 8192^2 textures, "
     "8 render targets, 768 MiB; D3D10 mandates 8 subpixel bits",
     16, 8, 8192, 8192, 0, 0, 768 * MiB, false, 8192, 8, 8,
     bit(Feature::CubeMap) | bit(Feature::TextureStages) | bit(Feature::ProjectedTexture) |
         bit(Feature::Texture3D) | bit(Feature::FloatTexture) |
         bit(Feature::FloatRenderTarget) | bit(Feature::MultipleRenderTargets) |
         bit(Feature::RenderToTexture) | bit(Feature::DepthTexture) |
         bit(Feature::VertexProgram) | bit(Feature::FragmentProgram) |
         bit(Feature::NonPowerOfTwoTexture) | bit(Feature::BlendMinMax) |
         bit(Feature::BlendSubtract) | bit(Feature::Depth16) | bit(Feature::Depth24) |
         bit(Feature::Depth32)},
}};

constexpr std::array<std::string_view, static_cast<size_t>(Feature::Count)> kFeatureNames = {
    "cube maps (ARB_texture_cube_map)",
    "Direct3D texture stages",
    "ARB_texture_env_combine",
    "pixel texture (SGIX_pixel_texture)",
    "texture color tables (SGI_texture_color_table)",
    "4D textures (SGIS_texture4D)",
    "3D textures",
    "projected texture coordinates",
    "float textures",
    "float render targets",
    "multiple render targets",
    "render to texture",
    "depth textures",
    "vertex programs",
    "fragment programs",
    "non-power-of-two textures",
    "blend min/max",
    "blend subtract",
    "16-bit depth",
    "24-bit depth",
    "32-bit depth",
};

}  // namespace

std::string_view featureName(Feature f) {
    auto i = static_cast<size_t>(f);
    return i < kFeatureNames.size() ? kFeatureNames[i] : std::string_view("unknown feature");
}

void Profile::require(Feature f, std::string_view detail) const {
    if (!has(f))
        throw UnsupportedFeature(std::string(name), std::string(featureName(f)),
                                 std::string(detail));
}

void Profile::requireLimit(std::string_view what, int64_t value, int64_t limit) const {
    if (value > limit)
        throw UnsupportedFeature(std::string(name), std::string(what),
                                 std::to_string(value) + " exceeds the limit " +
                                     std::to_string(limit));
}

std::span<const Profile> allProfiles() { return kProfiles; }

const Profile& profile(ProfileId id) { return kProfiles.at(static_cast<size_t>(id)); }

const Profile& profileByName(std::string_view name) {
    for (const Profile& p : kProfiles)
        if (p.name == name) return p;
    std::string known;
    for (const Profile& p : kProfiles) known += (known.empty() ? "" : ", ") + std::string(p.name);
    throw Error("unknown profile '" + std::string(name) + "' (known: " + known + ")");
}

}  // namespace rg
