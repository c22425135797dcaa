// Internal to conformance/: the Mesa peer of a programmable (version 2) trace
// (conformance/mesa_program_player.cpp). conformance/mesa_player.cpp dispatches to it.
#pragma once

#include <string>
#include <vector>

#include "core/color.h"
#include "rasterizer/trace.h"

namespace rg::conformance::detail {

// Empty when OpenGL 3 on llvmpipe can play every record: each draw's program has a GLSL
// twin (rasterizer/include/rasterizer/program_registry.h) naming a sampler for every unit
// and an output for every target it uses, and no texture is 4D. Otherwise why not, as a
// whole phrase (conformance::oursOnlyReason prints it after "ours only: ").
std::string mesaProgramUnsupported(const raster::Trace& trace);

// Plays the trace on the OSMesa context current in this process: textures and render
// targets as GL textures, each RenderTargets binding as a framebuffer object, every
// command, glFinish. With `image`, reads the trace's image (Trace::image) back as RGBA8,
// rows top to bottom (float targets through tex::floatToRgba8, as ours). GL objects are
// deleted at the end except the twins' linked programs, which stay for the next play on
// the same context (ours compiles its programs when retroglass is built). Throws
// rg::Error on a GL error or a twin that does not compile.
void playProgramTrace(const raster::Trace& trace, std::vector<Rgba8>* image);

}  // namespace rg::conformance::detail
