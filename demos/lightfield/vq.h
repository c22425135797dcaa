// Vector-quantized light fields rendered directly by the hardware (Heidrich et al. 1999 §5).
//
// Blocks of bs·bt·bu·bv samples (2 or 1 per axis) become one index into a codebook trained
// by LBG / k-means (Eigen computes the distances: ‖x‖² − 2x·c + ‖c‖² by matrix products).
// The codebook is split into one colour table per parity class (odd/even sample in each
// halved axis: "16 different tables, where each only returns a single color value"), and
// the indices into one-component textures (I16: 2-byte indices, the sgi-octane-mxe's
// 16-bit index path; I8 when K ≤ 256).
//
// Rendering (renderVq), the passes of §5 on the emulated device:
//   (s, t) halved: the Gortler reconstruction with the index texture (NEAREST) through the
//     table of the eye point's (s, t) parity; eye points ordered by parity, so 4 table
//     loads a frame.
//   (u, v) halved too: per eye point and (u, v) parity two passes: A writes the bilinear
//     basis (a 2×2 texture, one texel 255, replicated U/2 times, LINEAR, shifted one texel
//     per parity) times the eye point's weight into the destination alpha; B draws the
//     index texture NEAREST through that parity's table, blended DESTALPHA·src + ONE·dst
//     into RGB. The index lookup is offset by ½ sample towards the hat's block (our choice,
//     derived: without it a quarter of each hat reads the neighbouring block). Eye points
//     grouped by parity class: 16 table loads a frame.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/color.h"
#include "gortler_renderer.h"
#include "light_slab.h"
#include "rasterizer/device.h"
#include "texunit/color_table.h"

namespace rg::lightfield {

struct BlockShape {
    int s = 2, t = 2, u = 2, v = 2;  // samples per block along each axis (1 or 2)
    int samples() const { return s * t * u * v; }
    int dims() const { return samples() * 3; }
    bool uvHalved() const { return u == 2 || v == 2; }
};

struct VqOptions {
    int codebookSize = 1024;     // K
    int trainingBlocks = 32768;  // a random subset of the blocks (LBG on all of them at K = 2^16 takes hours)
    int iterations = 8;
    uint32_t seed = 1;
    int threads = 0;
};

struct VqLightField {
    LightSlab slab;          // the original resolution
    BlockShape shape;
    int K = 0;
    std::vector<uint8_t> codebook;    // K × dims, the block's samples in (s, t, u, v) parity order, RGB
    std::vector<uint16_t> indices;    // per block, [bt][bs][bv][bu]
    double trainSeconds = 0, encodeSeconds = 0;
    int blocksS() const { return slab.S / shape.s; }
    int blocksT() const { return slab.T / shape.t; }
    int blocksU() const { return slab.U / shape.u; }
    int blocksV() const { return slab.V / shape.v; }
    size_t blockIndex(int bi, int bj, int bk, int bl) const {
        return ((size_t(bj) * blocksS() + size_t(bi)) * blocksV() + size_t(bl)) * blocksU() + size_t(bk);
    }
    // The parity class of sample (i, j, k, l) inside its block: its offset in the codeword.
    int parity(int i, int j, int k, int l) const {
        const int ps = shape.s == 2 ? (i & 1) : 0, pt = shape.t == 2 ? (j & 1) : 0;
        const int pu = shape.u == 2 ? (k & 1) : 0, pv = shape.v == 2 ? (l & 1) : 0;
        return ((pt * shape.s + ps) * shape.v + pv) * shape.u + pu;
    }
    int indexBytes() const { return K > 256 ? 2 : 1; }
    uint64_t indexTextureBytes() const { return uint64_t(indices.size()) * uint64_t(indexBytes()); }
    uint64_t codebookBytes() const { return uint64_t(K) * uint64_t(shape.dims()); }
};

// Trains the codebook on a subset and encodes every block; throws rg::Error for a shape
// that does not divide the slab, K outside [2, 65536], or fewer blocks than K.
VqLightField quantize(const LightField& lf, const BlockShape& shape, const VqOptions& options);
// The decoded light field (each block replaced by its codeword): the software reference of
// what the passes reconstruct. Throws rg::Error naming the block when an index is outside
// the codebook.
LightField decode(const VqLightField& vq);

// The index textures and colour tables on one profile.
class VqTextures {
  public:
    // Refuses (rg::UnsupportedFeature naming the profile) a codebook larger than the
    // profile's colour tables, and an index outside the codebook (rg::Error).
    VqTextures(std::shared_ptr<tex::TextureMemory> memory, const VqLightField& vq);
    std::shared_ptr<const tex::Texture> indexTexture(int bi, int bj) const {
        return textures_[size_t(bj) * vq_->blocksS() + size_t(bi)];
    }
    std::shared_ptr<const tex::ColorTable> table(int parity) const { return tables_[size_t(parity)]; }
    std::shared_ptr<const tex::Texture> basis() const { return basis_; }
    uint64_t textureBytes() const;

  private:
    const VqLightField* vq_;
    std::vector<std::shared_ptr<tex::Texture>> textures_;
    std::vector<std::shared_ptr<const tex::ColorTable>> tables_;
    std::shared_ptr<tex::Texture> basis_;
};

struct VqStats {
    int tableLoads = 0;
    int colorPasses = 0, basisPasses = 0;     // draws
    uint64_t colorFragments = 0, basisFragments = 0;
};

VqStats renderVq(raster::Device& device, const VqTextures& textures, const VqLightField& vq, const ray::Camera& camera);

}  // namespace rg::lightfield
