// Inference of a map from a rendering matrix (001 §4), on synthetic systems with a known
// answer.
#include <gtest/gtest.h>

#include <random>

#include "inference.h"

namespace rg::pem {
namespace {

TEST(TexelLayout, IndicesAreDenseAndOrderedByLevelFaceRowColumn) {
    TexelLayout L{8, 6};
    EXPECT_EQ(L.levels(), 4);
    EXPECT_EQ(L.count(), 6 * (64 + 16 + 4 + 1));
    EXPECT_EQ(L.index(0, 0, 0, 0), 0);
    EXPECT_EQ(L.index(0, 1, 0, 0), 64);
    EXPECT_EQ(L.index(1, 0, 0, 0), 6 * 64);
    EXPECT_EQ(L.index(3, 5, 0, 0), L.count() - 1);
    EXPECT_EQ(L.index(0, 2, 3, 1), 2 * 64 + 8 + 3);
}

// A "rendering" that samples level 0 of a 2D 16×16 map bilinearly at random points.
RenderingMatrix syntheticMatrix(int rows, uint32_t seed) {
    RenderingMatrix m;
    m.layout = TexelLayout{16, 1};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 15.0);
    std::vector<Eigen::Triplet<double>> t;
    for (int r = 0; r < rows; ++r) {
        double x = u(rng), y = u(rng);
        int x0 = int(x), y0 = int(y);
        double fx = x - x0, fy = y - y0;
        t.emplace_back(r, m.layout.index(0, 0, x0, y0), (1 - fx) * (1 - fy));
        t.emplace_back(r, m.layout.index(0, 0, x0 + 1, y0), fx * (1 - fy));
        t.emplace_back(r, m.layout.index(0, 0, x0, y0 + 1), (1 - fx) * fy);
        t.emplace_back(r, m.layout.index(0, 0, x0 + 1, y0 + 1), fx * fy);
        m.rowPixel.push_back(r);
    }
    m.A.resize(rows, m.layout.count());
    m.A.setFromTriplets(t.begin(), t.end());
    return m;
}

TEST(Inference, RecoversASmoothMapFromItsRendering) {
    RenderingMatrix m = syntheticMatrix(4000, 1);
    Eigen::VectorXd truth = Eigen::VectorXd::Zero(m.layout.count());
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) truth[m.layout.index(0, 0, x, y)] = 0.2 + 0.6 * (x + y) / 30.0;
    Eigen::VectorXd b = m.A * truth;
    InferenceOptions o;
    o.smoothness = 1e-6;
    o.levelCoupling = 0;
    o.maxIterations = 2000;
    o.tolerance = 1e-10;
    InferenceStats st;
    Eigen::VectorXd x = inferChannel(m, b, o, &st);
    for (int y = 0; y < 16; ++y)
        for (int xx = 0; xx < 16; ++xx)
            EXPECT_NEAR(x[m.layout.index(0, 0, xx, y)], truth[m.layout.index(0, 0, xx, y)], 2e-3)
                << "texel " << xx << "," << y;
    EXPECT_LT(st.residual, 1e-3);
    EXPECT_EQ(st.clampedTexels, 0);
}

TEST(Inference, KeepsTexelsInRangeWhenTheTargetIsTooBright) {
    RenderingMatrix m = syntheticMatrix(2000, 2);
    Eigen::VectorXd b = Eigen::VectorXd::Constant(m.A.rows(), 1.4);  // clipped highlight
    Eigen::VectorXd x = inferChannel(m, b, InferenceOptions{});
    EXPECT_LE(x.maxCoeff(), 1.0);
    EXPECT_GE(x.minCoeff(), 0.0);
    EXPECT_NEAR(x[m.layout.index(0, 0, 8, 8)], 1.0, 1e-9);
}

TEST(Inference, FillsTexelsNoPixelReachesFromTheirNeighbours) {
    // Only the left half of the map is rendered; the right half must be filled smoothly
    // (close to the left half's constant), not left at zero.
    RenderingMatrix m;
    m.layout = TexelLayout{8, 1};
    std::vector<Eigen::Triplet<double>> t;
    int r = 0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 4; ++x, ++r) {
            t.emplace_back(r, m.layout.index(0, 0, x, y), 1.0);
            m.rowPixel.push_back(r);
        }
    m.A.resize(r, m.layout.count());
    m.A.setFromTriplets(t.begin(), t.end());
    Eigen::VectorXd b = Eigen::VectorXd::Constant(r, 0.7);
    Eigen::VectorXd x = inferChannel(m, b, InferenceOptions{});
    for (int y = 0; y < 8; ++y) EXPECT_NEAR(x[m.layout.index(0, 0, 7, y)], 0.7, 0.02);
}

TEST(Inference, RefusesMismatchedSizes) {
    RenderingMatrix m = syntheticMatrix(10, 3);
    EXPECT_THROW(inferChannel(m, Eigen::VectorXd::Zero(5), InferenceOptions{}), std::exception);
}

}  // namespace
}  // namespace rg::pem
