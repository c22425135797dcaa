// The interface between a paper's demo and the viewer (`retroglass view DEMO`).
//
// A demo is a render function plus the values that steer it. The viewer owns the emulated
// device, the camera and the input; it never knows which paper it shows. The same
// `render()` runs in the window, in `--headless` replay and in the tests, so what the
// window shows is what a replay writes, byte for byte.
//
//   viewer ──(params, camera)──▶ Demo::render(Device&, Camera) ──▶ Device passes ──▶ framebuffer
//
// Adding a paper: implement Demo in demos/<paper>/<paper>_demo.{h,cpp} and return it from
// the paper's Reproduction::makeDemo (reproduction.h); the registry, demos/registry.cpp,
// is the one list. docs/viewer.md has the details.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec4.hpp>

#include "core/color.h"
#include "raycore/camera.h"

namespace rg::raster {
class Device;
}

namespace rg::viewer {

// One named value the panel shows and the record file stores ("param NAME VALUE").
struct Param {
    enum class Kind { Bool, Int, Float, Enum };
    std::string name;                  // identifier: lower_snake, no spaces
    std::string label;                 // what the panel shows
    std::string help;                  // tooltip and docs
    Kind kind = Kind::Bool;
    double value = 0;                  // Bool 0/1, Int and Enum an integer, Float as is
    double min = 0, max = 1;           // Int and Float ranges
    std::vector<std::string> choices;  // Enum: value indexes this list
};

// A camera the paper pre-rendered or otherwise singles out (PEM: its viewpoint samples).
// The viewer jumps and steps through them.
struct ViewpointSample {
    std::string name;
    ray::Camera camera;
};

// Where the orbit camera turns: the viewer orbits `target` at the start camera's distance.
struct OrbitRig {
    ray::Camera start;                 // the reset camera
    float minDistance = 0.1f, maxDistance = 100.0f;
};
// The rig of a demo that starts at `camera` (named "start"): the viewer dollies between
// minFactor and maxFactor times its distance to its target.
OrbitRig orbitAround(const ray::Camera& camera, float minFactor, float maxFactor);

// One render target of a programmable pass, as the pass inspector shows it: its texels as
// floats (8-bit formats as v/255), and how to show them.
struct TargetImage {
    enum class Kind {
        Color8,  // an RGBA8 target: shown as it is
        Float,   // a float colour target: tone-mapped, its finite range [lo, hi] to [0, 1]
        Depth,   // a depth value per texel (in x): grey over its finite range, far = white
        Normal,  // a unit normal per texel (xyz): ½ + ½n as colour, zero-length as black
    };
    std::string name;
    Kind kind = Kind::Color8;
    int width = 0, height = 0;
    std::vector<glm::vec4> values;  // row-major, row 0 at the top
};

// A programmable demo's pass: its label, the state it ran with, the targets it wrote.
struct ProgrammablePass {
    std::string label;
    std::string state;
    std::vector<TargetImage> targets;
};

// What the inspector displays for a target: RGBA8 at width × height (nearest), and the
// range it mapped (for Float and Depth: "lo … hi"; empty otherwise).
std::vector<Rgba8> displayTarget(const TargetImage& t, int width, int height, std::string* range);

// Name/value lines the HUD prints under the device counters (e.g. the samples blended).
using FrameNotes = std::vector<std::pair<std::string, std::string>>;

struct DemoOptions {
    std::filesystem::path outDir;      // out/<demo>: where its reproduction stores assets
    std::string scene;                 // --scene FILE, empty for the paper's scene
    int threads = 0;
};

class Demo {
  public:
    virtual ~Demo() = default;
    virtual std::string name() const = 0;
    virtual std::string title() const = 0;            // the paper
    virtual std::string defaultProfile() const = 0;   // the paper's machine
    virtual std::pair<int, int> frameSize() const = 0;
    virtual OrbitRig rig() const = 0;
    virtual std::vector<ViewpointSample> viewpointSamples() const = 0;
    // The demo's parameters; the viewer edits `value` in place between frames.
    virtual std::vector<Param>& params() = 0;
    // Raises rg::Error naming the problem when the params as they stand are a combination
    // the demo cannot render; the viewer then refuses the edit and restores the old value.
    virtual void checkParams() const {}
    // What a frame does, pass by pass, in the paper's words (the inspector's legend).
    virtual std::vector<std::string> passDescriptions() const = 0;
    // Renders one frame into `device` (beginFrame … endFrame). Must depend only on the
    // params, the camera, the device's profile and size: no clocks, no randomness.
    // A demo of the programmable profile (geforce8800) draws its passes on its own
    // raster::ProgrammableDevice and hands the finished frame to `device` with drawPixels,
    // so the window, recordings, hashes and screenshots are the same for every demo.
    virtual FrameNotes render(raster::Device& device, const ray::Camera& camera) = 0;
    // Programmable demos: keep each pass's targets during render() (the inspector is open),
    // and the passes of the last frame so kept.
    virtual void setCapturePasses(bool capture) {}
    virtual std::vector<ProgrammablePass> programmablePasses() const { return {}; }
};

// Param helpers: lookup by name (throws rg::Error for an unknown name).
Param& findParam(std::vector<Param>& params, const std::string& name);
double paramValue(const std::vector<Param>& params, const std::string& name);

}  // namespace rg::viewer
