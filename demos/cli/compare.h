// `retroglass compare [--scene FILE|NAME] [--view SPEC ...]`: every registered technique
// that applies to the scene's objects (mirror or glass) renders the same views on its own
// profile, beside the ray tracer. Per view a table (PSNR / SSIM over the object against
// the ray tracer, precompute time, frame time, texture memory), an image grid, and a plot
// of PSNR per technique; report.md, index.html and results.json in the output folder.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "reproduction.h"

namespace rg::demos {

struct CompareOptions {
    std::string scene = "teapot-in-room";  // built-in name or scene file
    // Camera specs (raycore chooseCamera: name, index, PATH:I with fractional I) or the
    // words on / between / above (on the middle viewpoint of the scene's path, halfway to the
    // next one, and that point a quarter of the path's radius higher). Empty: on, between
    // and above when the scene has a path, else its cameras.
    std::vector<std::string> views;
    std::vector<std::string> techniques;  // registry names to run (empty: all that apply)
    std::string outDir = "out/compare";
    Quality quality = Quality::Quick;
    int width = 256, height = 256;  // square: tir's reference renders square images
    int threads = 0;
};

// Runs the comparison; returns what results.json holds. rg::Error when no registered
// technique applies to the scene, or a view shows none of an object's pixels.
nlohmann::json runCompare(const CompareOptions& options);

}  // namespace rg::demos
