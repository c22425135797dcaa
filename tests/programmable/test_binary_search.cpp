// The binary_search benchmark's program (bench/binary_search_retroglass.h) renders exactly
// the workload's scalar reference image (bench/binary_search_workload.h): the benchmark
// against llvmpipe measures the algorithm both sides agree on, byte for byte on ours.
#include <gtest/gtest.h>

#include "binary_search_retroglass.h"

namespace rg::bench::binary_search {
namespace {

TEST(ProgrammableSearch, BenchmarkFrameEqualsTheWorkloadReferenceOnAnyThreadCount) {
    const std::vector<uint8_t> want = referenceImage(depthImage());
    struct Run {
        int threads;
        bool quad;
        Path path;
    };
    for (const Run& r : {Run{1, true, Path::Fast}, Run{2, true, Path::Fast}, Run{2, false, Path::Fast},
                         Run{1, true, Path::Reference}}) {
        const int threads = r.threads;
        const std::vector<uint8_t> got = renderRetroglass(r.threads, r.quad, r.path);
        ASSERT_EQ(got.size(), want.size());
        size_t differing = 0, first = got.size();
        for (size_t i = 0; i < got.size(); ++i)
            if (got[i] != want[i]) {
                ++differing;
                if (first == got.size()) first = i;
            }
        EXPECT_EQ(differing, 0u) << threads << " threads, " << (r.quad ? "quad" : "scalar")
                                 << " program, " << (r.path == Path::Fast ? "fast" : "reference")
                                 << " path; first differing byte " << first
                                 << " (pixel " << first / 4 << ")";
    }
}

}  // namespace
}  // namespace rg::bench::binary_search
