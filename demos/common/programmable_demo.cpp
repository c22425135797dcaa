// The programmable demos' shared frame (programmable_demo.h).
#include "programmable_demo.h"

#include <cstdio>
#include <span>
#include <utility>

#include "core/error.h"
#include "rasterizer/device.h"
#include "texunit/texture.h"

namespace rg::viewer {

ProgrammableDemo::ProgrammableDemo(std::vector<Param> params) : params_(std::move(params)) {}

void ProgrammableDemo::requireProgrammable(const raster::Device& device, const std::string& needs) const {
    if (std::string(device.profile().name) != defaultProfile())
        throw Error(name() + " runs on " + defaultProfile() + " (" + needs + "); profile '" +
                    std::string(device.profile().name) + "' has neither");
}

void ProgrammableDemo::handOver(raster::Device& device, const tex::Texture& frame, int width, int height) {
    const Rgba8* px = const_cast<tex::Texture&>(frame).renderData8(0, 0);
    device.beginFrame();
    device.setState(raster::PipelineState{});
    device.beginPass("hand-over: the programmable frame by drawPixels");
    device.drawPixels(0, 0, width, height, std::span<const Rgba8>(px, size_t(width) * size_t(height)));
    device.endFrame();
}

void addPassNote(FrameNotes& notes, const std::string& pass, double ms, uint64_t fragments) {
    char b[128];
    std::snprintf(b, sizeof b, "%.2f ms, %llu fragments", ms, (unsigned long long)fragments);
    notes.push_back({pass, b});
}

}  // namespace rg::viewer
