// The llvmpipe side of the impostor_secant and impostor_height workloads
// (bench/impostor_peers_workload.h): GLSL 1.30 twins of WorldVP and of GlassFP /
// GlassHeightFP on an OSMesa compatibility context, set up as a GL 3.2 programmer would
// (textures, meshes and program loaded once; per frame one glClear, then per piece its two
// textures bound, its constants set and one glDrawElementsBaseVertex into an RGBA8 +
// depth24 framebuffer object), and a one-frame readback for tests.
#pragma once

#include <string>

#include "impostor_peers_workload.h"
#include "mesa_frame.h"

namespace rg::bench::impostor_peers {

// The shaders' sources (tests print them when a frame disagrees, and plant bugs in them).
extern const char* const kVertexShader;
const std::string& fragmentShader(Exit e);

// With a current OSMesa (compatibility profile) context of kWidth × kHeight: binds an RGBA8
// + depth24 framebuffer object, uploads the maps (environment and refractor cubes as
// GL_RGBA16F, height maps as GL_RGBA32F; NEAREST, CLAMP_TO_EDGE, one level, cube faces not
// seamless) and the meshes into vertex and index buffers, compiles and links the program
// with `fragment` as its fragment shader and leaves it bound. Throws rg::Error with the
// compiler's log when a shader does not compile or link, or when GL reports an error.
void setupGl(const Inputs& in, const std::string& fragment);
// One frame: glClear of colour (0, 0, 0, 0) and depth (1), then every draw.
void drawFrameGl(const Inputs& in);

using MesaImage = bench::MesaImage;

// Renders one frame on llvmpipe with `threads` threads in a forked child (renderMesaFrame,
// bench/mesa_frame.h) and returns it with rows in our order. `fragment` replaces the
// fragment shader (tests plant bugs in it); empty: the workload's own. Throws rg::Error
// when the child cannot create a context or render.
MesaImage renderMesa(const Inputs& in, int threads = 1, const std::string& fragment = {});

}  // namespace rg::bench::impostor_peers
