// 000 §4.1: compiling the outgoing rays — an intersection record per path per sample, with
// every front-facing intersection along the exit ray (continued through occluders so a
// layer can be rebuilt behind a closer one).
#include <algorithm>

#include "raycore/tracer_two_term.h"

namespace rg::ray {

std::vector<RayPathRecord> compileRayPathRecords(const Accel& accel, const Camera& camera,
                                                 const RenderOptions& o) {
    std::vector<std::vector<RayPathRecord>> rows(size_t(o.height));
    const int n = std::max(1, o.spp);
    parallelRows(o, [&](int y, RayCounts& counts) {
        auto& row = rows[size_t(y)];
        for (int x = 0; x < o.width; ++x)
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    glm::vec2 f = samplePosition(x, y, sx, sy, n);
                    Ray ray = primaryRay(camera, o.width, o.height, f.x, f.y);
                    counts.add(RayKind::Primary);
                    TwoTermSample s = traceTwoTerm(accel, ray, o.maxDepth, counts);
                    const RayPath* paths[2] = {&s.reflect, &s.refract};
                    for (int term = 0; term < 2; ++term) {
                        if (!paths[term]->valid) continue;
                        RayPathRecord rec;
                        rec.x = x;
                        rec.y = y;
                        rec.sx = sx;
                        rec.sy = sy;
                        rec.term = term;
                        rec.path = *paths[term];
                        counts.add(RayKind::Continuation);
                        rec.exitIntersections = accel.allIntersections(rec.path.exitRay, true);
                        row.push_back(std::move(rec));
                    }
                }
    });
    // Concatenate in row order: the record order is fixed whatever the thread schedule.
    std::vector<RayPathRecord> all;
    for (auto& r : rows)
        for (auto& rec : r) all.push_back(std::move(rec));
    return all;
}

}  // namespace rg::ray
