#include "mesa_frame.h"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <exception>

#include "core/error.h"
#include "core/fd_io.h"

namespace rg::bench {

MesaImage renderMesaFrame(const std::string& workload, int width, int height, int threads, RowOrder rowOrder,
                          const std::function<void()>& draw) {
    if (threads < 1) throw Error(workload + ": renderMesa needs at least one thread");
    int fds[2];
    if (::pipe(fds) != 0) throw Error(workload + ": pipe failed");
    const size_t bytes = size_t(width) * size_t(height) * 4;
    const pid_t pid = ::fork();
    if (pid < 0) throw Error(workload + ": fork failed");
    if (pid == 0) {
        // The child answers with [u32 length][GL_RENDERER] then [u32 length][error] and,
        // when the error is empty, the image. It never returns into the caller's code.
        ::close(fds[0]);
        ::setenv("GALLIUM_DRIVER", "llvmpipe", 1);
        ::setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
        std::string renderer, error;
        std::vector<uint8_t> buffer(bytes);
        OSMesaContext ctx = nullptr;
        try {
            const int attribs[] = {OSMESA_FORMAT,  OSMESA_RGBA,           OSMESA_DEPTH_BITS, 0,
                                   OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0};
            ctx = OSMesaCreateContextAttribs(attribs, nullptr);
            if (!ctx || !OSMesaMakeCurrent(ctx, buffer.data(), GL_UNSIGNED_BYTE, width, height))
                throw Error(workload + ": cannot create an OSMesa context");
            const GLubyte* r = glGetString(GL_RENDERER);
            renderer = r ? reinterpret_cast<const char*>(r) : "unknown";
            draw();
            // The bound framebuffer (the workload's framebuffer object), window row 0 first.
            std::vector<uint8_t> rows(rowOrder == RowOrder::TopRowFirst ? bytes : 0);
            uint8_t* const read = rowOrder == RowOrder::TopRowFirst ? rows.data() : buffer.data();
            glPixelStorei(GL_PACK_ALIGNMENT, 4);
            glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, read);
            glFinish();
            if (GLenum e = glGetError(); e != GL_NO_ERROR)
                throw Error(workload + ": GL error " + std::to_string(e) + " in the draw");
            if (rowOrder == RowOrder::TopRowFirst) {
                // GL's window row 0 is the bottom row; ours is the top one.
                const size_t pitch = size_t(width) * 4;
                for (int y = 0; y < height; ++y)
                    std::memcpy(buffer.data() + size_t(y) * pitch, rows.data() + size_t(height - 1 - y) * pitch,
                                pitch);
            }
        } catch (const std::exception& e) {
            error = e.what();
        }
        bool ok = true;
        for (const std::string* s : {&renderer, &error}) {
            const uint32_t len = uint32_t(s->size());
            ok = ok && io::writeAll(fds[1], &len, sizeof len) && io::writeAll(fds[1], s->data(), len);
        }
        if (ok && error.empty()) ok = io::writeAll(fds[1], buffer.data(), bytes);
        if (ctx) OSMesaDestroyContext(ctx);
        ::_exit(ok && error.empty() ? 0 : 1);
    }
    ::close(fds[1]);
    MesaImage out;
    std::string error;
    bool ok = true;
    for (std::string* s : {&out.renderer, &error}) {
        uint32_t len = 0;
        ok = ok && io::readAll(fds[0], &len, sizeof len) && len < (1u << 16);
        if (ok) {
            s->resize(len);
            ok = io::readAll(fds[0], s->data(), len);
        }
    }
    if (ok && error.empty()) {
        out.rgba.resize(bytes);
        ok = io::readAll(fds[0], out.rgba.data(), bytes);
    }
    ::close(fds[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    if (!error.empty()) throw Error(error);
    if (!ok) throw Error(workload + ": the OSMesa child died (wait status " + std::to_string(status) + ")");
    return out;
}

}  // namespace rg::bench
