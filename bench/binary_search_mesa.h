// The llvmpipe side of the `binary_search` workload (bench/binary_search_workload.h):
// the workload as a GLSL 1.30 shader on an OSMesa compatibility context, written as a
// GL 3.0 programmer would (R32F texture uploaded and program linked once, one
// glDrawArrays of a two-triangle quad per frame into an RGBA8 framebuffer object — off
// screen, so no copy of the frame into OSMesa's buffer at each glFinish), and a one-frame
// readback (glReadPixels) for tests.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rg::bench::binary_search {

// With a current OSMesa (compatibility profile) context of kWidth × kHeight: binds an
// RGBA8 framebuffer object of that size, uploads D as a GL_R32F texture (NEAREST, REPEAT,
// one level), compiles and links the shaders, loads the quad into a vertex buffer and
// leaves all of it bound. Throws rg::Error with the
// compiler's log when the shaders do not compile or link, or when GL reports an error.
void setupGl();
// One frame: the quad's glDrawArrays (no clear: the quad covers every pixel).
void drawFrameGl();

struct MesaImage {
    std::string renderer;       // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::vector<uint8_t> rgba;  // kWidth·kHeight·4 bytes, rows in the order of D's rows
};

// Renders one frame on llvmpipe with `threads` threads in a forked child (llvmpipe reads
// LP_NUM_THREADS once per process, and the caller's process must stay free of GL contexts
// so that bench/mesa_peer.h can fork later) and returns its image, rows ordered as
// referenceImage(). Throws rg::Error when the child cannot create a context or render.
MesaImage renderMesa(int threads = 1);

}  // namespace rg::bench::binary_search
