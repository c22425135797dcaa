// The parallel row loop shared by the tracers.
#include "raycore/render.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>

#include "core/progress.h"

namespace rg::ray {

void parallelRows(const RenderOptions& options,
                  const std::function<void(int y, RayCounts& counts)>& rowFn) {
    auto start = std::chrono::steady_clock::now();
    auto body = [&](const tbb::blocked_range<int>& range) {
        for (int y = range.begin(); y != range.end(); ++y) {
            RayCounts counts;
            rowFn(y, counts);
            if (options.counters) options.counters->add(counts);
            if (options.progress) options.progress->advance(1);
        }
    };
    if (options.threads == 1) {
        body(tbb::blocked_range<int>(0, options.height));
    } else {
        // One row per task: rows cost very different amounts (a row through the teapot
        // versus a row of wall), so fine grains balance; the result does not depend on it.
        tbb::task_arena arena(options.threads > 0 ? options.threads
                                                  : tbb::task_arena::automatic);
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<int>(0, options.height, 1), body);
        });
    }
    if (options.counters)
        options.counters->seconds +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

CameraRowRays::CameraRowRays(const Accel& accel, const Camera& camera, const RenderOptions& o, int y)
    : accel_(accel), camera_(camera), options_(o), y_(y), n_(std::max(1, o.spp)),
      perPixel_(size_t(n_) * size_t(n_)),
      chunkPixels_(int(std::max<size_t>(1, kChunkRays / perPixel_))) {
    const size_t capacity = size_t(std::min(chunkPixels_, std::max(1, o.width))) * perPixel_;
    rays_.resize(capacity);
    hits_.resize(capacity);
    points_.resize(capacity);
}

CameraRowRays::Samples CameraRowRays::pixel(int x) {
    if (x < x0_ || x >= x1_) {
        x0_ = x;
        x1_ = std::min(options_.width, x + chunkPixels_);
        for (int px = x0_; px < x1_; ++px)
            for (int sy = 0; sy < n_; ++sy)
                for (int sx = 0; sx < n_; ++sx) {
                    const glm::vec2 f = samplePosition(px, y_, sx, sy, n_);
                    rays_[size_t(px - x0_) * perPixel_ + size_t(sy * n_ + sx)] =
                        primaryRay(camera_, options_.width, options_.height, f.x, f.y);
                }
        accel_.intersectSurfaces(rays_.data(), points_.data(), size_t(x1_ - x0_) * perPixel_, hits_.data());
    }
    const size_t first = size_t(x - x0_) * perPixel_;
    return {rays_.data() + first, hits_.data() + first, points_.data() + first};
}

}  // namespace rg::ray
