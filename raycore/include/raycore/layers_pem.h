// The segmented layers of 001 §3–4, per object (or object part): for each reflector the
// ray tracer separates
//   diffuse   – the view-independent part (and, for surfaces that are not reflectors,
//               their whole shading),
//   fresnel   – F, the Fresnel modulation at the first hit (Schlick or constant, as the
//               material says),
//   incident specular, split by where the first reflected ray goes:
//     local color / local alpha – it strikes the reflector itself again (self-
//               reflection): the radiance it brings, and the fraction of samples that did;
//     distant   – the ray continued *through* the reflector after the first bounce until
//               it reaches anything else, so every sample has a distant value and the
//               distant layer needs no alpha (001 §4, "Layered EMs").
// At a sample, the Whitted image is diffuse + F·(α_L·local + (1−α_L)·distant), which is
// how the PEM viewer recombines the layers (001 §4, "over" then modulate by F).
#pragma once

#include <string>
#include <vector>

#include "raycore/accel.h"
#include "raycore/image.h"
#include "raycore/render.h"

namespace rg::ray {

// A selectable piece of the scene: an object, or one part of its mesh.
struct Segment {
    uint32_t object = 0;
    int part = -1;  // -1: the whole object
    friend bool operator==(const Segment&, const Segment&) = default;
};
// "teapot" or "teapot/lid"; raises rg::Error for unknown names.
Segment findSegment(const Scene& scene, const std::string& name);
std::string segmentName(const Scene& scene, const Segment& s);

// Which hits count as "the reflector itself" for the local layer.
enum class LocalScope { Object, Part };

struct PemLayerOptions {
    LocalScope localScope = LocalScope::Object;
    int maxContinuation = 64;  // hits skipped on the reflector when continuing a ray
};

// The layers of one segment. Averages over the n×n samples of a pixel:
//   coverage  fraction of samples whose primary ray hits the segment      (1 channel)
//   diffuse   Σ diffuse over the segment's samples / n²  (premultiplied: summing the
//             diffuse layers of all segments gives the diffuse image)       (RGB)
//   fresnel   mean F over the segment's samples                            (RGB)
//   localAlpha  fraction of the segment's samples whose reflection is local (1 channel)
//   localColor  mean radiance over those samples                           (RGB)
//   distant   mean continued-ray radiance over the segment's samples       (RGB)
struct PemLayers {
    Segment segment;
    Image coverage, diffuse, fresnel, localColor, localAlpha, distant;
    // diffuse/coverage + fresnel·(α·local + (1−α)·distant), times coverage: the segment's
    // share of the image as the PEM viewer would recombine it.
    Image composite() const;
};

struct PemLayerImages {
    std::vector<PemLayers> segments;  // in the order asked
    Image segmentId;   // 1 channel: index into `segments` of the centre sample, −1 other
    Image background;  // premultiplied shading of samples outside every asked segment
};

PemLayerImages renderPemLayers(const Accel& accel, const Camera& camera,
                               const RenderOptions& options,
                               const std::vector<Segment>& segments,
                               const PemLayerOptions& layerOptions = {});

}  // namespace rg::ray
