// Gamepad → viewer actions, and the hidapi side that finds, opens and reads the pad.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gamepad.h"
#include "viewer_session.h"

namespace rg::viewer {

// The default mapping: left stick orbits, right stick dollies (y) and raises the eye (x),
// L1/R1 step through the viewpoint samples, South (cross, A) takes a screenshot,
// North (triangle, Y) resets, East (circle, B) jumps to the nearest sample.
struct PadBindings {
    pad::StickShape shape;
    float orbitDegreesPerFrame = 2.0f;
    float dollyPerFrame = 0.03f;     // distance factor exp(∓this) at full deflection
    float raisePerFrame = 0.01f;     // of the distance
};
std::vector<Action> padActions(const pad::PadState& now, const pad::PadState& before,
                               const PadBindings& bindings);
// The d-pad's left/right press (the edge, so a held pad steps once): −1, +1, else 0; the
// window turns it into nudgeAction (the demo's first Float parameter).
int padNudge(const pad::PadState& now, const pad::PadState& before);

// Finds the first gamepad hidapi lists, reads its reports without blocking, notices unplug
// (read error) and rescans for a new pad every two seconds. Never throws.
class GamepadManager {
  public:
    GamepadManager();
    ~GamepadManager();
    GamepadManager(const GamepadManager&) = delete;
    GamepadManager& operator=(const GamepadManager&) = delete;
    // The pad's latest state (nullopt while none is open); drains pending reports.
    std::optional<pad::PadState> poll();
    const std::string& status() const { return status_; }
    // Messages for the log: connect, disconnect, and "no gamepad" once.
    std::vector<std::string> takeMessages();

  private:
    void scan();
    void close();
    struct Impl;
    std::unique_ptr<Impl> impl_;
    std::string status_ = "no gamepad";
    std::vector<std::string> messages_;
    bool toldNone_ = false;
    std::chrono::steady_clock::time_point nextScan_{};
};

}  // namespace rg::viewer
