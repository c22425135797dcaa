// Texture storage: texel arrays per level and face, the emulated texture memory that
// holds them, and the explicit-upload model (docs/hardware.md, "Texture storage and
// memory").
//
// Every mipmap level is uploaded explicitly (Direct3D 7 surfaces, glTexImage per level);
// buildBoxMipmaps() derives a chain only when the application asks for it. A texture is
// complete once every level of every face has been uploaded; validate() refuses to draw
// with an incomplete one.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec4.hpp>

#include "core/color.h"
#include "core/profile.h"
#include "texunit/format.h"

namespace rg::tex {

enum class TextureTarget : uint8_t { Texture1D, Texture2D, Texture3D, CubeMap, Texture4D };

// Cube faces in the ARB_texture_cube_map / D3DCUBEMAP_FACES order.
enum class CubeFace : uint8_t { PositiveX, NegativeX, PositiveY, NegativeY, PositiveZ, NegativeZ };

struct TextureDesc {
    TextureTarget target = TextureTarget::Texture2D;
    TexelFormat format = TexelFormat::RGBA8;
    // Level-0 extent per dimension: width (s), height (t), depth (r), size4 (q, the
    // SGIS_texture4D TEXTURE_4DSIZE_SGIS). Unused dimensions must be 1.
    int width = 1, height = 1, depth = 1, size4 = 1;
    int levels = 1;  // mipmap levels stored; at most the full chain
};

class TextureMemory;

class Texture {
  public:
    ~Texture();
    Texture(const Texture&) = delete;
    Texture& operator=(const Texture&) = delete;

    const TextureDesc& desc() const { return desc_; }
    const FormatInfo& format() const { return formatInfo(desc_.format); }
    int dims() const { return dims_; }            // 1, 2, 3 or 4 (cube: 2)
    int faces() const { return faces_; }          // 6 for cube maps, else 1
    int levels() const { return desc_.levels; }
    bool isFloat() const { return format().isFloat; }
    // Extent of `level` per dimension (max(1, size >> level)); unused dimensions are 1.
    const std::array<int, 4>& levelSize(int level) const { return levels_[level].size; }
    uint64_t bytes() const { return bytes_; }     // packed size, all levels and faces
    bool complete() const;                        // every level of every face uploaded

    // Expanded texel at integer coordinates inside the level (no addressing here:
    // that is the sampler's job). 8-bit formats only / float formats only.
    Rgba8 texel8(int level, int face, int x, int y, int z, int w) const {
        return levels_[level].texels8[size_t(face) * levels_[level].count +
                                      index(level, x, y, z, w)];
    }
    // I16 only: the stored 16-bit value (texel8 holds its 8-bit expansion, narrow16).
    uint16_t texel16(int level, int face, int x, int y, int z, int w) const {
        return levels_[level].texels16[size_t(face) * levels_[level].count +
                                       index(level, x, y, z, w)];
    }
    bool is16() const { return desc_.format == TexelFormat::I16; }
    glm::vec4 texelFloat(int level, int face, int x, int y, int z, int w) const {
        const size_t i = size_t(face) * levels_[level].count + index(level, x, y, z, w);
        if (singleChannel_) {
            // One float per texel in memory, expanded as expandTexelFloat() does.
            const float v = levels_[level].texelsR[i];
            return format().isDepth ? glm::vec4(v, v, v, 1.0f) : glm::vec4(v, 0.0f, 0.0f, 1.0f);
        }
        return levels_[level].texelsF[i];
    }
    // R16F, R32F and the depth formats keep one float per texel (dataR), the other float
    // formats a vec4 (dataF): a 512² R32F depth map is 1 MiB, not 4, and stays in cache
    // for the image-space searches that read it many times per fragment.
    bool singleChannel() const { return singleChannel_; }
    // Row-major level data of one face (x fastest, then y, z, w).
    const Rgba8* data8(int level, int face) const {
        return levels_[level].texels8.data() + size_t(face) * levels_[level].count;
    }
    const glm::vec4* dataF(int level, int face) const {
        return levels_[level].texelsF.data() + size_t(face) * levels_[level].count;
    }
    const float* dataR(int level, int face) const {
        return levels_[level].texelsR.data() + size_t(face) * levels_[level].count;
    }

    // Render-to-texture (geforce8800): a texture made by TextureMemory::createRenderTarget()
    // is written in place by the programmable pipeline's output merger, so a later pass
    // samples what an earlier one drew without a copy (the Direct3D 10 render-target view
    // and shader-resource view of one resource). Row-major level data of one face; the
    // 8-bit array for RGBA8, the float array (vec4 per texel) for float and depth formats.
    bool isRenderTarget() const { return renderTarget_; }
    Rgba8* renderData8(int level, int face) {
        return levels_[level].texels8.data() + size_t(face) * levels_[level].count;
    }
    glm::vec4* renderDataF(int level, int face) {
        return levels_[level].texelsF.data() + size_t(face) * levels_[level].count;
    }
    float* renderDataR(int level, int face) {
        return levels_[level].texelsR.data() + size_t(face) * levels_[level].count;
    }

  private:
    friend class TextureMemory;
    struct Level {
        std::array<int, 4> size{1, 1, 1, 1};
        size_t count = 0;                 // texels per face
        std::vector<Rgba8> texels8;       // faces × count (8-bit formats)
        std::vector<glm::vec4> texelsF;   // faces × count (RGBA16F, RGBA32F)
        std::vector<float> texelsR;       // faces × count (R16F, R32F, depth formats)
        std::vector<uint16_t> texels16;   // faces × count (I16; texels8 holds narrow16)
        std::array<bool, 6> uploaded{};
    };
    struct Pool;
    Texture(const TextureDesc& desc, std::shared_ptr<Pool> pool);
    size_t index(int level, int x, int y, int z, int w) const {
        const auto& s = levels_[level].size;
        return ((size_t(w) * s[2] + size_t(z)) * s[1] + size_t(y)) * s[0] + size_t(x);
    }

    TextureDesc desc_;
    int dims_ = 2, faces_ = 1;
    uint64_t bytes_ = 0;
    bool renderTarget_ = false;
    bool singleChannel_ = false;
    std::vector<Level> levels_;
    std::shared_ptr<Pool> pool_;
};

// The emulated texture memory of one profile (Profile::textureMemoryBytes). Creating a
// texture reserves its packed size for all levels up front, as the period drivers did;
// overflowing the memory is an error (rg::UnsupportedFeature naming the profile), never a
// silent eviction. Uploads are counted per frame in TextureCounters::uploadBytes.
class TextureMemory {
  public:
    explicit TextureMemory(const Profile& profile);
    ~TextureMemory();

    const Profile& profile() const { return *profile_; }
    // Checks the target, format and size against the profile (power-of-two rule, maximum
    // edge, cube/4D/float/depth features, a full chain at most) and reserves memory.
    std::shared_ptr<Texture> create(const TextureDesc& desc);
    // A texture the programmable pipeline can render into (Feature::RenderToTexture):
    // RGBA8, R16F, RGBA16F, R32F, RGBA32F colour or Depth24/Depth32F depth, 1D/2D or cube.
    // Every level is complete from the start, cleared to zero; it occupies texture memory
    // like any texture (the G80 kept render targets in the same video memory).
    std::shared_ptr<Texture> createRenderTarget(const TextureDesc& desc);
    // Uploads one level of one face from packed bytes in the format's layout (rows x
    // fastest). Throws rg::InvalidState when `bytes` does not hold exactly the level.
    void upload(Texture& texture, int level, int face, std::span<const uint8_t> bytes);
    // RGBA8 textures only: the same bytes seen as Rgba8 texels (R, G, B, A in memory).
    void upload(Texture& texture, int level, int face, std::span<const Rgba8> texels);

    // Builds levels 1.. of every face from level 0 by 2×…×2 box filtering (round to
    // nearest, per component of the packed format's expansion) and uploads them. Only
    // for 8-bit RGBA8/RGB8/L8/A8/L8A8/I8 formats; counted as uploads.
    void buildBoxMipmaps(Texture& texture);

    uint64_t residentBytes() const;
    uint64_t uploadBytes() const;    // since the last resetFrameCounters()
    void resetFrameCounters();

  private:
    const Profile* profile_;
    std::shared_ptr<Texture::Pool> pool_;
};

// Number of levels of a full mipmap chain for the given level-0 extent.
int fullChainLevels(const TextureDesc& desc);

}  // namespace rg::tex
