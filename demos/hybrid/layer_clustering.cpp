#include "layer_clustering.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.h"

namespace rg::hybrid {

std::vector<double> lbg1d(std::span<const float> values, int k, int* iterations) {
    if (k <= 0) throw Error("hybrid: LBG needs at least one cluster");
    if (values.empty()) throw Error("hybrid: LBG over no intersections");
    std::vector<float> sorted(values.begin(), values.end());
    std::sort(sorted.begin(), sorted.end());
    std::vector<double> c(static_cast<size_t>(k));
    for (int i = 0; i < k; ++i)
        c[size_t(i)] = sorted[std::min(sorted.size() - 1, size_t((i + 0.5) / k * double(sorted.size())))];
    // Centres ascending: the nearest one is found by the midpoints between neighbours.
    std::vector<int> assign(values.size(), -1);
    int it = 0;
    for (;; ++it) {
        std::sort(c.begin(), c.end());
        bool changed = false;
        std::vector<double> sum(size_t(k), 0.0);
        std::vector<int64_t> count(size_t(k), 0);
        for (size_t i = 0; i < values.size(); ++i) {
            const double v = values[i];
            int best = 0;
            for (int j = 1; j < k; ++j)
                if (std::abs(v - c[size_t(j)]) < std::abs(v - c[size_t(best)])) best = j;
            if (assign[i] != best) changed = true, assign[i] = best;
            sum[size_t(best)] += v;
            ++count[size_t(best)];
        }
        if (!changed || it >= 10000) break;
        for (int j = 0; j < k; ++j)
            if (count[size_t(j)]) c[size_t(j)] = sum[size_t(j)] / double(count[size_t(j)]);
    }
    if (iterations) *iterations = it + 1;
    return c;
}

LayerAssignment clusterLayers(std::span<const ClusterRecord> records, int k,
                              uint32_t objectCount) {
    LayerAssignment out;
    out.requested = k;
    std::vector<float> finite;
    finite.reserve(records.size());
    for (const ClusterRecord& r : records)
        if (r.object < objectCount && std::isfinite(r.distance)) finite.push_back(r.distance);
    if (finite.empty())
        throw Error("hybrid: no outgoing ray met the environment; nothing to cluster into layers");
    out.lbgCenters = lbg1d(finite, k, &out.iterations);
    const std::vector<double>& c = out.lbgCenters;
    auto nearest = [&](double v) {
        int best = 0;
        for (int j = 1; j < k; ++j)
            if (std::abs(v - c[size_t(j)]) < std::abs(v - c[size_t(best)])) best = j;
        return best;
    };
    // ---- whole objects: the cluster with most of the object's intersections ------------
    std::vector<std::vector<int64_t>> votes(objectCount, std::vector<int64_t>(size_t(k), 0));
    for (const ClusterRecord& r : records)
        if (r.object < objectCount && std::isfinite(r.distance))
            ++votes[r.object][size_t(nearest(r.distance))];
    std::vector<int> clusterOf(objectCount + 1, -1);
    std::vector<int64_t> clusterObjects(size_t(k), 0);
    for (uint32_t o = 0; o < objectCount; ++o) {
        const auto& v = votes[o];
        if (std::accumulate(v.begin(), v.end(), int64_t(0)) == 0) continue;
        clusterOf[o] = int(std::max_element(v.begin(), v.end()) - v.begin());
        ++clusterObjects[size_t(clusterOf[o])];
    }
    // Clusters that kept an object become layers, in order of their centres.
    std::vector<int> layerOfCluster(size_t(k), -1);
    int layers = 0;
    for (int j = 0; j < k; ++j)
        if (clusterObjects[size_t(j)] > 0) layerOfCluster[size_t(j)] = layers++;
    out.layers.resize(size_t(layers));
    out.layerOfObject.assign(objectCount + 1, -1);
    for (uint32_t o = 0; o < objectCount; ++o)
        if (clusterOf[o] >= 0) {
            const int l = layerOfCluster[size_t(clusterOf[o])];
            out.layerOfObject[o] = l;
            out.layers[size_t(l)].objects.push_back(o);
            out.layers[size_t(l)].lbgCenter = c[size_t(clusterOf[o])];
        }
    out.layerOfObject[objectCount] = layers - 1;  // the environment: outermost
    // ---- shell radius: mean distance, each ray's frontmost intersection per layer ------
    std::vector<double> sum(size_t(layers), 0.0);
    for (auto& L : out.layers) {
        L.minDistance = std::numeric_limits<float>::infinity();
        L.maxDistance = 0.0f;
    }
    std::vector<uint32_t> seenRay(size_t(layers), ~0u);
    for (const ClusterRecord& r : records) {
        if (r.object >= objectCount || !std::isfinite(r.distance)) continue;
        const int l = out.layerOfObject[r.object];
        if (l < 0) continue;
        LayerInfo& L = out.layers[size_t(l)];
        ++L.records;
        L.minDistance = std::min(L.minDistance, r.distance);
        L.maxDistance = std::max(L.maxDistance, r.distance);
        if (seenRay[size_t(l)] == r.ray) continue;  // behind this ray's frontmost one
        seenRay[size_t(l)] = r.ray;
        ++L.frontmost;
        sum[size_t(l)] += r.distance;
    }
    for (int l = 0; l < layers; ++l)
        out.layers[size_t(l)].radius = sum[size_t(l)] / double(std::max<int64_t>(1, out.layers[size_t(l)].frontmost));
    // Ascending radius (the LBG order already is, up to the whole-object moves).
    std::vector<int> order(static_cast<size_t>(layers));
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
        return out.layers[size_t(a)].radius < out.layers[size_t(b)].radius;
    });
    std::vector<LayerInfo> sorted;
    std::vector<int> newIndex(static_cast<size_t>(layers));
    for (int i = 0; i < layers; ++i) {
        sorted.push_back(out.layers[size_t(order[size_t(i)])]);
        newIndex[size_t(order[size_t(i)])] = i;
    }
    out.layers = std::move(sorted);
    for (int& l : out.layerOfObject)
        if (l >= 0) l = newIndex[size_t(l)];
    out.layerOfObject[objectCount] = layers - 1;
    return out;
}

}  // namespace rg::hybrid
