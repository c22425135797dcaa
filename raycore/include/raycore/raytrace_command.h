// `retroglass raytrace --scene FILE|NAME [--camera NAME|INDEX|PATH:I] [--spp N]
//  [--mode whitted|two-term] [--depth D] [--width W --height H] --out IMG`
// The implementation behind the command; the CLI (demos/cli) parses the flags into
// RaytraceArgs and returns what this returns.
#pragma once

#include <string>

#include "raycore/camera.h"

namespace rg::ray {

struct RaytraceArgs {
    std::string scene;            // built-in name or JSON file
    std::string camera;           // camera name, index, or "<path>:<i>" (viewpoint path)
    int spp = 1;                  // n for n×n supersampling
    std::string mode = "whitted"; // whitted | two-term | pem-layers
    int depth = 8;
    int width = 640, height = 480;
    int threads = 0;
    std::string out;              // image file; two-term and pem-layers add suffixes
    bool quiet = false;           // no progress bar, no summary line
};

struct Scene;

// A camera of `scene` by spec: empty (its first camera, else its first path's first
// viewpoint), a camera name or index, or "<path>:<i>" (viewpoint i of a path; a
// fractional i, e.g. "circle:49.5", lies on the circle between two viewpoints).
// rg::Error naming what is missing.
Camera chooseCamera(const Scene& scene, const std::string& spec);

// Returns 0 on success, 1 on error (message on stderr naming the problem).
int runRaytraceCommand(const RaytraceArgs& args);

}  // namespace rg::ray
