// The llvmpipe side of the `binary_search` workload (bench/binary_search_workload.h):
// the workload as a GLSL 1.30 shader on an OSMesa compatibility context, written as a
// GL 3.0 programmer would (R32F texture uploaded and program linked once, one
// glDrawArrays of a two-triangle quad per frame into an RGBA8 framebuffer object — off
// screen, so no copy of the frame into OSMesa's buffer at each glFinish), and a one-frame
// readback (glReadPixels) for tests.
#pragma once

#include "mesa_frame.h"

namespace rg::bench::binary_search {

// With a current OSMesa (compatibility profile) context of kWidth × kHeight: binds an
// RGBA8 framebuffer object of that size, uploads D as a GL_R32F texture (NEAREST, REPEAT,
// one level), compiles and links the shaders, loads the quad into a vertex buffer and
// leaves all of it bound. Throws rg::Error with the
// compiler's log when the shaders do not compile or link, or when GL reports an error.
void setupGl();
// One frame: the quad's glDrawArrays (no clear: the quad covers every pixel).
void drawFrameGl();

// GL_RENDERER and the frame's kWidth·kHeight·4 bytes, in the order of D's rows (GL's
// window rows from 0 up).
using MesaImage = bench::MesaImage;

// Renders one frame on llvmpipe with `threads` threads in a forked child (renderMesaFrame,
// bench/mesa_frame.h) and returns its image, rows ordered as referenceImage(). Throws
// rg::Error when the child cannot create a context or render.
MesaImage renderMesa(int threads = 1);

}  // namespace rg::bench::binary_search
