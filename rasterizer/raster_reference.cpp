// The reference rasterizer: one thread, every triangle in submission order, every 2×2
// quad of its box, coverage by evaluating the three edge functions at each pixel centre
// (docs/hardware.md, "Setup and rasterization"). The fast path (raster_tiles.cpp) must
// produce the same bytes; tests/rasterizer/test_paths_agree.cpp checks that it does.
#include "fragment_quad.h"

namespace rg::raster::detail {

void rasterizeReference(const DrawContext& dc, const std::vector<SetupTriangle>& tris,
                        const std::vector<Plane>& texPool, RasterCounters& rc) {
    const int s = dc.subpixelBits;
    const int64_t half = int64_t{1} << (s - 1);
    for (const SetupTriangle& t : tris) {
        tex::FragmentQuad fragment;  // reused by the triangle's quads (fragment_quad.h)
        for (int qy = t.minY & ~1; qy <= t.maxY; qy += 2)
            for (int qx = t.minX & ~1; qx <= t.maxX; qx += 2) {
                unsigned coverage = 0;
                for (int i = 0; i < 4; ++i) {
                    int px = qx + (i & 1), py = qy + (i >> 1);
                    if (px < t.minX || px > t.maxX || py < t.minY || py > t.maxY) continue;
                    int64_t X = (int64_t(px) << s) + half, Y = (int64_t(py) << s) + half;
                    bool inside = true;
                    for (int e = 0; e < 3; ++e)
                        inside = inside && t.C[e] + t.A[e] * X + t.B[e] * Y >= 0;
                    if (inside) coverage |= 1u << i;
                }
                if (coverage) processQuad<false, false, false, false>(dc, t, texPool.data(), qx, qy, coverage, rc,
                                                        &fragment);
            }
    }
}

}  // namespace rg::raster::detail
