// The nearest-codeword search of the VQ (demos/lightfield/vq.cpp, assign: Eigen products per
// chunk of 1024 blocks and tile of 128 codewords, a running minimum per block) against
//   - the former single product per chunk (MatrixF d = (−2·(X·Cᵀ)).rowwise() + ‖c‖², then
//     minCoeff per row), copied here: on float data the same labels, bit for bit the same
//     distances deciding them;
//   - brute force in double on integer data (the light field's bytes and the rounded
//     codebook: every distance exact in float too): the same labels, ties to the lowest index.
// Ties made on purpose: duplicated codewords, blocks equal to codewords, few distinct values,
// and (float data) blocks midway between two codewords, decided by rounding alone.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "vq.h"

namespace rg::lightfield {
namespace {

using MatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The former assign (before the tiles), one chunk after another.
std::vector<int> formerAssign(const std::vector<float>& x, int64_t rows, const std::vector<float>& c, int K, int D) {
    const MatrixF X = Eigen::Map<const MatrixF>(x.data(), rows, D);
    const MatrixF C = Eigen::Map<const MatrixF>(c.data(), K, D);
    const Eigen::VectorXf cn = C.rowwise().squaredNorm();
    std::vector<int> label(static_cast<size_t>(rows));
    constexpr int kChunk = 1024;
    for (int64_t a = 0; a < rows; a += kChunk) {
        const int n = int(std::min<int64_t>(kChunk, rows - a));
        MatrixF d = (-2.0f * (X.middleRows(a, n) * C.transpose())).rowwise() + cn.transpose();
        for (int i = 0; i < n; ++i) {
            Eigen::Index k;
            d.row(i).minCoeff(&k);
            label[size_t(a + i)] = int(k);
        }
    }
    return label;
}

// Brute force in double, strict < from codeword 0: the lowest index among equal distances.
std::vector<int> bruteForce(const std::vector<float>& x, int64_t rows, const std::vector<float>& c, int K, int D) {
    std::vector<int> label(static_cast<size_t>(rows));
    for (int64_t i = 0; i < rows; ++i) {
        double best = 0;
        int bestK = 0;
        for (int k = 0; k < K; ++k) {
            double s = 0;
            for (int d = 0; d < D; ++d) {
                const double e = double(x[size_t(i) * D + size_t(d)]) - double(c[size_t(k) * D + size_t(d)]);
                s += e * e;
            }
            if (k == 0 || s < best) {
                best = s;
                bestK = k;
            }
        }
        label[size_t(i)] = bestK;
    }
    return label;
}

struct Problem {
    int64_t rows;
    int K, D;
    std::vector<float> x, c;
};

// `levels` > 0: integer values 0..levels−1 (few levels: many exact ties); 0: floats in [0, 255).
// A quarter of the codewords duplicate earlier ones (later copies must never win) and every
// seventh block is a codeword.
Problem makeProblem(int64_t rows, int K, int D, int levels, uint32_t seed) {
    Problem p{rows, K, D, std::vector<float>(size_t(rows) * size_t(D)), std::vector<float>(size_t(K) * size_t(D))};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> real(0.0f, 255.0f);
    std::uniform_int_distribution<int> level(0, std::max(levels, 1) - 1);
    auto value = [&] { return levels > 0 ? float(level(rng)) : real(rng); };
    for (float& v : p.c) v = value();
    for (float& v : p.x) v = value();
    std::uniform_int_distribution<int> code(0, K - 1);
    for (int k = 1; k < K; ++k)
        if (rng() % 4 == 0) {
            const int from = code(rng) % k;
            std::copy_n(p.c.begin() + std::ptrdiff_t(from) * D, D, p.c.begin() + std::ptrdiff_t(k) * D);
        }
    for (int64_t i = 0; i < rows; i += 7) {
        const int from = code(rng);
        std::copy_n(p.c.begin() + std::ptrdiff_t(from) * D, D, p.x.begin() + std::ptrdiff_t(i) * D);
    }
    // Float data: every other block midway between two codewords, equally far from both but
    // for rounding, so the labels follow the order in which the products are summed.
    if (levels == 0)
        for (int64_t i = 1; i < rows; i += 2) {
            const int a = code(rng), b = code(rng);
            for (int d = 0; d < D; ++d)
                p.x[size_t(i) * D + size_t(d)] = 0.5f * (p.c[size_t(a) * D + size_t(d)] + p.c[size_t(b) * D + size_t(d)]);
        }
    return p;
}

// Sizes around the chunk (1024 blocks) and the tile (128 codewords, the last tile taking
// the remainder): one block, a few, a partial last chunk; K below, at and across tiles.
struct Size {
    int64_t rows;
    int K, D;
};
const Size kSizes[] = {{1, 300, 12},    {13, 257, 48},   {31, 129, 3},    {1030, 2, 48},   {1030, 128, 12},
                       {2053, 129, 48}, {2053, 255, 12}, {2500, 256, 48}, {3077, 383, 48}, {4099, 1000, 12}, {8192, 300, 48}, {8192, 260, 12}};

TEST(VqAssign, SameLabelsAsTheFormerProductOnFloatData) {
    for (const Size& s : kSizes) {
        const Problem p = makeProblem(s.rows, s.K, s.D, 0, uint32_t(s.rows * 31 + s.K));
        const std::vector<int> former = formerAssign(p.x, p.rows, p.c, p.K, p.D);
        for (int threads : {1, 2}) {
            const std::vector<int> fast = nearestCodewords(p.x.data(), p.rows, p.c.data(), p.K, p.D, threads);
            ASSERT_EQ(fast.size(), former.size());
            int64_t differ = 0;
            for (size_t i = 0; i < fast.size(); ++i) differ += fast[i] != former[i];
            EXPECT_EQ(differ, 0) << s.rows << " blocks, K " << s.K << ", " << s.D << " dims, " << threads << " threads";
        }
    }
}

TEST(VqAssign, NearestWithLowestIndexOnTiesOnIntegerData) {
    for (const Size& s : kSizes)
        for (int levels : {3, 256}) {
            const Problem p = makeProblem(s.rows, s.K, s.D, levels, uint32_t(s.rows * 17 + s.K + levels));
            const std::vector<int> truth = bruteForce(p.x, p.rows, p.c, p.K, p.D);
            const std::vector<int> fast = nearestCodewords(p.x.data(), p.rows, p.c.data(), p.K, p.D, 2);
            int64_t differ = 0;
            for (size_t i = 0; i < fast.size(); ++i) differ += fast[i] != truth[i];
            EXPECT_EQ(differ, 0) << s.rows << " blocks, K " << s.K << ", " << s.D << " dims, " << levels << " levels";
            // The former product agrees too (integer data: every distance exact in float).
            EXPECT_EQ(formerAssign(p.x, p.rows, p.c, p.K, p.D), truth);
        }
}

}  // namespace
}  // namespace rg::lightfield
