// What the viewer shows, without a window: a demo, the emulated device it draws into, the
// orbit camera, and the actions that change them. The window (viewer_window.cpp) and the
// headless replay (view_command.cpp) both drive a ViewerSession, so a replayed frame is the
// window's frame byte for byte.
//
// Actions are the viewer's input stream after key bindings and gamepad decoding: what a
// recording stores (docs/viewer.md, "Record format").
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "demo.h"
#include "orbit_camera.h"
#include "rasterizer/device.h"

namespace rg::viewer {

struct Action {
    enum class Kind {
        Orbit,       // x = Δazimuth°, y = Δelevation°
        Dolly,       // x = distance factor
        Pan,         // x, y in units of the distance
        Raise,       // x in units of the distance
        Reset,       // the demo's start camera
        Sample,      // value = viewpoint sample index
        Step,        // value = ±1: next / previous viewpoint sample
        Nearest,     // the viewpoint sample nearest the camera
        Param,       // name = parameter, value
        Profile,     // name = profile
        Threads,     // value = thread count (0: all cores); changes no byte
        Screenshot,  // the frame's PNG (the window's writer decides the file)
    };
    Kind kind = Kind::Reset;
    float x = 0, y = 0;
    double value = 0;
    std::string name;
    friend bool operator==(const Action&, const Action&) = default;
};

const char* actionVerb(Action::Kind kind);

// The keyboard's -/= and the pad's d-pad left/right step the demo's first Float parameter
// (impostors: the moving piece along its path) by a twentieth of its range, clamped; the
// step is an ordinary Param action, so recordings replay it. nullopt: the demo has none.
std::optional<Action> nudgeAction(const std::vector<Param>& params, int direction);

// One pass of the last frame as the pass inspector shows it: the framebuffer when the
// pass ended and the state its last draw used.
struct PassSnapshot {
    raster::PassRecord record;
    int width = 0, height = 0;
    std::vector<Rgba8> color;  // what the inspector displays, at the frame's size
    std::string state;  // profile, pipeline state, texture stages, bound textures
    // A programmable pass's target: its texels (hovering shows them) and the range the
    // display mapped; for fixed-function passes `values` is empty (the bytes are the values).
    std::string target, range;
    TargetImage image;
};

// The device state as text: profile, depth/blend/cull, active texture stages with their
// ops, arguments, coordinate sets and bound textures, TFACTOR.
std::string describeDeviceState(const raster::Device& device);

class ViewerSession {
  public:
    ViewerSession(std::unique_ptr<Demo> demo, const std::string& profile, int threads);

    Demo& demo() { return *demo_; }
    raster::Device& device() { return *device_; }
    const OrbitCamera& camera() const { return camera_; }
    const std::string& profile() const { return profile_; }
    int threads() const { return threads_; }
    const std::vector<ViewpointSample>& samples() const { return samples_; }
    // Index of the viewpoint sample nearest the camera (by eye direction); -1 if none.
    int nearestSample() const;

    // Applies one action. Profile changes that the demo cannot draw on throw rg::Error and
    // leave the session on its previous profile.
    void apply(const Action& action);
    // Renders the frame for the current state; with `capturePasses`, keeps a snapshot per pass.
    void render(bool capturePasses);

    const FrameNotes& notes() const { return notes_; }
    const std::vector<PassSnapshot>& passSnapshots() const { return snapshots_; }
    double frameMs() const { return frameMs_; }
    // FNV-1a 64 of the colour buffer bytes: the identity of a frame in recordings.
    uint64_t frameHash() const;

  private:
    void makeDevice(const std::string& profile);
    std::unique_ptr<Demo> demo_;
    std::unique_ptr<raster::Device> device_;
    std::string profile_;
    int threads_ = 0;
    OrbitRig rig_;
    OrbitCamera camera_;
    std::vector<ViewpointSample> samples_;
    FrameNotes notes_;
    std::vector<PassSnapshot> snapshots_;
    double frameMs_ = 0;
};

// ---- record format ----------------------------------------------------------------------
//   retroglass-view-record 1
//   demo pem
//   profile geforce256
//   scene -                     (or the --scene file)
//   <frame> <verb> <args...>    actions applied before rendering <frame>
//   <frame> hash <16 hex>       FNV-1a 64 of the framebuffer the window showed at <frame>
//   end <frames>
struct Recording {
    std::string demo = "pem", profile, scene;
    struct Entry {
        int64_t frame = 0;
        Action action;
    };
    std::vector<Entry> actions;                          // in order
    std::vector<std::pair<int64_t, uint64_t>> hashes;    // (frame, hash)
    int64_t frames = 0;
};
void writeRecordingHeader(std::ostream& out, const Recording& r);
void writeAction(std::ostream& out, int64_t frame, const Action& action);
void writeHash(std::ostream& out, int64_t frame, uint64_t hash);
void writeEnd(std::ostream& out, int64_t frames);
// Throws rg::Error naming the line for anything malformed.
Recording readRecording(std::istream& in);
Recording readRecordingFile(const std::string& path);

}  // namespace rg::viewer
