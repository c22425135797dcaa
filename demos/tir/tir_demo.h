// `retroglass view tir`: Davis & Wyman 2007 in the viewer. The four passes run on the demo's
// own geforce8800 ProgrammableDevice (TirRenderer); the finished frame goes to the viewer's
// framebuffer by drawPixels. Bounces, iterations, front-and-back, the method and the map
// size are live parameters; the pass inspector shows every map of Figure 2.
#pragma once

#include <memory>

#include "programmable_demo.h"
#include "tir_renderer.h"
#include "tir_scene.h"

namespace rg::tir {

class TirDemo final : public viewer::ProgrammableDemo {
  public:
    // options.scene: a tir scene name (kitchen, statue, dragon, prism), a raycore built-in
    // scene or a scene file with a glass object; empty: the kitchen.
    explicit TirDemo(const viewer::DemoOptions& options);
    ~TirDemo() override;

    std::string name() const override { return "tir"; }
    std::string title() const override;
    std::pair<int, int> frameSize() const override { return {512, 512}; }
    viewer::OrbitRig rig() const override;
    std::vector<viewer::ViewpointSample> viewpointSamples() const override;
    std::vector<std::string> passDescriptions() const override;
    viewer::FrameNotes render(raster::Device& device, const ray::Camera& camera) override;

    TirSettings settings() const;  // the frame's settings from the params

  private:
    TirScene scene_;
    std::unique_ptr<TirRenderer> renderer_;
};

}  // namespace rg::tir
