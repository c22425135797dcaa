// One frame of a peer workload rendered on llvmpipe and read back, for the tests that check
// a workload's Mesa side against its definition (tests/peer/): the child process, the
// OSMesa context and the pipe that brings the image home, shared by the GLSL 1.30 workloads
// (bench/binary_search_mesa.h, bench/tir_final_pass_mesa.h), which keep their own GL setup
// and draw.
//
// Why a child: llvmpipe reads LP_NUM_THREADS once per process, and the caller's process
// must stay free of GL contexts so that bench/mesa_peer.h can fork later.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace rg::bench {

struct MesaImage {
    std::string renderer;       // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::vector<uint8_t> rgba;  // width·height·4 bytes, rows as `rowOrder` says
};

// Which row of the frame comes first in MesaImage::rgba.
enum class RowOrder {
    WindowRowZeroFirst,  // as glReadPixels returns them: GL's window row 0, the bottom, first
    TopRowFirst,         // the top row first (Direct3D's and our framebuffer's order)
};

// Renders one frame on llvmpipe with `threads` threads in a forked child and returns it.
// The child sets GALLIUM_DRIVER=llvmpipe and LP_NUM_THREADS, makes an OSMesa compatibility
// context of width × height current (RGBA, no depth buffer: the workloads draw into
// framebuffer objects of their own), runs `draw` (the workload's setup and one frame; it
// throws rg::Error on failure), reads the bound framebuffer back (RGBA8, pack alignment 4),
// calls glFinish and checks glGetError. `workload` names the workload in the errors. Throws
// rg::Error with the child's message when it cannot create a context or render, or when it
// dies.
MesaImage renderMesaFrame(const std::string& workload, int width, int height, int threads, RowOrder rowOrder,
                          const std::function<void()>& draw);

}  // namespace rg::bench
