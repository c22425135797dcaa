#include "mesa_peer.h"

#include <GL/gl.h>
#include <GL/osmesa.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace rg::bench {

namespace {

bool writeAll(int fd, const void* data, size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
        // send() with MSG_NOSIGNAL: a dead peer is an error here, not a SIGPIPE.
        ssize_t n = ::send(fd, p, size, MSG_NOSIGNAL);
        if (n <= 0) return false;
        p += n;
        size -= size_t(n);
    }
    return true;
}

bool readAll(int fd, void* data, size_t size) {
    char* p = static_cast<char*>(data);
    while (size > 0) {
        ssize_t n = ::read(fd, p, size);
        if (n <= 0) return false;
        p += n;
        size -= size_t(n);
    }
    return true;
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
        setup();
        frame();  // warm-up: llvmpipe compiles its shaders on first use
        glFinish();
    }
    uint32_t len = uint32_t(renderer.size());
    writeAll(out, &len, sizeof len);
    writeAll(out, renderer.data(), len);
    if (renderer.empty()) ::_exit(1);
    int32_t frames;
    while (readAll(in, &frames, sizeof frames) && frames > 0) {
        auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < frames; ++i) {
            frame();
            glFinish();
        }
        double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (!writeAll(out, &seconds, sizeof seconds)) break;
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
    if (!readAll(toChild_, &len, sizeof len) || len == 0 || len > 4096) {
        ::close(toChild_);
        ::waitpid(child_, nullptr, 0);
        throw std::runtime_error("MesaPeer: the child could not create an OSMesa context");
    }
    renderer_.resize(len);
    readAll(toChild_, renderer_.data(), len);
}

MesaPeer::~MesaPeer() {
    int32_t stop = 0;
    if (toChild_ >= 0) {
        writeAll(toChild_, &stop, sizeof stop);
        ::close(toChild_);
    }
    if (child_ > 0) ::waitpid(child_, nullptr, 0);
}

double MesaPeer::run(int frames) {
    int32_t n = frames;
    double seconds = -1.0;
    if (!writeAll(toChild_, &n, sizeof n) || !readAll(toChild_, &seconds, sizeof seconds))
        throw std::runtime_error("MesaPeer: the child stopped answering");
    return seconds;
}

}  // namespace rg::bench
