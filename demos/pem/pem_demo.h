// The PEM demo for the viewer (`retroglass view pem`): the layered PEMs of the reproduction
// (out/pem/assets, precomputed quickly when missing) rendered by PemRenderer for any
// camera. Between two viewpoint samples the frame blends the two nearest by angle on the
// viewpoint circle, with the weight from the angle (001 §5).
#pragma once

#include <map>
#include <memory>
#include <optional>

#include "pem_precompute.h"
#include "pem_renderer.h"
#include "pem_scene.h"
#include "demo.h"

namespace rg::pem {

// The two samples a camera blends: a, b (== a on a sample or with blending off) and the
// weight w of b. `position` is the fractional sample index of the camera's angle.
struct SampleBlend {
    int a = 0, b = 0;
    float w = 0.0f;
    float position = 0.0f;
};
// Samples at startDegrees + i·stepDegrees, i < count; angles outside the path clamp to
// its ends. Without blending, the nearest sample alone.
SampleBlend blendForAngle(const ray::ViewpointPath& path, float angleDegrees, bool blending);
// The camera's angle on the path's circle (the inverse of ray::cameraOnCircle).
float angleOnPath(const ray::ViewpointPath& path, const ray::Camera& camera);

class PemDemo final : public viewer::Demo {
  public:
    // Loads out/pem/assets (runs the quick precompute there first when it is missing or
    // was made for another scene).
    explicit PemDemo(const viewer::DemoOptions& options);
    ~PemDemo() override;

    std::string name() const override { return "pem"; }
    std::string title() const override;
    std::string defaultProfile() const override { return "geforce256"; }
    std::pair<int, int> frameSize() const override { return {width_, height_}; }
    viewer::OrbitRig rig() const override;
    std::vector<viewer::ViewpointSample> viewpointSamples() const override;
    std::vector<viewer::Param>& params() override { return params_; }
    std::vector<std::string> passDescriptions() const override;
    viewer::FrameNotes render(raster::Device& device, const ray::Camera& camera) override;

    const ray::ViewpointPath& path() const { return path_; }

  private:
    const PemSample& uploaded(int view, EmMode mode);
    std::unique_ptr<PemScene> scene_;
    ray::ViewpointPath path_;
    std::vector<ViewSample> samples_;
    std::optional<MapTexels> static_;   // traced on first use (Embree, a second or so)
    int emSize_ = 0, width_ = 640, height_ = 480;
    std::vector<viewer::Param> params_;
    // The renderer is bound to one device; rebuilt when the viewer hands another.
    raster::Device* bound_ = nullptr;
    std::unique_ptr<PemRenderer> renderer_;
    std::map<std::pair<int, int>, PemSample> uploads_;   // (view or -1 static, mode)
};

}  // namespace rg::pem
