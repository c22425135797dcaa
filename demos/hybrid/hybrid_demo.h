// `retroglass view hybrid`: 000 §5 in the viewer. Every frame traces the lens objects'
// vertices from the viewer's camera, tessellates adaptively (τ live) and draws the layered
// EMs of the two nearest viewpoint samples in 4n passes on the viewer's GeForce 256 (the
// pass inspector lists each layer pass and each alpha clear). The layers are clustered
// over every viewpoint when the demo starts; a sample's EMs are inferred the first time a
// frame needs them (a few seconds each at the viewer's size), kept per layer count.
#pragma once

#include <map>
#include <memory>

#include "demo.h"
#include "hybrid_precompute.h"
#include "hybrid_renderer.h"
#include "lens_scene.h"

namespace rg::hybrid {

struct HybridDemoSettings {
    int width = 320, height = 240;
    int teapotLevel = 12;
    int emSize = 32;
    int clusterWidth = 48, clusterHeight = 36;
};

class HybridDemo final : public viewer::Demo {
  public:
    explicit HybridDemo(const viewer::DemoOptions& options, HybridDemoSettings settings = {});
    ~HybridDemo() override;

    std::string name() const override { return "hybrid"; }
    std::string title() const override;
    std::string defaultProfile() const override { return "geforce256"; }
    std::pair<int, int> frameSize() const override { return {settings_.width, settings_.height}; }
    viewer::OrbitRig rig() const override;
    std::vector<viewer::ViewpointSample> viewpointSamples() const override;
    std::vector<viewer::Param>& params() override { return params_; }
    std::vector<std::string> passDescriptions() const override;
    viewer::FrameNotes render(raster::Device& device, const ray::Camera& camera) override;

  private:
    const std::vector<LensLayers>& layersFor(int glassLayers);
    const SampleSolution& solution(int glassLayers, bool prevention, int view);
    HybridDemoSettings settings_;
    int threads_ = 0;
    bool builtin_ = true;
    std::unique_ptr<LensScene> scene_;
    ray::ViewpointPath path_;
    std::vector<ClusterPass> passes_;                  // per lens object, every viewpoint
    std::map<int, std::vector<LensLayers>> layers_;    // per glass layer count
    std::vector<viewer::Param> params_;
    // The precompute's own device (the display's size: A is built there).
    std::unique_ptr<raster::Device> precomputeDevice_;
    std::shared_ptr<tex::TextureMemory> precomputeMemory_;
    std::map<int, std::unique_ptr<HybridRenderer>> precomputeRenderers_;
    std::map<std::tuple<int, bool, int>, SampleSolution> solutions_;
    // The frame's renderer, bound to the viewer's device (rebuilt for another device or
    // layer count), and the samples uploaded to it.
    raster::Device* bound_ = nullptr;
    int boundLayers_ = 0;
    std::shared_ptr<tex::TextureMemory> memory_;
    std::unique_ptr<HybridRenderer> renderer_;
    std::map<std::pair<bool, int>, SampleMaps> uploads_;
};

}  // namespace rg::hybrid
