// Hardware profiles: data tables naming what each emulated machine has and its limits.
//
// A demo runs on the profile of its paper's machine and the profile's limits shape the
// passes (two texture stages per pass on a GeForce 256 → the PEM paper's 3 passes).
// Every capability check goes through Profile::require(), which throws
// rg::UnsupportedFeature naming the profile and the feature: never a silent fallback.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace rg {

enum class Feature : uint32_t {
    CubeMap,              // ARB_texture_cube_map / D3D7 cube environment maps
    TextureStages,        // the Direct3D 7 texture-stage cascade (COLOROP/ALPHAOP)
    TextureEnvCombine,    // ARB_texture_env_combine on the SGI profiles
    PixelTexture,         // SGIX_pixel_texture
    TextureColorTable,    // SGI_texture_color_table
    Texture4D,            // SGIS_texture4D
    Texture3D,            // volume textures
    ProjectedTexture,     // the q divide of projective texturing
    FloatTexture,         // R16F, RGBA16F, R32F, RGBA32F textures
    FloatRenderTarget,    // float colour targets and their blending
    MultipleRenderTargets,
    RenderToTexture,
    DepthTexture,         // depth textures with compare (shadow maps)
    VertexProgram,
    FragmentProgram,
    NonPowerOfTwoTexture,
    BlendMinMax,          // EXT_blend_minmax / D3DBLENDOP_MIN, MAX
    BlendSubtract,        // EXT_blend_subtract / D3DBLENDOP_(REV)SUBTRACT
    Depth16,
    Depth24,
    Depth32,
    Count
};

std::string_view featureName(Feature f);

enum class ProfileId : uint32_t { GeForce256, GeForce3, SgiOctaneMxe, SgiO2, GeForce8800 };

// The 'api' a profile speaks decides which texture-environment vocabulary applies.
enum class Api : uint32_t { Direct3D7, Direct3D8, OpenGL12, Direct3D10 };

struct Profile {
    ProfileId id;
    std::string_view name;         // command-line name: "geforce256", ...
    std::string_view machine;      // "NVIDIA GeForce 256 (NV10), 1999"
    Api api;
    std::string_view apiName;      // "Direct3D 7 fixed function"
    std::string_view sources;      // where the numbers come from (docs/hardware.md)

    // Texturing
    int maxTextureStages;          // texture accesses per pass (D3D MaxSimultaneousTextures)
    int maxTexCoordSets;           // interpolated coordinate sets per vertex
    int maxTextureSize;            // largest 1D/2D edge, texels
    int maxCubeMapSize;            // largest cube face edge (0: no cube maps)
    int max4DTextureSize;          // largest 4D edge (0: no 4D textures)
    int colorTableSize;            // largest texture colour table (0: none)
    uint64_t textureMemoryBytes;   // emulated texture memory
    bool powerOfTwoOnly;

    // Framebuffer
    int maxViewport;               // largest render-target edge, pixels
    int colorBits;                 // per channel of the colour buffer (8 for RGBA8)
    int subpixelBits;              // fractional bits of window coordinates after snapping

    uint64_t featureMask;          // bit (1 << Feature)

    bool has(Feature f) const { return (featureMask >> static_cast<uint32_t>(f)) & 1u; }
    // Throws rg::UnsupportedFeature("<name>", "<feature>", detail) when !has(f).
    void require(Feature f, std::string_view detail = {}) const;
    // Throws rg::UnsupportedFeature when value > limit (e.g. "texture size 4096 > 2048").
    void requireLimit(std::string_view what, int64_t value, int64_t limit) const;
};

std::span<const Profile> allProfiles();
const Profile& profile(ProfileId id);
// Throws rg::Error listing the known names when `name` is not one of them.
const Profile& profileByName(std::string_view name);

}  // namespace rg
