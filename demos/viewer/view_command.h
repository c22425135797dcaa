// `retroglass view DEMO`: the interactive viewer, its headless replay, and the key
// bindings (shared by --help, the panel and docs/viewer.md).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "viewer_session.h"

namespace rg::viewer {

struct ViewOptions {
    std::string demo;
    std::string profile;       // empty: the demo's paper profile
    std::string scene;         // --scene FILE
    std::string outRoot = "out";  // where reproductions keep their assets (out/<demo>)
    int threads = 0;
    std::string record;        // --record FILE
    std::string replay;        // --replay FILE
    bool headless = false;     // --headless (with --replay): no window
    std::string out;           // --out DIR for headless frames
    std::string shots = "out/view";  // screenshot folder of the window
    int64_t maxFrames = 0;     // --frames N: quit after N frames (0: run until closed)
};

// (keys, what they do) in the order --help and the panel list them.
const std::vector<std::pair<std::string, std::string>>& keyBindings();
std::string bindingsHelp();

int runView(const ViewOptions& options);

// Writes the emulated framebuffer as an 8-bit RGBA PNG (OpenImageIO): the bytes exactly.
void writeFramebufferPng(const std::string& path, const raster::Framebuffer& fb);
void writePixelsPng(const std::string& path, int width, int height, const std::vector<Rgba8>& pixels);

// Throws rg::Error when there is no display to open a window on (viewer_window.cpp).
void requireDisplay();
// The window (viewer_window.cpp); returns the exit status.
int runWindow(ViewerSession& session, const ViewOptions& options);

}  // namespace rg::viewer
