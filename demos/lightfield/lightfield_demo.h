// `retroglass view lightfield`: Heidrich et al. 1999 in the viewer. Each frame is the
// paper's: the geometry light field by the Gortler reconstruction, the read-back, the
// lookup by pixel texture (sgi-octane-mxe) or in software (any profile; the O2's route), or
// a vector-quantized radiance light field drawn through colour tables. Route, environment
// and VQ mode are live parameters; the viewer's profile switch picks the machine. The pass
// inspector shows each pass: the colour-coded coordinates, the read-back written back, the
// lookup, and the VQ passes.
#pragma once

#include <map>
#include <memory>

#include "demo.h"
#include "gortler_renderer.h"
#include "lightfield_scene.h"
#include "lookup.h"
#include "vq.h"

namespace rg::lightfield {

class LightfieldDemo final : public viewer::Demo {
  public:
    explicit LightfieldDemo(const viewer::DemoOptions& options);
    ~LightfieldDemo() override;

    std::string name() const override { return "lightfield"; }
    std::string title() const override;
    std::string defaultProfile() const override { return "sgi-octane-mxe"; }
    std::pair<int, int> frameSize() const override { return {400, 400}; }
    viewer::OrbitRig rig() const override;
    std::vector<viewer::ViewpointSample> viewpointSamples() const override;
    std::vector<viewer::Param>& params() override { return params_; }
    std::vector<std::string> passDescriptions() const override;
    viewer::FrameNotes render(raster::Device& device, const ray::Camera& camera) override;

    // The VQ light field a `vq_mode` (1–3) draws, trained on its first use and kept.
    const VqLightField& vq(int mode);

  private:
    struct PerProfile;  // textures in one profile's texture memory
    PerProfile& resources(const Profile& profile);

    LfScene scene_;
    std::unique_ptr<ray::Accel> accel_;
    LightField geo_;
    ParaboloidMap env_[2];
    HostTexture host_[2];
    std::unique_ptr<SoftwareLookup> lookup_[2];
    LightField radiance_;  // built on the first VQ frame
    std::map<int, VqLightField> vq_;
    std::map<ProfileId, std::unique_ptr<PerProfile>> perProfile_;
    std::vector<viewer::Param> params_;
    int threads_ = 0;
};

}  // namespace rg::lightfield
