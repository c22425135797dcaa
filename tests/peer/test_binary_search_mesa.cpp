// The binary_search workload (bench/binary_search_workload.h): its scalar reference
// against hand-computed values, and Mesa llvmpipe's GLSL version against the reference.
//   BinarySearchReference  the depth image, texel selection, convergence on flat depth
//   BinarySearchMesa       llvmpipe's 512×512 frame against referenceImage()
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench/binary_search_mesa.h"
#include "bench/binary_search_workload.h"

namespace rg::bench::binary_search {
namespace {

// ---- the reference -----------------------------------------------------------------

// D[j][i] = float(0.5 + 0.25·sin(0.05·i)·cos(0.07·j)); the expected floats were computed
// apart (Python, double then struct-packed to binary32). (10, 20) against (20, 10)
// catches a swapped row/column.
TEST(BinarySearchReference, DepthImageFormula) {
    const std::vector<float> d = depthImage();
    ASSERT_EQ(d.size(), size_t(kDepthSize) * kDepthSize);
    auto at = [&](int i, int j) { return d[size_t(j) * kDepthSize + size_t(i)]; };
    for (int j = 0; j < kDepthSize; ++j)
        EXPECT_EQ(at(0, j), 0.5f) << "sin(0) = 0, row " << j;
    EXPECT_EQ(at(31, 0), 0x1.7ff8eap-1f);
    EXPECT_EQ(at(10, 20), 0x1.0a6e28p-1f);
    EXPECT_EQ(at(100, 300), 0x1.433ac4p-1f);
    EXPECT_EQ(at(511, 511), 0x1.db9de2p-2f);
    for (float v : d) {
        EXPECT_GE(v, 0.25f);
        EXPECT_LE(v, 0.75f);
    }
}

// floor(c·512) mod 512 at and around texel boundaries, including the wrap.
TEST(BinarySearchReference, NearestRepeatTexel) {
    EXPECT_EQ(nearestRepeat(0.0f, 512), 0);
    EXPECT_EQ(nearestRepeat(1.0f / 512, 512), 1);
    EXPECT_EQ(nearestRepeat(std::nextafter(1.0f / 512, 0.0f), 512), 0);
    EXPECT_EQ(nearestRepeat(511.5f / 512, 512), 511);
    EXPECT_EQ(nearestRepeat(1.0f, 512), 0);
    EXPECT_EQ(nearestRepeat(1.125f, 512), 64);
    EXPECT_EQ(nearestRepeat(-0.5f / 512, 512), 511);
}

// Flat depth c: the search brackets c between multiples of 1/256, so t = (⌊256c⌋ + ½)/256
// for every fragment, d = c; c = 0.5 is hit exactly by the first mid, where `p.z > d`
// is false and the search goes up.
TEST(BinarySearchReference, FlatDepthConverges) {
    for (float c : {0.3f, 0.5f, 0.7f, 0.01f}) {
        const std::vector<float> flat(size_t(kDepthSize) * kDepthSize, c);
        const float expected = (std::floor(c * 256.0f) + 0.5f) / 256.0f;
        for (float u : {pixelCentre(0, kWidth), pixelCentre(300, kWidth),
                        pixelCentre(511, kWidth)}) {
            const Hit h = shadeFragment(flat.data(), u, pixelCentre(7, kHeight));
            EXPECT_EQ(h.t, expected) << "c = " << c << ", u = " << u;
            EXPECT_EQ(h.d, c);
        }
    }
    const std::vector<float> half(size_t(kDepthSize) * kDepthSize, 0.5f);
    EXPECT_EQ(shadeFragment(half.data(), 0.5f, 0.5f).t, 0.5f + 0.5f / 256.0f);
    EXPECT_EQ(toRgba8(Hit{0.5f + 0.5f / 256.0f, 0.5f}),
              (std::array<uint8_t, 4>{128, 128, 0, 255}));
}

// The texel the last step reads: with D[j][i] = 1 + i (above every p.z) the last d names
// the column. At pixel (0, 0) the search always goes up, mids 1/2, 3/4, …, 255/256, so
// the last p.x·512 = ½ + 64·255/256 = 64.25: column 64.
TEST(BinarySearchReference, LastStepTexel) {
    std::vector<float> columns(size_t(kDepthSize) * kDepthSize);
    for (int j = 0; j < kDepthSize; ++j)
        for (int i = 0; i < kDepthSize; ++i)
            columns[size_t(j) * kDepthSize + size_t(i)] = 1.0f + float(i);  // above p.z
    const Hit h =
        shadeFragment(columns.data(), pixelCentre(0, kWidth), pixelCentre(0, kHeight));
    EXPECT_EQ(h.t, 1.0f - 0.5f / 256.0f);
    EXPECT_EQ(h.d, 1.0f + 64.0f);
}

// ---- llvmpipe against the reference ------------------------------------------------

const char* const kRepro =
    "reproduce: build/bin/test_peer --gtest_filter='BinarySearchMesa.*'";

// Exact agreement, except where the reference's d·255 is a binary32 tie (x.5): the
// workload rounds halves away from zero (round()), llvmpipe's float → unorm8 conversion
// to even. The search itself is exact arithmetic on both sides
// (bench/binary_search_workload.h): every texel choice and comparison must agree, so red
// (½(lo + hi)) may never differ, and green only by 1 at a tie. A texel picked one off at
// a boundary (steps 6 and 7 sit on exact boundaries for every pixel) would change the
// search and show up here.
TEST(BinarySearchMesa, MatchesScalarReference) {
    const MesaImage mesa = renderMesa(1);
    ASSERT_NE(mesa.renderer.find("llvmpipe"), std::string::npos) << mesa.renderer;
    const std::vector<float> depth = depthImage();
    const std::vector<uint8_t> want = referenceImage(depth);
    ASSERT_EQ(mesa.rgba.size(), want.size());
    int differing = 0, ties = 0, unexplained = 0, maxDiff = 0;
    for (int y = 0; y < kHeight; ++y)
        for (int x = 0; x < kWidth; ++x) {
            const size_t o = (size_t(y) * kWidth + size_t(x)) * 4;
            int diff[4];
            for (int k = 0; k < 4; ++k) {
                diff[k] =
                    std::abs(int(mesa.rgba[o + size_t(k)]) - int(want[o + size_t(k)]));
                maxDiff = std::max(maxDiff, diff[k]);
            }
            if (!diff[0] && !diff[1] && !diff[2] && !diff[3]) continue;
            ++differing;
            const Hit h = shadeFragment(depth.data(), pixelCentre(x, kWidth),
                                        pixelCentre(y, kHeight));
            const float scaled = h.d * 255.0f;
            const bool tie = scaled - std::floor(scaled) == 0.5f;
            if (tie && diff[1] == 1 && !diff[0] && !diff[2] && !diff[3]) {
                ++ties;
                continue;
            }
            if (unexplained++ < 5)
                ADD_FAILURE() << "pixel (" << x << ", " << y << "): llvmpipe "
                              << int(mesa.rgba[o]) << " " << int(mesa.rgba[o + 1]) << " "
                              << int(mesa.rgba[o + 2]) << " " << int(mesa.rgba[o + 3])
                              << ", reference " << int(want[o]) << " " << int(want[o + 1])
                              << " " << int(want[o + 2]) << " " << int(want[o + 3])
                              << " (t = " << h.t << ", d = " << h.d << "); " << kRepro;
        }
    std::printf(
        "binary_search on %s: %d of %d pixels differ from the reference (%d of them "
        "a green rounding tie), largest channel difference %d\n",
        mesa.renderer.c_str(), differing, kWidth * kHeight, ties, maxDiff);
    EXPECT_EQ(unexplained, 0) << kRepro;
}

// The benchmark's 2-thread peer renders the same frame as the 1-thread one.
TEST(BinarySearchMesa, ThreadCountDoesNotChangeImage) {
    EXPECT_EQ(renderMesa(2).rgba, renderMesa(1).rgba) << kRepro;
}

}  // namespace
}  // namespace rg::bench::binary_search
