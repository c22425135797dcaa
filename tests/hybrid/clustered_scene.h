// The small ball-and-box scene with its layers clustered as the reproduction builds them
// (48×36 images, 8² EMs, three viewpoints): the shared fixture of the direct-image and
// shared-layer tests.
#pragma once

#include <vector>

#include "hybrid_precompute.h"
#include "hybrid_test_scenes.h"

namespace rg::hybrid::test {

struct ClusteredScene {
    LensScene scene{ballAndBox(), LensSceneOptions{}};
    PrecomputeSettings settings;
    std::vector<LensLayers> layers;
    std::vector<ray::Camera> views;
    ClusteredScene() {
        settings.width = 48;
        settings.height = 36;
        settings.subsample = 1;
        settings.clusterWidth = 32;
        settings.clusterHeight = 24;
        settings.emSize = 8;
        settings.inference.maxIterations = 60;
        const ray::ViewpointPath& path = scene.scene().viewpointPaths[0];
        for (uint32_t v = 0; v < 3; ++v) views.push_back(path.at(v));
        for (size_t i = 0; i < scene.objects().size(); ++i)
            layers.push_back(buildLayers(scene, i, clusterPass(scene, i, views, settings),
                                         scene.objects()[i].layers, {}, settings.emSize));
    }
};

}  // namespace rg::hybrid::test
