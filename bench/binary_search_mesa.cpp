#include "binary_search_mesa.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include "binary_search_workload.h"
#include "core/error.h"
#include "gl_program.h"

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

// Clip-space corners and their uv: two triangles covering the viewport. Window x of the
// pixel centre is x + ½, so the interpolated uv there is (x + ½)/512, as specified.
const float kQuad[6][4] = {
    {-1, -1, 0, 0}, {1, -1, 1, 0}, {1, 1, 1, 1},
    {-1, -1, 0, 0}, {1, 1, 1, 1},  {-1, 1, 0, 1},
};

}  // namespace

void setupGl() {
    gl::bindOffscreenTarget(kWidth, kHeight, /*depth=*/false, "binary_search");
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

    const GLuint program = gl::useProgram(kVertexShader, kFragmentShader, {"position", "texCoord"}, "binary_search");
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
