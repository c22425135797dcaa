// 000 §4.3's second way to fill the parts of a layered EM the lens object does not image
// from the viewpoint sample: direct images of the environment.
//
//   "An alternative method to fill in the missing portions in the environment map is to
//    infer it using extra rays in addition to the ones that exit the lens object. These
//    additional rays can be taken from the object center as in traditional environment
//    maps. They can also be taken from the viewpoint, but looking directly at the
//    environment (i.e., without the lens object) ... Direct images from the lens object
//    center tend to work better for reflective objects while direct images from the
//    viewpoint are better suited for refractive (transparent) objects."
//
//   "... solve simultaneously across images of the lens object from the viewpoint as before
//    (lens object images), combined with direct images of the environment without the lens
//    object (direct images). In these direct images, per-pixel confidence is computed as a
//    function of the likelihood that the pixel represents a missing portion of the
//    environment. We compute this via distance of the direct image ray's intersection with
//    its closest point in the intersection records of the lens object images."
//
// Per lens object, layer and direct camera:
//   b      every front-facing hit along each camera ray except on the lens object itself,
//          the first of each layer shaded (as the lens images' records, 000 §4.1), RGBA
//          premultiplied at display resolution, n×n rays per pixel;
//   c      per ray, the distance d from its point in the layer (the layer's first hit, or
//          where it meets the layer's shell when it hits nothing of the layer) to the
//          nearest such point of the lens images' records, mapped by directConfidence;
//          the pixel's mean; 0 where a ray meets a quad only by 000 §4.2's forced
//          intersection or outside its rectangle (it says nothing about the texture there:
//          the sampler would clamp it onto the edge texels);
//   A      the layer's shell itself seen from the camera: a screen grid whose vertices
//          carry the shell coordinate of their camera ray, drawn with the layer's sampler
//          on the same 3×3-subsampled device, taps read by the instrumented pass.
// The blocks join the layer's stacked system (pem::InferenceSystem) with the lens images'.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

#include "hybrid_renderer.h"
#include "lens_scene.h"
#include "raycore/camera.h"
#include "raycore/image.h"
#include "rendering_matrix.h"
#include "shells.h"

namespace rg::hybrid {

struct PrecomputeSettings;

// Where a lens object's direct images look from (000 §4.3).
enum class DirectSource {
    Auto,       // the paper's advice: the viewpoint for glass, the centre for a mirror
    Viewpoint,  // one image from the viewpoint sample, its camera
    Center,     // six 90° images from the EM origin (a cube of views, as a traditional EM)
};

struct DirectImageOptions {
    DirectSource source = DirectSource::Auto;
    // [D] c = min(1, d / d0), d0 = this many texels of the layer's finest level at the
    // layer's distance: a direct ray within a few texels of a record point adds little the
    // lens images do not already say; one farther off is a missing portion.
    float confidenceTexels = 4.0f;
};

// The cameras of a lens object's direct images: the sample's own camera (Viewpoint), or
// six at the EM origin (Center: four around the vertical at the device's aspect and a 90°
// vertical field of view, one up, one down).
std::vector<ray::Camera> directCameras(const LensObject& lens, DirectSource source,
                                       const ray::Camera& sample);
DirectSource resolveDirectSource(const LensObject& lens, DirectSource source);

// d0 of directConfidence for one layer: `texels` texels of the finest level at the shell's
// distance from the EM origin (a cube face spans 90° over emSize texels; a quad's texture
// 2·emSize texels across its rectangle).
float directConfidenceScale(const Shell& shell, int emSize, float texels);
// [D] min(1, d / d0): 0 on a record point, 1 at d0 and beyond.
float directConfidence(float distance, float d0);

// The records' points of one layer, bucketed on a grid of cell d0: nearest(p) is the
// distance to the closest point, capped at d0 (all a confidence needs).
class RecordPoints {
  public:
    explicit RecordPoints(float cell = 1.0f);
    void add(const glm::vec3& p);
    float nearest(const glm::vec3& p) const;  // min(d0, distance to the closest point)
    size_t size() const { return count_; }
    float cell() const { return cell_; }

  private:
    int64_t key(int x, int y, int z) const;
    float cell_;
    size_t count_ = 0;
    std::unordered_map<int64_t, std::vector<glm::vec3>> cells_;
};

// The point a ray stands for in a layer: its first hit there (finite t), else where it
// meets the layer's shell; false for a forced quad intersection (no point).
bool layerPoint(const Shell& shell, const glm::vec3& origin, const glm::vec3& dir,
                bool hit, const glm::vec3& hitPoint, glm::vec3& out);

// One direct image of a lens object's environment: b and c per layer (display resolution).
struct DirectImage {
    ray::Camera camera;
    std::vector<ray::Image> b;           // [layer] RGBA, rgb premultiplied
    std::vector<ray::Image> confidence;  // [layer] 1 channel
};
DirectImage traceDirectImage(const LensScene& scene, size_t lens, const LensLayers& layers,
                             const ray::Camera& camera, const PrecomputeSettings& settings,
                             const std::vector<RecordPoints>& records,
                             const DirectImageOptions& options);

// The layer's shell seen from `camera` on `device` (display × subsample), sampled as the
// frame samples the layer: the direct block's rendering matrix through
// pem::buildMatrixByInstrumentedPass.
pem::IsolatingRendering directIsolating(raster::Device& device, const ray::Camera& camera,
                                        const Shell& shell, const pem::TexelLayout& layout,
                                        int subsample);

}  // namespace rg::hybrid
