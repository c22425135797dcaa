// Figures for the reports: framebuffers as images, images side by side, labelled grids.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "raycore/image.h"

namespace rg::raster {
class Framebuffer;
}

namespace rg::demos {

// The emulated framebuffer's RGB as floats (bytes / 255), and optionally where it drew
// (alpha > 0 → 1, else 0).
ray::Image framebufferImage(const raster::Framebuffer& fb, ray::Image* drawn = nullptr);

// `image` where mask > 0, black elsewhere (a reference cut to the object the technique draws).
ray::Image masked(const ray::Image& image, const ray::Image& mask);

// Images side by side (top-aligned) or stacked (left-aligned), `gap` white pixels apart.
ray::Image hstack(const std::vector<ray::Image>& images, int gap = 4);
ray::Image vstack(const std::vector<ray::Image>& images, int gap = 4);

// A labelled grid: cells left to right, `columns` per row, each with its label rendered
// above it (DejaVu Sans through OpenImageIO). Cells may differ in size.
struct Cell {
    ray::Image image;
    std::string label;
};
ray::Image labelledGrid(const std::vector<Cell>& cells, int columns, int labelHeight = 18);

// A line plot as SVG: one or more series over the same x values (non-finite values are
// left out). The y axis runs from 0, or with `yFromData` from just below the smallest
// value (PSNR in dB, where 0 would squash the lines together), to just above the largest.
struct Series {
    std::string name, colour;
    std::vector<double> y;
};
void writeLinePlot(const std::filesystem::path& path, const std::string& title,
                   const std::string& xLabel, const std::string& yLabel,
                   const std::vector<double>& x, const std::vector<Series>& series,
                   bool yFromData = false);

}  // namespace rg::demos
