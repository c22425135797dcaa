// The layered-EM precompute of 000 §4, per lens object:
//
//   all viewpoints ─▶ outgoing-ray records (a coarse image per view, every front-facing
//     intersection along each exit ray) ─▶ LBG over their distances from the object's
//     centroid, whole objects per layer ─▶ shells (LensLayers), shared by every sample
//   each viewpoint sample (and, for disocclusion prevention, the views around it)
//     ─▶ records of the supersampled image, continued through occluders, the first hit of
//        each layer shaded ─▶ b_R, b_T per layer (premultiplied RGBA at display resolution)
//        and the confidence per term (000 §4.3, θc = 5°)
//     ─▶ A_R, A_T per layer: hybrid rendering of that layer alone at the view, the
//        instrumented pass over the 3×3-subsampled device
//     ─▶ per layer, every channel: least squares over both terms (and all views) at once,
//        all MIPMAP levels, conjugate gradient with pem's regulariser.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "direct_images.h"
#include "hybrid_renderer.h"
#include "inference.h"
#include "layer_clustering.h"
#include "lens_scene.h"
#include "raycore/camera.h"
#include "raycore/image.h"

namespace rg::hybrid {

struct PrecomputeSettings {
    int width = 240, height = 180;  // display
    int subsample = 2;              // n: n×n rays per pixel, device = display × n
    int clusterWidth = 80, clusterHeight = 60;  // the clustering pass (1 ray per pixel)
    int emSize = 64;
    int maxDepth = 8;
    int threads = 0;
    float tau = 3.0f;               // the tessellation A is rendered with
    pem::InferenceOptions inference;
};

// Which shell each layer gets: "auto" (the rule below), or a list of kinds, nearest
// layer first (the paper chose by hand: teapot quad, cylinder, sphere; cup spheres).
//   auto: the outermost layer is a sphere (it must hold every direction); an inner layer
//   whose frontmost intersections lie in one direction from the origin (mean resultant
//   length of their unit directions ≥ 0.6) is a quad ("sparsely occupied", 000 §4.2); an
//   inner layer all around the origin (≤ 0.3) made only of objects taller than wide is a
//   cylinder; otherwise a sphere.
struct ShellChoice {
    std::vector<ShellKind> kinds;  // empty: auto
};

// The records of the clustering pass of one lens object, over every view.
struct ClusterPass {
    std::vector<ClusterRecord> records;
    std::vector<glm::vec3> points;                 // per record: the intersection
    std::vector<glm::vec3> rayOrigins, rayDirs;    // per record: its outgoing ray
    int64_t samples = 0;                            // incoming rays that reached the object
};
ClusterPass clusterPass(const LensScene& scene, size_t lens, const std::vector<ray::Camera>& views,
                        const PrecomputeSettings& settings);
// Clusters into `k` layers and fits the shells.
LensLayers buildLayers(const LensScene& scene, size_t lens, const ClusterPass& pass, int k,
                       const ShellChoice& choice, int emSize);

// b images of one lens object at one view (000 §4.3): per term and layer, RGBA at display
// resolution, rgb premultiplied (the mean over the pixel's rays of the colour of the
// layer's first hit, 0 for rays missing the layer, each clipped to [0, 1]), alpha the
// fraction of the pixel's rays whose outgoing ray hit the layer. confidence per term:
// 1 − min(θm², θc²)/θc² over the pixel's exit directions, 0 unless every ray of the pixel
// reached the object with a valid path of that term.
struct LayerImages {
    std::vector<std::array<ray::Image, 2>> b;   // [layer][term]
    std::array<ray::Image, 2> confidence;
    ray::Image coverage;                         // rays reaching the object / rays
    int64_t records = 0, occludedRecords = 0, hits = 0;
    // With RecordOptions::collectPoints: per layer, the point each valid exit ray stands
    // for there (its first hit in the layer, else where it meets the shell; direct_images.h).
    std::vector<std::vector<glm::vec3>> points;
};
struct RecordOptions {
    bool incomingContinuation = true, outgoingContinuation = true;
    // 000 §4.3: direct images of the environment stacked with the lens object images
    // (direct_images.h); their confidence needs the records' points.
    bool directImages = false;
    DirectImageOptions direct{};
    bool collectPoints = false;
};
LayerImages layerImages(const LensScene& scene, size_t lens, const LensLayers& layers,
                        const ray::Camera& camera, const PrecomputeSettings& settings,
                        const RecordOptions& options);

// One inferred layer map (texels in the layout's numbering, premultiplied RGBA8).
struct LayerMap {
    pem::TexelLayout layout;
    std::vector<Rgba8> texels;
    double residual = 0;         // relative, confidence-weighted, mean over channels
    int64_t rows = 0, unconstrained = 0;  // texels no row reaches (finest level)
    int64_t directRows = 0;      // rows of the direct images (confidence > 0)
};

struct SampleSolution {
    int view = -1;
    std::vector<std::vector<LayerMap>> maps;      // [lens][layer]
    std::vector<LayerImages> images;               // [lens], at the sample's own camera
    double recordsS = 0, matrixS = 0, solveS = 0;
    int views = 0;                                 // viewpoints stacked per layer
    int directImages = 0;                          // direct images stacked (all objects)
    double directS = 0;                            // their tracing and matrices
};

// Infers every layer of every lens object at viewpoint sample `view` (camera views[0]),
// stacking the equations of every camera in `views` (000 §4.3 "Simultaneous Inference
// Over Multiple Viewpoints"; one camera: none), and with options.directImages the direct
// images of each object's environment (direct_images.h), their confidence from the
// records of every stacked view. `renderer` carries the layers and is re-prepared at each
// camera with τ = settings.tau.
SampleSolution inferSample(HybridRenderer& renderer, int view,
                           const std::vector<ray::Camera>& views,
                           const PrecomputeSettings& settings, const RecordOptions& options);

SampleMaps uploadSample(HybridRenderer& renderer, const SampleSolution& solution);

// 000 §4.3's shared distant layers: the outermost layer of every lens object after the
// first takes the first object's outermost shell (its origin and radius) and, at
// inference, joins that layer's stacked system — one map x over both objects' rows,
// uploaded once (uploadSample hands the same texture to both). Refused unless the shells
// are cube shells of one size.
void shareDistantLayers(std::vector<LensLayers>& layers);
// Why `layers` cannot share their outermost layer (shareDistantLayers would refuse them:
// for example one glass layer, which is a quad, not a cube shell); empty when they can.
std::string whyDistantLayersCannotBeShared(const std::vector<LensLayers>& layers);

}  // namespace rg::hybrid
