// 000 §4.1: compiling the outgoing rays — an intersection record per path per sample, with
// every front-facing intersection along the exit ray (continued through occluders so a
// layer can be rebuilt behind a closer one).
#include <algorithm>
#include <limits>

#include "raycore/tracer_whitted.h"

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

namespace rg::ray {

namespace {

// The first hit of the incoming ray on `lens`, continued through other objects when
// `through` (Figure 4b). False when it never reaches it.
bool reachLens(const Accel& accel, Ray ray, uint32_t lens, bool through, Hit& hit,
               SurfacePoint& s, bool& occluded, RayCounts& counts) {
    occluded = false;
    for (int k = 0; k < 64; ++k) {
        s = accel.intersectSurface(ray, hit);
        if (!hit.valid()) return false;
        if (hit.object == lens) return true;
        if (!through) return false;
        occluded = true;
        counts.add(RayKind::Continuation);
        ray.tnear = hit.t + accel.epsilon() * (1.0f + hit.t);
    }
    return false;
}

}  // namespace

void compileLensRecords(const Accel& accel, const Camera& camera, const RenderOptions& o,
                        const LensRecordOptions& lens,
                        const std::function<void(const LensRecordRow&)>& rowSink) {
    const int n = std::max(1, o.spp);
    const bool shade = !lens.layerOfObject.empty();
    const Scene& scene = accel.scene();
    auto layerOf = [&](uint32_t object) {
        if (object == kNoHit) return shade ? int(lens.layerOfObject.back()) : -1;
        return object < lens.layerOfObject.size() ? lens.layerOfObject[object] : -1;
    };
    parallelRows(o, [&](int y, RayCounts& counts) {
        LensRecordRow row;
        row.y = y;
        std::vector<Hit> along;
        for (int x = 0; x < o.width; ++x)
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    const glm::vec2 f = samplePosition(x, y, sx, sy, n);
                    const Ray ray = primaryRay(camera, o.width, o.height, f.x, f.y);
                    counts.add(RayKind::Primary);
                    Hit hit;
                    SurfacePoint s;
                    LensSampleRecord rec;
                    if (!reachLens(accel, ray, lens.lensObject, lens.incomingContinuation, hit, s,
                                   rec.occluded, counts))
                        continue;
                    if (s.material->type == MaterialType::Diffuse) continue;
                    rec.x = x;
                    rec.sx = sx;
                    rec.sy = sy;
                    RayPath paths[2];
                    traceLensHit(accel, ray, hit, s, o.maxDepth, false, counts, paths[0], paths[1]);
                    for (int term = 0; term < 2; ++term) {
                        const RayPath& p = paths[term];
                        rec.path[term] = summarise(p);
                        rec.firstHit[term] = uint32_t(row.hits.size());
                        if (!p.valid) continue;
                        along.clear();
                        if (lens.outgoingContinuation) {
                            counts.add(RayKind::Continuation);
                            for (const Hit& h : accel.allIntersections(p.exitRay, true))
                                if (h.object != lens.lensObject) along.push_back(h);
                        } else if (p.exitHit.valid()) {
                            along.push_back(p.exitHit);
                        }
                        const int depth = int(p.events.size());
                        uint64_t seenLayers = 0;
                        auto add = [&](const Hit& h) {
                            LensHit lh;
                            lh.object = h.valid() ? h.object : kNoHit;
                            lh.layer = layerOf(lh.object);
                            if (shade) {
                                if (lh.layer < 0 || lh.layer >= 64 ||
                                    (seenLayers >> lh.layer) & 1u)
                                    return;
                                seenLayers |= uint64_t(1) << lh.layer;
                            }
                            lh.t = h.valid() ? h.t : std::numeric_limits<float>::infinity();
                            lh.p = h.valid() ? p.exitRay.origin + h.t * p.exitRay.dir
                                             : glm::vec3(0.0f);
                            if (shade)
                                lh.color = h.valid() ? whittedShade(accel, p.exitRay, h, depth,
                                                                    o.maxDepth, counts)
                                                     : scene.environment.lookup(p.exitRay.dir);
                            row.hits.push_back(lh);
                        };
                        for (const Hit& h : along) add(h);
                        if (along.empty()) add(Hit());
                        rec.hitCount[term] = uint32_t(row.hits.size()) - rec.firstHit[term];
                    }
                    row.samples.push_back(rec);
                }
        rowSink(row);
    });
}

}  // namespace rg::ray
