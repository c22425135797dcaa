#include "binary_search_mesa.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include "binary_search_workload.h"
#include "core/error.h"

namespace rg::bench::binary_search {

namespace {

// GLSL 1.30 (OpenGL 3.0, the generation of the GeForce 8800): textureLod and integer
// loops, nothing later. uv comes from the vertices, so the rasterizer interpolates it;
// at w = 1 with dyadic end points that interpolation is exact (see the workload header).
const char* const kVertexShader = R"(#version 130
in vec2 position;
in vec2 texCoord;
out vec2 uv;
void main() {
    uv = texCoord;
    gl_Position = vec4(position, 0.0, 1.0);
}
)";

const char* const kFragmentShader = R"(#version 130
uniform sampler2D depthTexture;
in vec2 uv;
out vec4 colour;
void main() {
    vec3 a = vec3(uv, 0.0);
    vec3 b = vec3(uv + vec2(0.125, 0.0625), 1.0);
    float lo = 0.0, hi = 1.0, d = 0.0;
    for (int step = 0; step < 8; ++step) {
        float mid = 0.5 * (lo + hi);
        vec3 p = a + (b - a) * mid;
        d = textureLod(depthTexture, p.xy, 0.0).r;
        if (p.z > d) hi = mid; else lo = mid;
    }
    colour = vec4(0.5 * (lo + hi), d, 0.0, 1.0);
}
)";

GLuint compile(GLenum kind, const char* source) {
    GLuint shader = glCreateShader(kind);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[2048] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        throw Error(std::string("binary_search: the ") +
                    (kind == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                    " shader does not compile: " + log);
    }
    return shader;
}

// Clip-space corners and their uv: two triangles covering the viewport. Window x of the
// pixel centre is x + ½, so the interpolated uv there is (x + ½)/512, as specified.
const float kQuad[6][4] = {
    {-1, -1, 0, 0}, {1, -1, 1, 0}, {1, 1, 1, 1},
    {-1, -1, 0, 0}, {1, 1, 1, 1},  {-1, 1, 0, 1},
};

}  // namespace

void setupGl() {
    // The frame goes to a framebuffer object (an RGBA8 texture), as an application that
    // renders off screen would: OSMesa's window buffer would add a copy of the whole image
    // into the caller's memory at every glFinish, which is not rendering.
    GLuint colour = 0, fbo = 0;
    glGenTextures(1, &colour);
    glBindTexture(GL_TEXTURE_2D, colour);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, kWidth, kHeight, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("binary_search: the RGBA8 framebuffer object is not complete");
    glViewport(0, 0, kWidth, kHeight);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDisable(GL_DITHER);

    // D: row 0 first, which GL puts at t ∈ [0, 1/512), the workload's row order.
    const std::vector<float> depth = depthImage();
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, kDepthSize, kDepthSize, 0, GL_RED, GL_FLOAT,
                 depth.data());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);

    GLuint program = glCreateProgram();
    const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
    const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glBindAttribLocation(program, 0, "position");
    glBindAttribLocation(program, 1, "texCoord");
    glBindFragDataLocation(program, 0, "colour");
    glLinkProgram(program);
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked) {
        char log[2048] = {};
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        throw Error(std::string("binary_search: the program does not link: ") + log);
    }
    glDeleteShader(vs);
    glDeleteShader(fs);
    glUseProgram(program);
    glUniform1i(glGetUniformLocation(program, "depthTexture"), 0);

    GLuint vao = 0, vbo = 0;
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof kQuad, kQuad, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, 4 * sizeof(float),
                          reinterpret_cast<const void*>(2 * sizeof(float)));
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);

    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        throw Error("binary_search: GL error " + std::to_string(e) + " in setup");
}

void drawFrameGl() { glDrawArrays(GL_TRIANGLES, 0, 6); }

MesaImage renderMesa(int threads) {
    return renderMesaFrame("binary_search", kWidth, kHeight, threads, RowOrder::WindowRowZeroFirst, [] {
        // Buffer row 0 is GL's window row 0, where v = ½/512: the workload's rows. (The
        // frame is read from the framebuffer object, whose rows from window row 0 up are
        // the workload's order too.)
        OSMesaPixelStore(OSMESA_Y_UP, 1);
        setupGl();
        drawFrameGl();
    });
}

}  // namespace rg::bench::binary_search
