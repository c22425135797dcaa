// 000 §4.2 "Building Layered EM Geometry": the layers of a lens object's EM found by the
// LBG algorithm (Linde, Buzo & Gray 1980) on the distances from the object's centroid of
// every recorded intersection of its outgoing rays, over all viewpoints at once.
//
//   1. LBG in one dimension: initial cluster distances, each intersection to the closest,
//      the means recomputed, until no intersection is reassigned.
//   2. Whole objects: each object goes to the single cluster holding most of its
//      intersections (parts of one object never tear across layers).
//   3. Each layer's shell sits at the mean distance of its intersections, an outgoing ray
//      continued through several of its objects counting only its frontmost one.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace rg::hybrid {

// One intersection of an outgoing ray with the environment. Records of one ray are
// contiguous, nearest first. object == objectCount stands for the environment at
// infinity (a ray that met nothing): it joins the outermost layer and no mean.
struct ClusterRecord {
    float distance = 0;
    uint32_t object = 0;
    uint32_t ray = 0;
};

// 1D LBG: cluster centres ascending. Initial centres: the values' quantiles at
// (i + ½)/k (deterministic where the paper starts from random ones); an emptied cluster
// keeps its centre. `iterations` counts assignment rounds up to the one with no change.
std::vector<double> lbg1d(std::span<const float> values, int k, int* iterations = nullptr);

struct LayerInfo {
    double radius = 0;           // mean frontmost distance (the shell's)
    double lbgCenter = 0;        // the LBG cluster it came from
    std::vector<uint32_t> objects;
    int64_t records = 0;         // intersections of its objects
    int64_t frontmost = 0;       // of which frontmost on their ray within the layer
    float minDistance = 0, maxDistance = 0;
};

struct LayerAssignment {
    int requested = 0;
    std::vector<double> lbgCenters;
    int iterations = 0;
    std::vector<int> layerOfObject;   // objectCount + 1 entries (the last: the environment);
                                      // −1 for objects never recorded
    std::vector<LayerInfo> layers;    // ascending radius; clusters left without a whole
                                      // object are dropped
};

LayerAssignment clusterLayers(std::span<const ClusterRecord> records, int k,
                              uint32_t objectCount);

}  // namespace rg::hybrid
