// The Mesa peer of a trace replay: the same records through OSMesa's fixed-function
// OpenGL (llvmpipe), with Direct3D 7 state mapped to GL 1.3 (+ the GL 1.4 blend
// equations, mirrored repeat, LOD bias, window position and secondary colour that Mesa
// has). See docs/testing.md, "Conformance against Mesa".
#pragma once

#include <string>
#include <vector>

#include "rasterizer/framebuffer.h"
#include "rasterizer/trace.h"

namespace rg::conformance {

// Empty when GL 1.3 can express every record of the trace; otherwise why it cannot
// (pixel texture, colour tables, 4D textures, a stage op without a combine twin, ...).
// A programmable trace: empty when every draw's program has a GLSL twin
// (rasterizer/include/rasterizer/program_registry.h) that OpenGL 3 can run.
std::string mesaUnsupported(const raster::Trace& trace);
// What `retroglass bench --trace`, `replay --backend mesa` and `conform` print after
// "ours only: " for a trace Mesa cannot play (empty when it can): "Mesa lacks <feature>",
// or "no GLSL twin registered for program '<name>'" and the like for a program.
std::string oursOnlyReason(const raster::Trace& trace);

struct MesaReplay {
    std::string unsupported;          // non-empty: not played
    raster::Framebuffer framebuffer;  // RGBA8, rows top to bottom as ours
    std::string renderer;             // GL_RENDERER
};

// Plays the trace in a child process (OSMesa must not share a process with threads that
// later fork, and llvmpipe's thread count is per process): the child creates the
// context, plays, sends the pixels back and exits.
MesaReplay replayOnMesa(const raster::Trace& trace);

// Plays the whole trace on the OSMesa context current in this process (RGBA, the trace's
// size): initial contents, texture uploads (deleted again at the end), every command, a
// final glFinish. replayOnMesa's child calls it once; `retroglass bench --trace`
// (bench/bench_trace.cpp) calls it once per timed frame in bench/mesa_peer's child, so that
// one call is one replay, as replayTrace is on ours. The caller checks mesaUnsupported().
void playOnCurrentContext(const raster::Trace& trace);

// `retroglass conform`: every golden trace on ours and on Mesa; prints a table and
// returns non-zero when a trace exceeds its tolerance.
int runConform(const std::string& goldenDir);

}  // namespace rg::conformance
