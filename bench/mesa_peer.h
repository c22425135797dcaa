// The Mesa llvmpipe peer: an OSMesa (fixed-function OpenGL 1.x) context in a child
// process, so that each benchmark gets the llvmpipe thread count it asks for.
//
// Why a child process: llvmpipe reads LP_NUM_THREADS once, when its screen is created,
// and OSMesa creates that screen once per process. Measuring 1 and N threads in one
// `retroglass bench` run therefore needs one process per thread count. MesaPeer forks
// before any GL call of this process (the parent never creates a context), the child sets
// LP_NUM_THREADS, creates the context, runs the caller's setup and one warm-up frame
// (shader JIT), then serves "render n frames" requests over a socket pair and reports the
// seconds it spent, each frame ending in glFinish(). The parent feeds those seconds to
// Google Benchmark as manual time, so the round trip is not charged to llvmpipe.
//
// Reusable by any module's benchmarks: pass GL 1.x setup and frame callbacks.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <string>

namespace rg::bench {

class MesaPeer {
  public:
    // Forks the child. `setup` runs once with the context current (state, arrays, ...);
    // `frame` renders one frame (the child adds glFinish). Throws std::runtime_error when
    // the child cannot create its context.
    MesaPeer(int width, int height, int threads, std::function<void()> setup,
             std::function<void()> frame);
    ~MesaPeer();  // asks the child to exit and reaps it
    MesaPeer(const MesaPeer&) = delete;
    MesaPeer& operator=(const MesaPeer&) = delete;

    // Renders `frames` frames in the child; returns the seconds it measured.
    double run(int frames);
    // GL_RENDERER of the child's context (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)").
    const std::string& renderer() const { return renderer_; }

  private:
    pid_t child_ = -1;
    int toChild_ = -1;  // our end of the socket pair to the child
    std::string renderer_;
};

// In the child, before a workload's draws: window coordinates with y down as in
// Direct3D (glOrtho(0, w, h, 0, −1, 1)), identity modelview, and depth test, culling and
// dithering off — the state every peer workload starts from.
void setupWindowOrtho(int width, int height);

}  // namespace rg::bench

namespace benchmark {
class State;
}

namespace rg::bench {

// The llvmpipe side of a paired benchmark: starts a peer child with `threads` llvmpipe
// threads, refuses (SkipWithError) anything but llvmpipe, times one frame per iteration
// and reports `itemsPerFrame` items per frame.
void runMesaBenchmark(benchmark::State& state, int width, int height, int threads,
                      std::function<void()> setup, std::function<void()> frame,
                      int64_t itemsPerFrame);

}  // namespace rg::bench
