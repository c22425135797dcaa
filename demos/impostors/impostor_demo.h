// `retroglass view impostors`: Dancsik & Minarik in the viewer. The passes run on the demo's
// own geforce8800 ProgrammableDevice (ImpostorRenderer); the finished frame goes to the
// viewer's framebuffer by drawPixels. The mode (static, classical, separated, mode A),
// DEPTH, the secant iterations, the impostors' size and the moving piece's place on its
// path are live parameters; the pass inspector shows the impostors, refractor maps and
// light maps the frame built.
#pragma once

#include <memory>

#include "programmable_demo.h"
#include "impostor_renderer.h"
#include "impostor_scene.h"

namespace rg::impostors {

class ImpostorDemo final : public viewer::ProgrammableDemo {
  public:
    // options.scene: empty for §8's chess scene, else a scene file or raycore built-in name
    // with glass or mirror objects (the last of them moves).
    explicit ImpostorDemo(const viewer::DemoOptions& options);
    ~ImpostorDemo() override;

    std::string name() const override { return "impostors"; }
    std::string title() const override;
    std::pair<int, int> frameSize() const override { return {600, 600}; }
    viewer::OrbitRig rig() const override;
    std::vector<viewer::ViewpointSample> viewpointSamples() const override;
    std::vector<std::string> passDescriptions() const override;
    viewer::FrameNotes render(raster::Device& device, const ray::Camera& camera) override;
    // The settings' limits (validate), and mode A's need of a board, tried on a tiny frame.
    void checkParams() const override;

    ImpostorSettings settings() const;  // the frame's settings from the params

  private:
    ImpostorScene scene_;
    std::unique_ptr<ImpostorRenderer> renderer_;
};

}  // namespace rg::impostors
