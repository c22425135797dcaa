// What every tracer shares: image size, supersampling, depth, threads, and the parallel
// pixel loop that makes the image bytes independent of the thread count.
#pragma once

#include <functional>
#include <vector>

#include "raycore/accel.h"
#include "raycore/camera.h"
#include "raycore/counters.h"

namespace rg {
class Progress;
}

namespace rg::ray {

struct RenderOptions {
    int width = 320, height = 240;
    int spp = 1;          // n: an n×n grid of samples per pixel (camera.h, samplePosition)
    int maxDepth = 8;     // interfaces a path may cross after the primary hit
    int threads = 0;      // 0: all (TBB's default); 1 runs on the calling thread only
    RenderCounters* counters = nullptr;  // optional
    Progress* progress = nullptr;        // optional: advanced by one per row
};

// Runs rowFn(y, counts) for every row y in parallel (TBB, `threads` workers). Rows are
// independent and each pixel's value depends only on (pixel, sample): any schedule gives
// the same bytes. Adds the counts and the wall time to options.counters.
void parallelRows(const RenderOptions& options,
                  const std::function<void(int y, RayCounts& counts)>& rowFn);

// The camera rays of one image row, traced ahead of shading a few pixels at a time: the
// n² samples of pixel x (sample sy·n + sx) come with the Hit and SurfacePoint that
// accel.intersectSurface gives for each (Accel::intersectSurfaces: each ray traversed
// alone, the hits resolved in groups). Pixels are asked for left to right; a pixel outside
// the chunk held traces the chunk starting there, at most kChunkRays rays (one pixel's
// samples at least), so memory stays bounded at any width and spp. Counting the rays is
// the caller's part.
class CameraRowRays {
  public:
    static constexpr size_t kChunkRays = 1024;
    CameraRowRays(const Accel& accel, const Camera& camera, const RenderOptions& options, int y);
    struct Samples {
        const Ray* rays;
        const Hit* hits;
        const SurfacePoint* points;
    };
    Samples pixel(int x);
    size_t perPixel() const { return perPixel_; }

  private:
    const Accel& accel_;
    const Camera& camera_;
    const RenderOptions& options_;
    int y_, n_;
    size_t perPixel_;
    int chunkPixels_, x0_ = 0, x1_ = 0;  // the chunk held: pixels [x0_, x1_)
    std::vector<Ray> rays_;
    std::vector<Hit> hits_;
    std::vector<SurfacePoint> points_;
};

}  // namespace rg::ray
