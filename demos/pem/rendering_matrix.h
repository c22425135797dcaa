// Building the rendering matrix A (001 §4 "EM Inference") two ways that must agree:
//
//  (a) the paper's way — test renderings on the emulated hardware that isolate texel
//      contributions. Per MIPMAP level ℓ: one identification rendering with nearest
//      filtering forced to ℓ whose texels encode (face, x, y), then 9 renderings in which
//      only texels with (x mod 3, y mod 3) = (px, py) on level ℓ are white. A bilinear
//      footprint spans two texels per axis, so at most one lit texel reaches a pixel, and
//      the identification rendering tells which: the lit one among x_n − 1, x_n, x_n + 1.
//      The pixel's 8-bit value / 255 is the texel's weight. 10 renderings per level.
//  (b) an instrumented pass of the rasterizer: the device reports every fragment that
//      passed the depth test, and the texture unit lists the taps (level, face, x, y,
//      weight) it read — the same code as the sampler, with exact weights.
//
// (a) is quantized to 8 bits, so the two agree to within 1/255 per entry.
//
// Both are written once for any layer of any demo (IsolatingRendering: how to draw the
// layer alone, its texel layout, and how many device pixels make a display pixel); the
// PEM's own layers and hybrid's layered EMs (000 §4.3, rendered 3×3 supersampled) use it.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "inference.h"
#include "pem_renderer.h"

namespace rg::pem {

enum class EmLayer { Local, Distant, Infinite, Ptm };
const char* emLayerName(EmLayer layer);

struct MatrixBuildStats {
    int renderings = 0;
    double seconds = 0;
};

// The texel layout of a layer's map: a cube of `baseSize` (a 2D atlas for the PTM).
TexelLayout layoutFor(EmLayer layer, int baseSize);

// An RGBA8 map of `layout` (cube, or 2D for one face) with every level uploaded, texel i
// of the layout's numbering = texel(i).
std::shared_ptr<tex::Texture> makeMapFromTexels(tex::TextureMemory& memory,
                                                const TexelLayout& layout,
                                                const std::function<Rgba8(int64_t)>& texel);

// One layer drawn alone on `device`: render(texture, sampler) draws a frame whose first
// pass lays the object's depth and whose later passes draw the layer's triangles with
// stage 0 = SELECTARG1(TEXTURE) (colour and alpha) reading `texture` through `sampler`.
// The device's framebuffer is `subsample`× the display along each axis: a display pixel's
// row averages its subsample² device pixels (each tap weighs 1/subsample²), so A models a
// supersampled frame box-filtered to the display (000 §6: 3×3 subsamples).
struct IsolatingRendering {
    TexelLayout layout;
    int subsample = 1;
    tex::SamplerState sampler;  // the frame's sampler (trilinear, clamped)
    std::function<void(const std::shared_ptr<const tex::Texture>&, const tex::SamplerState&)>
        render;
};
RenderingMatrix buildMatrixByTestRenderings(raster::Device& device, tex::TextureMemory& memory,
                                            const IsolatingRendering& rendering,
                                            MatrixBuildStats* stats = nullptr);
RenderingMatrix buildMatrixByInstrumentedPass(raster::Device& device,
                                              tex::TextureMemory& memory,
                                              const IsolatingRendering& rendering,
                                              MatrixBuildStats* stats = nullptr);

// The PEM's layers through the same builders.
RenderingMatrix buildMatrixByTestRenderings(raster::Device& device, PemRenderer& renderer,
                                            const ray::Camera& camera, size_t part, EmLayer layer,
                                            int baseSize, MatrixBuildStats* stats = nullptr);

RenderingMatrix buildMatrixByInstrumentedPass(raster::Device& device, PemRenderer& renderer,
                                              const ray::Camera& camera, size_t part,
                                              EmLayer layer, int baseSize,
                                              MatrixBuildStats* stats = nullptr);

// Largest |A_a − A_b| over the union of both patterns, and the count of entries present
// in one but not the other with weight above `ignoreBelow`.
struct MatrixAgreement {
    double maxAbsDifference = 0;
    int64_t rowsA = 0, rowsB = 0, nonZerosA = 0, nonZerosB = 0, unmatched = 0;
    bool sameRows = false;
};
MatrixAgreement compareMatrices(const RenderingMatrix& a, const RenderingMatrix& b,
                                double ignoreBelow);

}  // namespace rg::pem
