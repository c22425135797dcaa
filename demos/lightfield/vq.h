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
// The nearest codeword of each of `rows` vectors of `dims` floats (row-major in `blocks`)
// among the K codewords (row-major in `codebook`): distances ‖c‖² − 2x·c by Eigen matrix
// products, ties to the lowest index. What quantize's LBG iterations and its encoding use,
// for the tests.
std::vector<int> nearestCodewords(const float* blocks, int64_t rows, const float* codebook, int K, int dims, int threads = 0);
// The decoded light field (each block replaced by its codeword): the software reference of
// what the passes reconstruct. Throws rg::Error naming the block when an index is outside
// the codebook.
LightField decode(const VqLightField& vq);

// The index textures and colour tables on one profile.
class VqTextures {
  public:
    // Refuses (rg::UnsupportedFeature naming the profile) a codebook larger than the
    // profile's colour tables, and an index outside the codebook (rg::Error).
    //
    // When the index textures do not all fit beside what the memory holds (the (s, t)- or
    // (u, v)-halved variants at the paper's 32·32·128·128: 8 MiB of 2-byte indices against
    // the Octane's 4 MiB), one texture is re-uploaded whenever another block's indices are
    // asked for — §5's "swapped in and out for every frame", counted by the memory's
    // uploads — instead of refusing the frame.
    VqTextures(std::shared_ptr<tex::TextureMemory> memory, const VqLightField& vq);
    // Block (bi, bj)'s index texture; uploads it first when swapping. The upload changes
    // which block the one streaming texture holds, not what any draw sees: residency, so
    // the accessor stays const (the members it touches are mutable).
    std::shared_ptr<const tex::Texture> indexTexture(int bi, int bj) const;
    std::shared_ptr<const tex::ColorTable> table(int parity) const { return tables_[size_t(parity)]; }
    std::shared_ptr<const tex::Texture> basis() const { return basis_; }
    bool resident() const { return stream_ == nullptr; }
    uint64_t textureBytes() const;

  private:
    std::vector<uint8_t> indexBytes(int bi, int bj) const;
    const VqLightField* vq_;
    std::shared_ptr<tex::TextureMemory> memory_;
    std::vector<std::shared_ptr<tex::Texture>> textures_;
    std::shared_ptr<tex::Texture> stream_;  // when swapping: the one index texture
    mutable int streamed_ = -1;             // the block it holds
    std::vector<std::shared_ptr<const tex::ColorTable>> tables_;
    std::shared_ptr<tex::Texture> basis_;
};

struct VqStats {
    int tableLoads = 0;
    int colorPasses = 0, basisPasses = 0;     // draws
    uint64_t colorFragments = 0, basisFragments = 0;
};

VqStats renderVq(raster::Device& device, const VqTextures& textures, const VqLightField& vq, const ray::Camera& camera);

// ---- §5 "4D VQ": the same codebook drawn through 4D textures (SGIS_texture4D) ----------
//
// "Since 4D texture mapping does not treat the (u, v)-plane differently from the (s, t)-
// plane ... the basis functions are generated by 4D textures of resolution 2^4." The
// (u, v) window is drawn as one polygon (two triangles) whose vertices carry the 4D
// texture coordinates (u, v, s, t) of the ray from the camera through them (affine on the
// window plane, so perspective-correct interpolation is exact). Per parity class p (16 for
// 2×2×2×2 blocks):
//   pass A: the 2^4 basis texture (LINEAR = quadrilinear, WRAP, coordinates × N/2 per
//     axis, shifted one texel along every axis where p is odd), REPLACE into alpha;
//   pass B: the index texture, a 4D I16 (I8) texture of (U/2, V/2, S/2, T/2) blocks,
//     NEAREST, offset ½ sample towards the hat's block on each halved axis, through table
//     p, blended DESTALPHA·src + ONE·dst into RGB.
// 16 table loads and 16 colour passes of one polygon a frame.
//
// The paper: "In each of these textures, exactly two pixels are one and the others are
// zero." With one table per parity class the basis functions sum to one only if each
// texture has one texel set (BasisReading::OneHot, what we render by default);
// BasisReading::TwoPixels sets texel 0 and its opposite corner (1, 1, 1, 1) and, shifted
// once per parity class like the one-hot texture, sums to two (measured, Figure 6).
enum class BasisReading : uint8_t { OneHot, TwoPixels };
const char* basisReadingName(BasisReading r);

// The index texture and tables as 4D textures of one profile. Refuses (rg::UnsupportedFeature
// naming the profile) a profile without SGIS_texture4D or colour tables large enough —
// never falls back to the 2D route — and an index outside the codebook (rg::Error).
class VqTextures4D {
  public:
    VqTextures4D(std::shared_ptr<tex::TextureMemory> memory, const VqLightField& vq,
                 BasisReading reading = BasisReading::OneHot);
    std::shared_ptr<const tex::Texture> indexTexture() const { return index_; }
    std::shared_ptr<const tex::ColorTable> table(int parity) const { return tables_[size_t(parity)]; }
    std::shared_ptr<const tex::Texture> basis() const { return basis_; }
    BasisReading reading() const { return reading_; }
    uint64_t textureBytes() const { return index_->bytes() + basis_->bytes(); }

  private:
    std::shared_ptr<tex::Texture> index_;
    std::vector<std::shared_ptr<const tex::ColorTable>> tables_;
    std::shared_ptr<tex::Texture> basis_;
    BasisReading reading_;
};

// What renderVq4D can hand back besides the frame: Σ over the parity classes of the
// destination alpha each basis pass left (read back after every pass A; per pixel in
// readPixels order). Costs one read-back per pass: tests and figures only.
struct Vq4DProbe {
    std::vector<int> basisSum;
};

VqStats renderVq4D(raster::Device& device, const VqTextures4D& textures, const VqLightField& vq,
                   const ray::Camera& camera, Vq4DProbe* probe = nullptr);

// The 4D texture coordinates (u, v, s, t) of the ray from `eye` through the window point
// at window fractions (wu, wv): eye point i at (i + ½)/S as in LightSlab::textureCoords.
glm::vec4 window4DCoords(const LightSlab& slab, const glm::vec3& eye, float wu, float wv);

}  // namespace rg::lightfield
