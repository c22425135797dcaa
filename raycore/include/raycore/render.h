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

// The camera rays of one image row, all samples, traced before the row is shaded: ray i
// is sample (sx, sy) of pixel x at i = x·n² + sy·n + sx, and hits[i] / points[i] are what
// accel.intersectSurface(rays[i], hit) gives (Accel::intersectSurfaces: each ray
// traversed alone, the hits resolved in groups). Counting them is the caller's part.
struct CameraRow {
    size_t perPixel = 1;  // n²
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    std::vector<SurfacePoint> points;
};
CameraRow traceCameraRow(const Accel& accel, const Camera& camera, const RenderOptions& options, int y);

}  // namespace rg::ray
