// The PEM precompute, one viewpoint sample at a time (001 §3–4): segmented ray tracing,
// then the rendering matrix of every layer of every part on the emulated hardware and the
// least-squares inference of its map, all MIPMAP levels jointly.
//
// The inferred maps stay in "system memory" as RGBA8 texel arrays, as in the paper's
// viewer, and are downloaded into the profile's texture memory only for the samples a frame
// needs (uploadSample), so texture download is counted the way the paper experienced it.
#pragma once

#include <memory>
#include <vector>

#include "inference.h"
#include "pem_renderer.h"
#include "pem_scene.h"
#include "raycore/accel.h"
#include "raycore/image.h"
#include "rendering_matrix.h"

namespace rg::pem {

struct PemSettings {
    int views = 8;
    float stepDegrees = 4.0f;
    int emSize = 64;          // cap of the EM resolution (texture memory, 001 §4)
    int emProbeSize = 128;    // resolution of the probe that finds the finest level accessed
    int ptmSize = 128;        // the PTM atlas
    int width = 320, height = 240;
    int teapotLevel = 12;     // 32·level²·2 triangles (25 → 40,000, the paper's)
    int spp = 2;              // n×n samples per pixel in the ray tracer
    int viewerWidth = 640, viewerHeight = 480, viewerFrames = 10;
    int threads = 0;
    InferenceOptions inference;
};

// One layer map of one part, in the numbering of its TexelLayout.
struct MapTexels {
    TexelLayout layout;
    std::vector<Rgba8> texels;
};

struct PartMaps {
    MapTexels local, distant, infinite, ptm;
};

struct ViewSample {
    int view = -1;
    std::vector<PartMaps> parts;
    ray::Image groundTruth;   // RGB: the ray tracer's reflector (Σ segment composites)
    ray::Image coverage;      // 1 channel: fraction of samples on the reflector
    ray::PemLayerImages layers;  // empty when loaded from assets
    double raytraceSeconds = 0;
    double inferenceSeconds = 0;   // the PEM's maps: A (instrumented) + solves
    double inferenceCpuSeconds = 0;  // the same, CPU time of the process (user + system)
    double baselineSeconds = 0;    // the single-EM and PTM baselines' maps, when made
    bool hasBaselines() const { return !parts.empty() && !parts[0].ptm.texels.empty(); }
    std::vector<InferenceStats> stats;  // per part and layer, in solve order
};

// Ray traces the segmented layers of every part at `camera`.
ray::PemLayerImages traceLayers(const ray::Accel& accel, const PemScene& scene,
                                const ray::Camera& camera, const PemSettings& settings);
// Σ composites and Σ coverage of the layers (the reflector as the ray tracer sees it).
void groundTruthOf(const ray::PemLayerImages& layers, ray::Image& rgb, ray::Image& coverage);

// The full precompute of one viewpoint: trace, build A per layer (instrumented pass),
// infer. `emSize` is the resolution chosen for this PEM. `baselines` also infers the
// single sphere-at-infinity EM and the PTM of this view (only the evaluation needs them).
ViewSample precomputeView(const ray::Accel& accel, PemRenderer& renderer, int view,
                          const ray::Camera& camera, int emSize, const PemSettings& settings,
                          bool baselines);

// The static EM baseline (Figure 1c): a cube map ray traced from the object's EM origin
// with the object removed, box-filtered MIPMAPs, indexed by the reflection vector.
MapTexels traceStaticEm(const ray::Accel& accel, const PemScene& scene, int size,
                        const PemSettings& settings);

// Downloads maps into the renderer's texture memory.
// Only the maps `mode` reads: local + distant (Layered), the single EM as `distant`
// (SingleInfinite), the atlas (Ptm).
PemSample uploadSample(PemRenderer& renderer, const ViewSample& sample, EmMode mode);
std::shared_ptr<const tex::Texture> uploadMap(PemRenderer& renderer, const MapTexels& map);

}  // namespace rg::pem
