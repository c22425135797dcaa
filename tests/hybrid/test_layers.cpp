// 000 §4.2: LBG on known one-dimensional sets, the whole-object rule, and the shell radius
// from each ray's frontmost intersection per layer.
#include <gtest/gtest.h>

#include "core/error.h"

#include <cmath>
#include <limits>

#include "layer_clustering.h"

namespace rg::hybrid {
namespace {

TEST(Lbg, FindsThreeWellSeparatedClustersAndStopsWhenNothingMoves) {
    std::vector<float> v;
    double mean[3] = {0, 0, 0};
    for (int i = 0; i < 99; ++i) v.push_back(2.0f + 0.01f * float(i % 11 - 5));
    for (int i = 0; i < 294; ++i) v.push_back(10.0f + 0.02f * float(i % 21 - 10));
    for (int i = 0; i < 50; ++i) v.push_back(25.0f + 0.1f * float(i % 5 - 2));
    for (size_t i = 0; i < v.size(); ++i) mean[i < 99 ? 0 : i < 393 ? 1 : 2] += v[i];
    mean[0] /= 99, mean[1] /= 294, mean[2] /= 50;
    int it = 0;
    const std::vector<double> c = lbg1d(v, 3, &it);
    ASSERT_EQ(c.size(), 3u);
    EXPECT_NEAR(c[0], mean[0], 1e-9);
    EXPECT_NEAR(c[1], mean[1], 1e-9);
    EXPECT_NEAR(c[2], mean[2], 1e-9);
    EXPECT_NEAR(c[1], 10.0, 1e-4);
    EXPECT_GE(it, 1);
    EXPECT_LT(it, 20);
}

TEST(Lbg, OneClusterIsTheMeanAndBadInputIsRefused) {
    const std::vector<float> v = {1, 2, 3, 10};
    EXPECT_NEAR(lbg1d(v, 1)[0], 4.0, 1e-12);
    EXPECT_THROW(lbg1d(v, 0), Error);
    EXPECT_THROW(lbg1d(std::vector<float>{}, 2), Error);
}

TEST(Lbg, ReassignsUntilStable) {
    // Quantile starts at 1 and 3 (the 25% and 75% points); the stable answer separates
    // {0, 1, 2} from {10}: the means must move and the points be reassigned.
    const std::vector<float> v = {0, 1, 2, 10};
    int it = 0;
    const std::vector<double> c = lbg1d(v, 2, &it);
    EXPECT_NEAR(c[0], 1.0, 1e-12);
    EXPECT_NEAR(c[1], 10.0, 1e-12);
    EXPECT_GE(it, 2);
}

ClusterRecord rec(float d, uint32_t object, uint32_t ray) { return {d, object, ray}; }

TEST(ClusterLayers, WholeObjectsGoToTheClusterHoldingMostOfTheirRecords) {
    // Object 0 (a floor): 60 records near 2, 40 near 10. Object 1 (columns): 100 near 10.
    // Object 2 (walls): 50 near 25. LBG splits object 0 across two clusters; the rule puts
    // it whole where most of it is.
    std::vector<ClusterRecord> r;
    uint32_t ray = 0;
    for (int i = 0; i < 60; ++i) r.push_back(rec(2.0f + 0.01f * float(i % 3), 0, ray++));
    for (int i = 0; i < 40; ++i) r.push_back(rec(10.0f, 0, ray++));
    for (int i = 0; i < 100; ++i) r.push_back(rec(10.0f + 0.01f * float(i % 3), 1, ray++));
    for (int i = 0; i < 50; ++i) r.push_back(rec(25.0f, 2, ray++));
    r.push_back(rec(std::numeric_limits<float>::infinity(), 3, ray++));  // the environment
    const LayerAssignment a = clusterLayers(r, 3, 3);
    ASSERT_EQ(a.layers.size(), 3u);
    EXPECT_EQ(a.layerOfObject[0], 0);
    EXPECT_EQ(a.layerOfObject[1], 1);
    EXPECT_EQ(a.layerOfObject[2], 2);
    EXPECT_EQ(a.layerOfObject[3], 2) << "the environment joins the outermost layer";
    EXPECT_EQ(a.layers[0].objects, std::vector<uint32_t>{0});
    // Layer 0's shell: the mean over all of object 0's records (each on its own ray).
    EXPECT_NEAR(a.layers[0].radius, (60 * 2.01 + 40 * 10.0) / 100.0, 1e-3);
    EXPECT_EQ(a.layers[0].records, 100);
}

TEST(ClusterLayers, AContinuedRayCountsOnlyItsFrontmostIntersectionPerLayer) {
    // One ray meets column A at 9 and, continued, column B at 11 (both layer 1); another
    // ray meets only B at 12. Radius = mean(9, 12), not mean(9, 11, 12).
    std::vector<ClusterRecord> r = {rec(2, 0, 0), rec(9, 1, 1), rec(11, 2, 1), rec(12, 2, 2),
                                    rec(30, 3, 3)};
    const LayerAssignment a = clusterLayers(r, 3, 4);
    ASSERT_EQ(a.layers.size(), 3u);
    EXPECT_EQ(a.layerOfObject[1], a.layerOfObject[2]);
    const LayerInfo& L = a.layers[size_t(a.layerOfObject[1])];
    EXPECT_NEAR(L.radius, 10.5, 1e-9);
    EXPECT_EQ(L.frontmost, 2);
    EXPECT_EQ(L.records, 3);
}

TEST(ClusterLayers, AClusterLeftWithoutAWholeObjectIsDropped) {
    // Two objects, three clusters asked: the middle cluster gets records but no object.
    std::vector<ClusterRecord> r;
    uint32_t ray = 0;
    for (int i = 0; i < 10; ++i) r.push_back(rec(1.0f, 0, ray++));
    for (int i = 0; i < 4; ++i) r.push_back(rec(5.0f, 0, ray++));
    for (int i = 0; i < 10; ++i) r.push_back(rec(20.0f, 1, ray++));
    const LayerAssignment a = clusterLayers(r, 3, 2);
    EXPECT_EQ(a.layers.size(), 2u);
    EXPECT_EQ(a.requested, 3);
    EXPECT_LT(a.layers[0].radius, a.layers[1].radius);
}

TEST(ClusterLayers, NothingToClusterIsAnError) {
    std::vector<ClusterRecord> r = {rec(std::numeric_limits<float>::infinity(), 2, 0)};
    EXPECT_THROW(clusterLayers(r, 2, 2), Error);
}

}  // namespace
}  // namespace rg::hybrid
