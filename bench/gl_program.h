// What every GLSL twin of the llvmpipe peers sets up the same way (binary_search,
// tir_final_pass, impostor_peers): an off-screen framebuffer object in our target's formats,
// and a program from a vertex and a fragment shader, with the workload's name in every error.
// Runs in the peer's child with its OSMesa context current (bench/mesa_peer.h).
#pragma once

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <initializer_list>
#include <string>

namespace rg::bench::gl {

// Binds a framebuffer object of an RGBA8 colour texture (and, with `depth`, a 24-bit depth
// renderbuffer) of width × height and sets the viewport to it. Off screen, as an application
// would render: OSMesa's window buffer would add a copy of the whole image into the
// caller's memory at every glFinish, which is not rendering. rg::Error naming `workload`
// where the object is incomplete.
void bindOffscreenTarget(int width, int height, bool depth, const std::string& workload);

// Compiles both shaders, binds attribute i to attributes[i] and fragment output 0 to
// "colour", links and makes the program current; the shaders are deleted once linked.
// rg::Error naming `workload` and carrying GL's log where a shader does not compile or the
// program does not link.
GLuint useProgram(const char* vertex, const char* fragment, std::initializer_list<const char*> attributes,
                  const std::string& workload);

}  // namespace rg::bench::gl
