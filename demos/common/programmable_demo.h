// What the viewer demos of the programmable profile share (`retroglass view tir`,
// `retroglass view impostors`; demo.h is the interface). Such a demo draws its passes on a
// geforce8800 raster::ProgrammableDevice of its own and hands the finished frame to the
// viewer's device by drawPixels, so the window, recordings, hashes and screenshots work as
// for every other demo:
//
//   params ──▶ the paper's renderer (its own ProgrammableDevice) ──▶ RGBA8 frame texture
//          ──handOver──▶ viewer's Device: one frame, one pass, one drawPixels
//
// The paper's demo keeps what is its own: its scene, its params and the settings made from
// them, the renderer call, the images the pass inspector shows and the HUD's notes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "demo.h"

namespace rg::tex {
class Texture;
}

namespace rg::viewer {

class ProgrammableDemo : public Demo {
  public:
    std::string defaultProfile() const override { return "geforce8800"; }
    std::vector<Param>& params() override { return params_; }
    void setCapturePasses(bool capture) override { capture_ = capture; }
    std::vector<ProgrammablePass> programmablePasses() const override { return passes_; }

  protected:
    explicit ProgrammableDemo(std::vector<Param> params);

    // Throws rg::Error unless `device` runs geforce8800: "NAME runs on geforce8800 (needs);
    // profile 'P' has neither", `needs` the features the demo's passes use.
    void requireProgrammable(const raster::Device& device, const std::string& needs) const;
    // The finished frame, `frame`'s RGBA8 level 0 of width × height, into `device` as it is:
    // beginFrame, the default state, one pass ("hand-over: …") of one drawPixels, endFrame.
    static void handOver(raster::Device& device, const tex::Texture& frame, int width, int height);

    std::vector<Param> params_;
    bool capture_ = false;                  // keep each pass's targets (the inspector is open)
    std::vector<ProgrammablePass> passes_;  // the last frame's, when kept
};

// The HUD's line for one pass of the programmable device: "1.23 ms, 4567 fragments".
void addPassNote(FrameNotes& notes, const std::string& pass, double ms, uint64_t fragments);

}  // namespace rg::viewer
