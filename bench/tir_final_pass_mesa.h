// The llvmpipe side of the `tir_final_pass` workload (bench/tir_final_pass_workload.h): the
// GLSL 1.30 twin of EyeVP and TirFP on an OSMesa compatibility context, set up as a GL 3.0
// programmer would (textures, mesh and program loaded once; per frame one glClear and one
// glDrawElements into an RGBA8 + depth24 framebuffer object), and a one-frame readback for
// tests.
#pragma once

#include <string>

#include "mesa_frame.h"
#include "tir_final_pass_workload.h"

namespace rg::bench::tir_final_pass {

// The shaders' sources (tests print them when a frame disagrees).
extern const char* const kVertexShader;
extern const char* const kFragmentShader;

// With a current OSMesa (compatibility profile) context of kWidth × kHeight: binds an RGBA8
// + depth24 framebuffer object, uploads the maps (GL_RGBA16F, NEAREST, CLAMP_TO_EDGE, one
// level) and the environment (GL_RGBA16F cube map, LINEAR, CLAMP_TO_EDGE, one level), the
// refractor into vertex and index buffers, compiles and links the program with `fragment`
// as its fragment shader, sets the uniforms from `in` and leaves all of it bound. Throws
// rg::Error with the compiler's log when a shader does not compile or link, or when GL
// reports an error.
void setupGl(const Inputs& in, const char* fragment = kFragmentShader);
// One frame: glClear of colour (0, 0, 0, 0) and depth (1), then the refractor.
void drawFrameGl(const Inputs& in);

// GL_RENDERER and the frame's kWidth·kHeight·4 bytes, row 0 at the top (our order).
using MesaImage = bench::MesaImage;

// Renders one frame on llvmpipe with `threads` threads in a forked child (renderMesaFrame,
// bench/mesa_frame.h) and returns it with rows in our order. `fragment`
// replaces the fragment shader (tests plant bugs in it). Throws rg::Error when the child
// cannot create a context or render.
MesaImage renderMesa(const Inputs& in, int threads = 1, const std::string& fragment = kFragmentShader);

}  // namespace rg::bench::tir_final_pass
