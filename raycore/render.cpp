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

CameraRow traceCameraRow(const Accel& accel, const Camera& camera, const RenderOptions& o, int y) {
    const int n = std::max(1, o.spp);
    CameraRow row;
    row.perPixel = size_t(n) * size_t(n);
    const size_t count = size_t(o.width) * row.perPixel;
    row.rays.resize(count);
    row.hits.resize(count);
    row.points.resize(count);
    for (int x = 0; x < o.width; ++x)
        for (int sy = 0; sy < n; ++sy)
            for (int sx = 0; sx < n; ++sx) {
                const glm::vec2 f = samplePosition(x, y, sx, sy, n);
                row.rays[size_t(x) * row.perPixel + size_t(sy * n + sx)] =
                    primaryRay(camera, o.width, o.height, f.x, f.y);
            }
    accel.intersectSurfaces(row.rays.data(), row.points.data(), count, row.hits.data());
    return row;
}

}  // namespace rg::ray
