// 000 §5 "Multipass Rendering with Layered EM Indexing" on the emulated GeForce 256
// (Direct3D 7, two texture stages per pass), every frame from the actual viewpoint:
//
//   prepare:  per lens object, adaptive tessellation (vertex paths traced through the
//             object alone) ─▶ texture generation: per vertex, term and layer the exit ray
//             meets the layer's shell; (hit − EM origin) is the cube index, (s, t) on a
//             quad; F·G per term into the vertex's diffuse colour
//   draw:     per lens object and term (reflection, then refraction), per viewpoint sample
//             (one on a sample, the two nearest between samples), its layers front to
//             back, one layer per pass:
//                stage 0  COLOR = MODULATE(TEXTURE, DIFFUSE)   ALPHA = SELECTARG1(TEXTURE)
//                stage 1  COLOR = MODULATE(CURRENT, TFACTOR)   (TFACTOR.rgb = the sample's
//                         weight; only when blending two samples)
//                blend    SRC = INVDESTALPHA, DST = ONE: C += (1 − A)·c, A += (1 − A)·a,
//                         "L1 over L2 over … Ln" front to back with premultiplied texels
//             each (term, sample) sequence after the first starts with the alpha-clear
//             polygon: a screen quad blended ZERO, SRCCOLOR with diffuse (255, 255, 255, 0)
//             — rgb × 1, alpha × 0 (000 §5) — so its layers sum onto what is there.
//             The object's very first pass lays depth (LESSEQUAL, write) and replaces the
//             colour (blending off: the same as "under" from 0, and it lets a nearer lens
//             object cover a farther one); every later pass tests depth EQUAL.
//   counts:   4n passes between two samples (2n on a sample) for a two-term object of n
//             layers, 2n (n) for a mirror; alpha clears 3 (1) and 1 (0).
//
// On a profile with four stages (geforce3, 000 §5's forecast) the two samples are lerped
// inside a pass instead: stage 0 the layer texel of sample a, stage 1
// BLENDFACTORALPHA(texel of b, CURRENT) with TFACTOR.a = the weight of b, stage 2
// MODULATE(CURRENT, DIFFUSE): one pass per (term, layer), 2n between samples as on one,
// one alpha clear for a glass object. The paper's "n passes and no clear" would put both
// terms in one pass, but each term's layers composite "under" their own running alpha and
// a pass has one destination alpha: two stacks cannot share it, so 2n + 1 is the exact
// count (a geforce8800 could do all in one pass with up to 4n ≤ 16 textures).
//
// The device is display × subsample along each axis (000 §6: 3×3 subsamples); the frame
// is box-filtered to the display after read-back, counted in "other".
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "adaptive_tessellation.h"
#include "inference.h"
#include "layer_clustering.h"
#include "lens_scene.h"
#include "rasterizer/device.h"
#include "raycore/camera.h"
#include "raycore/image.h"
#include "rendering_matrix.h"
#include "shells.h"
#include "texunit/texture.h"

namespace rg::hybrid {

// A lens object's layered-EM geometry, shared by every viewpoint sample (000 §4.2:
// clustered over all viewpoints at once).
struct LensLayers {
    LayerAssignment assignment;
    std::vector<Shell> shells;    // per layer, nearest first
    int emSize = 64;              // cube face edge; a quad's 2D texture has twice the edge
                                  // (2/3 of a cube's texels: the memory the impostor saves)
    // 000 §4.3: "To conserve texture memory, it is beneficial to share more distant EM
    // layers between local lens objects ... add more equations to the linear system (1)
    // corresponding to multiple lens objects and simultaneously solving for a single EM x."
    // When set, layer `sharedLayer` (the outermost) uses the shell and the map of
    // (sharedLens, sharedOwnerLayer): one map, inferred over both objects' rows, resident once.
    int sharedLayer = -1;
    size_t sharedLens = 0;
    int sharedOwnerLayer = -1;
    bool shares(int layer) const { return layer == sharedLayer && sharedOwnerLayer >= 0; }
    pem::TexelLayout layout(int layer) const {
        const bool cube = shells.at(size_t(layer)).cube();
        return {cube ? emSize : 2 * emSize, cube ? 6 : 1};
    }
    int layers() const { return int(shells.size()); }
};

// One viewpoint sample's maps on the device: maps[lens][layer], RGBA8, premultiplied
// (rgb = α·colour), every MIPMAP level.
struct SampleMaps {
    int view = -1;
    std::vector<std::vector<std::shared_ptr<const tex::Texture>>> maps;
};

// The four rows of 000 §6's table, one frame.
struct FrameTimes {
    double vertexRaysS = 0;     // ray tracing at vertices
    double texgenS = 0;         // texture coordinate generation
    double tessellationS = 0;   // subdivision decisions, edge hash, t-junction removal
    double drawS = 0;           // the emulated device's passes
    double downsampleS = 0;     // read-back and box filter to the display
    double otherS() const { return drawS + downsampleS; }
    double totalS() const { return vertexRaysS + texgenS + tessellationS + otherS(); }
};

struct FrameCounts {
    ray::RayCounts rays;
    int64_t verticesTraced = 0, trianglesOut = 0;
    int layerPasses = 0, alphaClears = 0;   // geometry passes of the layers; clear polygons
    int maxLevel = 0;
};

class HybridRenderer {
  public:
    HybridRenderer(raster::Device& device, std::shared_ptr<tex::TextureMemory> memory,
                   LensScene& scene, std::vector<LensLayers> layers, int subsample,
                   TessellationSettings tessellation);

    // Every frame: tessellate and generate coordinates for `camera`. `counting` traces
    // with the counting twins instead (for 000 §6's triangle tests, never timed).
    void prepare(const ray::Camera& camera, bool counting = false);
    // The passes for a (alone), or a and b blended with weight wB of b (1 − wB of a).
    void draw(const SampleMaps& a, const SampleMaps* b = nullptr, float wB = 0.0f);
    // prepare + draw + downsample, timed.
    FrameTimes render(const ray::Camera& camera, const SampleMaps& a, const SampleMaps* b = nullptr,
                      float wB = 0.0f);

    // The last frame box-filtered to the display (rgb), and the fraction of each display
    // pixel's subpixels a lens object covers (depth written).
    ray::Image displayImage(ray::Image* coverage = nullptr) const;
    // Figure 5: the prepared meshes drawn flat, darker with each subdivision level.
    void drawLevels();

    // The rendering of one layer of one term alone at the prepared camera, for the
    // rendering matrix (000 §4.3: A_R, A_T are hybrid rendering with an initial
    // reflection or refraction).
    pem::IsolatingRendering isolating(size_t lens, int term, int layer);
    std::shared_ptr<const tex::Texture> uploadMap(size_t lens, int layer,
                                                  const std::vector<Rgba8>& texels);

    const FrameCounts& counts() const { return counts_; }
    const AdaptiveMesh& mesh(size_t lens) const { return meshes_.at(lens); }
    const LensLayers& layers(size_t lens) const { return layers_.at(lens); }
    const std::vector<LensLayers>& allLayers() const { return layers_; }
    LensScene& scene() { return scene_; }
    raster::Device& device() { return device_; }
    tex::TextureMemory& memory() { return *memory_; }
    int subsample() const { return subsample_; }
    const ray::Camera& camera() const { return camera_; }
    TessellationSettings& tessellation() { return tess_; }
    double lastTexgenSeconds() const { return texgenS_; }

    // Four stages: lerp the two samples inside a pass (above); two: a pass per sample.
    bool lerpsInPass() const { return lerpInPass_; }
    static tex::SamplerState layerSampler();
    // Texture bytes of one sample's maps (every object and layer, all levels).
    static uint64_t sampleBytes(const std::vector<LensLayers>& layers);

  private:
    void setCamera();
    raster::Device& device_;
    std::shared_ptr<tex::TextureMemory> memory_;
    LensScene& scene_;
    std::vector<LensLayers> layers_;
    int subsample_;
    TessellationSettings tess_;
    ray::Camera camera_;
    std::vector<AdaptiveMesh> meshes_;
    std::vector<std::vector<raster::Vertex>> vertices_;   // per lens: the used vertices
    std::vector<std::vector<uint32_t>> indices_, used_;   // into vertices_; mesh vertex of each
    std::vector<std::array<std::vector<Rgba8>, 2>> fg_;  // per lens, term: F·G per vertex
    FrameCounts counts_;
    double texgenS_ = 0;
    bool lerpInPass_ = false;
};

// 000 §5's alpha clear: a pretransformed polygon over the whole target, depth off, blended
// src·ZERO + dst·SRCCOLOR with src = (255, 255, 255, 0): rgb × 255/255 (exactly rgb:
// mulDiv255(x, 255) = x) and alpha × 0. One pass labelled `label`.
void drawAlphaClear(raster::Device& device, const std::string& label);

// The frame's camera on the device (pem's conventions: Direct3D clip, the ray tracer's
// field of view).
glm::mat4 viewProjection(const ray::Camera& camera, int width, int height);

}  // namespace rg::hybrid
