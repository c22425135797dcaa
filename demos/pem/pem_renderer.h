// The PEM viewer's frame on the emulated hardware (001 §5, run-time on a GeForce 256 with
// two texture stages per pass). With D = distant EM, L = local EM (alpha α), F = Fresnel:
//
//   on the manifold (one viewpoint sample, 3 texture accesses → 2 passes)
//     pass 1  all triangles      stage 0 D (SELECTARG1)      stage 1 F (MODULATE)      → D·F
//     pass 2  off-hull triangles stage 0 L (SELECTARG1)      stage 1 F (MODULATE, α kept)
//             blended SRCALPHA/INVSRCALPHA                                   → F(αL + (1−α)D)
//   between two samples i, j with weight w of j (5 texture accesses → 3 passes)
//     pass 1  all triangles      stage 0 D_i                 stage 1 D_j (BLENDFACTORALPHA, TFACTOR α = w)
//     pass 2  off-hull triangles stage 0 L_i                 stage 1 L_j (BLENDFACTORALPHA), over
//     pass 3  all triangles      stage 0 F, blended DESTCOLOR·ZERO (modulates the framebuffer)
//
// Passes after the first test depth EQUAL without writing it, so every pass touches the
// same pixels. Triangles on the convex hull never draw the local layer (001 §4).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "em_texgen.h"
#include "pem_scene.h"
#include "rasterizer/device.h"
#include "raycore/camera.h"
#include "texunit/texture.h"

namespace rg::pem {

// One viewpoint sample's maps, per part (indices follow PemScene::parts).
struct PemSample {
    std::vector<std::shared_ptr<const tex::Texture>> local;    // RGBA8 cube, alpha = α_L
    std::vector<std::shared_ptr<const tex::Texture>> distant;  // RGBA8 cube
    std::vector<std::shared_ptr<const tex::Texture>> ptm;      // RGBA8 2D atlas (PTM)
};

// Which EMs index the reflector.
enum class EmMode {
    Layered,           // local ellipsoid over distant box (the paper's layered PEM)
    SingleInfinite,    // one EM per part, sphere at infinity (baseline of Figure 6)
    Static,            // one EM for the object rendered from its centre (Figure 1c)
    Ptm,               // parameterized texture maps: a texture on the surface per sample
};
const char* emModeName(EmMode mode);

struct FrameTiming {
    double texgenMs = 0, drawMs = 0;
    int reflectorPasses = 0;
};

glm::mat4 viewMatrix(const ray::Camera& camera);
glm::mat4 projectionMatrix(const ray::Camera& camera, int width, int height);

class PemRenderer {
  public:
    PemRenderer(raster::Device& device, const PemScene& scene);

    // The emulated frame: clears, then draws the reflector. `b` may be null (on the
    // manifold); otherwise the result blends a and b with weight w of b. For
    // SingleInfinite, the samples' `distant` maps hold the single EM and `local` is unused;
    // for Static, a.distant[0] is the object's static cube map, b must be null.
    FrameTiming render(const ray::Camera& camera, EmMode mode, const PemSample& a,
                       const PemSample* b = nullptr, float w = 0.0f);

    // Shared with the inference: per-part vertex arrays for the camera, with coordinate
    // sets 0 = distant (box, or infinite for SingleInfinite/Static), 1 = local, 2 = Fresnel,
    // 3 = the PTM atlas uv.
    const std::vector<raster::Vertex>& vertices(size_t part) const { return vertices_[part]; }
    const std::vector<uint32_t>& allIndices(size_t part) const { return all_[part]; }
    const std::vector<uint32_t>& offHullIndices(size_t part) const { return offHull_[part]; }
    // Generates coordinates for `camera` (timed in FrameTiming::texgenMs by render()).
    void prepare(const ray::Camera& camera, EmMode mode);
    void setCameraTransforms(const ray::Camera& camera);

    const std::shared_ptr<const tex::Texture>& fresnelTexture() const { return fresnel_; }
    tex::TextureMemory& memory() { return *memory_; }
    raster::Device& device() { return device_; }
    const PemScene& scene() const { return scene_; }
    static tex::SamplerState cubeSampler();
    static tex::SamplerState fresnelSampler();

  private:
    void drawAll(size_t part, bool offHullOnly);
    raster::Device& device_;
    const PemScene& scene_;
    std::shared_ptr<tex::TextureMemory> memory_;
    std::shared_ptr<const tex::Texture> fresnel_;
    std::vector<std::vector<raster::Vertex>> vertices_;
    std::vector<std::vector<uint32_t>> all_, offHull_;
    EmTexCoords coords_;
};

}  // namespace rg::pem
