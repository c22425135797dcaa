#include "mesa_peer.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/fd_io.h"

namespace rg::bench {

namespace {

// The frames go to a framebuffer object (an RGBA8 colour texture and a 24-bit depth
// renderbuffer, the formats of our side), as an application rendering off screen would
// draw: OSMesa's window buffer would add a copy of the whole image into the caller's
// memory at every glFinish, which is not rendering and would be charged to llvmpipe.
// Returns false when the context cannot make a complete one.
bool bindOffscreenTarget(int width, int height) {
    GLuint colour = 0, depth = 0, fbo = 0;
    glGenTextures(1, &colour);
    glBindTexture(GL_TEXTURE_2D, colour);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE &&
           glGetError() == GL_NO_ERROR;
}

// The child: never returns.
[[noreturn]] void serve(int in, int out, int width, int height, int threads,
                        const std::function<void()>& setup, const std::function<void()>& frame) {
    ::setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
    ::setenv("GALLIUM_DRIVER", "llvmpipe", 1);
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                           OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0};
    OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
    std::vector<uint8_t> buffer(size_t(width) * size_t(height) * 4);
    std::string renderer;
    if (ctx && OSMesaMakeCurrent(ctx, buffer.data(), GL_UNSIGNED_BYTE, width, height)) {
        const GLubyte* r = glGetString(GL_RENDERER);
        renderer = r ? reinterpret_cast<const char*>(r) : "unknown";
        if (bindOffscreenTarget(width, height)) {
            setup();
            frame();  // warm-up: llvmpipe compiles its shaders on first use
            glFinish();
        } else {
            renderer.clear();  // the parent reports it
        }
    }
    uint32_t len = uint32_t(renderer.size());
    io::writeAll(out, &len, sizeof len);
    io::writeAll(out, renderer.data(), len);
    if (renderer.empty()) ::_exit(1);
    int32_t frames;
    while (io::readAll(in, &frames, sizeof frames) && frames > 0) {
        auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < frames; ++i) {
            frame();
            glFinish();
        }
        double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!io::writeAll(out, &seconds, sizeof seconds)) break;
    }
    OSMesaDestroyContext(ctx);
    ::_exit(0);
}

}  // namespace

MesaPeer::MesaPeer(int width, int height, int threads, std::function<void()> setup,
                   std::function<void()> frame) {
    int sv[2];
    if (::socketpair(AF_UNIX, SOCK_STREAM, 0, sv) != 0)
        throw std::runtime_error("MesaPeer: socketpair failed");
    pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error("MesaPeer: fork failed");
    if (pid == 0) {
        ::close(sv[0]);
        serve(sv[1], sv[1], width, height, threads, setup, frame);
    }
    ::close(sv[1]);
    child_ = pid;
    toChild_ = sv[0];
    uint32_t len = 0;
    if (!io::readAll(toChild_, &len, sizeof len) || len == 0 || len > 4096) {
        ::close(toChild_);
        ::waitpid(child_, nullptr, 0);
        throw std::runtime_error("MesaPeer: the child could not create an OSMesa context with an RGBA8 + depth24 framebuffer object");
    }
    renderer_.resize(len);
    io::readAll(toChild_, renderer_.data(), len);
}

MesaPeer::~MesaPeer() {
    int32_t stop = 0;
    if (toChild_ >= 0) {
        io::writeAll(toChild_, &stop, sizeof stop);
        ::close(toChild_);
    }
    if (child_ > 0) ::waitpid(child_, nullptr, 0);
}

double MesaPeer::run(int frames) {
    int32_t n = frames;
    double seconds = -1.0;
    if (!io::writeAll(toChild_, &n, sizeof n) || !io::readAll(toChild_, &seconds, sizeof seconds))
        throw std::runtime_error("MesaPeer: the child stopped answering");
    return seconds;
}

void setupWindowOrtho(int width, int height) {
    glViewport(0, 0, width, height);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glOrtho(0, width, height, 0, -1, 1);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_DITHER);
}

void runMesaBenchmark(benchmark::State& state, int width, int height, int threads,
                      std::function<void()> setup, std::function<void()> frame,
                      int64_t itemsPerFrame) {
    std::unique_ptr<MesaPeer> peer;
    try {
        peer = std::make_unique<MesaPeer>(width, height, threads, std::move(setup), std::move(frame));
    } catch (const std::exception& e) {
        state.SkipWithError(e.what());
        return;
    }
    if (peer->renderer().find("llvmpipe") == std::string::npos) {
        state.SkipWithError(("the OSMesa renderer is '" + peer->renderer() + "', not llvmpipe").c_str());
        return;
    }
    for (auto _ : state) state.SetIterationTime(peer->run(1));
    state.SetItemsProcessed(state.iterations() * itemsPerFrame);
    state.SetLabel(peer->renderer());
}

}  // namespace rg::bench
