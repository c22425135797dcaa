// 000 §4.3's shared distant layers: "add more equations to the linear system (1)
// corresponding to multiple lens objects and simultaneously solving for a single EM x".
// The second object's outermost layer takes the first's shell; one system holds the rows of
// both (exactly the rows the two separate systems would have on the same shells), both
// objects get the same texels and, on the device, the same texture, resident once.
#include <gtest/gtest.h>

#include "core/error.h"
#include "core/profile.h"
#include "hybrid_precompute.h"
#include "clustered_scene.h"
#include "hybrid_test_scenes.h"

namespace rg::hybrid {
namespace {

using Small = test::ClusteredScene;

TEST(SharedDistantLayers, OneSystemOverBothObjectsRowsOneMapResidentOnce) {
    Small s;
    ASSERT_EQ(s.layers.size(), 2u);
    std::vector<LensLayers> shared = s.layers;
    shareDistantLayers(shared);
    const int owner = shared[0].layers() - 1, last = shared[1].layers() - 1;
    EXPECT_TRUE(shared[1].shares(last));
    EXPECT_FALSE(shared[0].shares(owner));
    EXPECT_EQ(shared[1].shells[size_t(last)].describe(), shared[0].shells[size_t(owner)].describe());
    EXPECT_EQ(HybridRenderer::sampleBytes(shared),
              HybridRenderer::sampleBytes(s.layers) - uint64_t(s.layers[1].layout(last).count()) * 4);
    // The same shells without sharing: each object's own system.
    std::vector<LensLayers> apart = shared;
    apart[1].sharedOwnerLayer = -1;
    ASSERT_FALSE(apart[1].shares(last));

    raster::Device device(profileByName("geforce256"), s.settings.width, s.settings.height,
                          raster::DepthFormat::D24);
    auto memory = std::make_shared<tex::TextureMemory>(device.profile());
    HybridRenderer rs(device, memory, s.scene, shared, 1, TessellationSettings{});
    HybridRenderer ra(device, memory, s.scene, apart, 1, TessellationSettings{});
    const std::vector<ray::Camera> one{s.views[0]};
    const SampleSolution a = inferSample(ra, 0, one, s.settings, RecordOptions{});
    const SampleSolution b = inferSample(rs, 0, one, s.settings, RecordOptions{});
    const LayerMap& own0 = a.maps[0][size_t(owner)];
    const LayerMap& own1 = a.maps[1][size_t(last)];
    ASSERT_GT(own0.rows, 0);
    ASSERT_GT(own1.rows, 0);
    EXPECT_EQ(b.maps[0][size_t(owner)].rows, own0.rows + own1.rows) << "both objects' equations";
    EXPECT_TRUE(b.maps[1][size_t(last)].texels == b.maps[0][size_t(owner)].texels);
    EXPECT_FALSE(own1.texels == own0.texels) << "apart, the two systems differ";
    // The layers nearer than the shared one are the objects' own, as before.
    for (size_t i = 0; i < 2; ++i)
        for (int l = 0; l + 1 < shared[i].layers(); ++l)
            EXPECT_TRUE(a.maps[i][size_t(l)].texels == b.maps[i][size_t(l)].texels) << i << " L" << l;
    const SampleMaps m = uploadSample(rs, b);
    EXPECT_EQ(m.maps[1][size_t(last)].get(), m.maps[0][size_t(owner)].get()) << "one texture";
}

TEST(SharedDistantLayers, RefusedForLayersOfDifferentSizes) {
    Small s;
    s.layers[1].emSize = 16;
    EXPECT_THROW(shareDistantLayers(s.layers), Error);
}

}  // namespace
}  // namespace rg::hybrid
