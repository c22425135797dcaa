#include "gl_program.h"

#include "core/error.h"

namespace rg::bench::gl {

void bindOffscreenTarget(int width, int height, bool depth, const std::string& workload) {
    GLuint colour = 0, depthBuffer = 0, fbo = 0;
    glGenTextures(1, &colour);
    glBindTexture(GL_TEXTURE_2D, colour);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour, 0);
    if (depth) {
        glGenRenderbuffers(1, &depthBuffer);
        glBindRenderbuffer(GL_RENDERBUFFER, depthBuffer);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depthBuffer);
    }
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error(workload + ": the RGBA8" + (depth ? " + depth24" : "") + " framebuffer object is not complete");
    glViewport(0, 0, width, height);
}

namespace {

GLuint compile(GLenum kind, const char* source, const std::string& workload) {
    GLuint shader = glCreateShader(kind);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        throw Error(workload + ": the " + (kind == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                    " shader does not compile: " + log);
    }
    return shader;
}

}  // namespace

GLuint useProgram(const char* vertex, const char* fragment, std::initializer_list<const char*> attributes,
                  const std::string& workload) {
    GLuint program = glCreateProgram();
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex, workload);
    const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment, workload);
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    GLuint location = 0;
    for (const char* name : attributes) glBindAttribLocation(program, location++, name);
    glBindFragDataLocation(program, 0, "colour");
    glLinkProgram(program);
    GLint linked = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!linked) {
        char log[4096] = {};
        glGetProgramInfoLog(program, sizeof log, nullptr, log);
        throw Error(workload + ": the program does not link: " + log);
    }
    glDeleteShader(vs);
    glDeleteShader(fs);
    glUseProgram(program);
    return program;
}

}  // namespace rg::bench::gl
