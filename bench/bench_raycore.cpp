// raycore benchmarks: Mrays/s of our ray casting path (rg::ray::Accel: ray set-up, Embree
// traversal, hit resolved to a SurfacePoint — what every tracer does per ray; single rays
// each traversed alone and resolved 16 at a time, Accel::intersectSurfaces; packets and
// streams resolve their hits as a batch: Accel::surfaces, Accel::intersectStreamSurfaces)
// beside a bare Embree loop on the very same rays with no shading, in the same run.
// Names follow bench/harness.h: <workload>/<retroglass|embree>/<layout>/threads:N, with
//   workload  primary_coherent      camera rays of the teapot-in-room scene (640×480, view 0
//                                   of the "circle" path; packets are 4×2 / 4×4 pixel tiles)
//             secondary_incoherent  one bounce from every primary hit in a direction hashed
//                                   from the pixel (uniform over the hemisphere), so
//                                   neighbouring rays share nothing
//   layout    single (rtcIntersect1), packet8 (rtcIntersect8), packet16 (rtcIntersect16),
//             stream (rtcIntersect1M over the 256 rays of a chunk, flagged coherent for
//             primary and incoherent for secondary rays)
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "harness.h"
#include "raycore/accel.h"
#include "raycore/builtin_scenes.h"

namespace rg::bench {
namespace {

using rg::ray::Accel;
using rg::ray::Hit;
using rg::ray::Ray;

constexpr int kWidth = 640, kHeight = 480;

struct Fixture {
    rg::ray::Scene scene;
    std::unique_ptr<Accel> accel;
    std::vector<Ray> primary;    // tile order: 4×4 tiles, row-major inside a tile
    std::vector<Ray> secondary;  // one per primary hit
};

uint32_t hash32(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

const Fixture& fixture() {
    static const std::unique_ptr<Fixture> f = [] {
        auto fx = std::make_unique<Fixture>();
        fx->scene = rg::ray::makeBuiltinScene("teapot-in-room");  // 40,000-triangle teapot
        fx->accel = std::make_unique<Accel>(fx->scene);
        const rg::ray::Camera cam = fx->scene.viewpointPaths[0].at(0);
        // 4×4 tiles in tile order: a packet of 16 is one tile, a packet of 8 half of one.
        for (int ty = 0; ty < kHeight; ty += 4)
            for (int tx = 0; tx < kWidth; tx += 4)
                for (int y = ty; y < ty + 4; ++y)
                    for (int x = tx; x < tx + 4; ++x)
                        fx->primary.push_back(rg::ray::primaryRay(cam, kWidth, kHeight, x + 0.5f, y + 0.5f));
        for (size_t i = 0; i < fx->primary.size(); ++i) {
            const Ray& r = fx->primary[i];
            Hit h = fx->accel->intersect(r);
            if (!h.valid()) continue;
            rg::ray::SurfacePoint s = fx->accel->surface(r, h);
            glm::vec3 n = s.frontFace ? s.ng : -s.ng;
            // Uniform direction on the hemisphere around n from two hashed numbers.
            float u1 = float(hash32(uint32_t(i) * 2u) >> 8) / 16777216.0f;
            float u2 = float(hash32(uint32_t(i) * 2u + 1u) >> 8) / 16777216.0f;
            float z = u1, rr = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 6.2831853f * u2;
            glm::vec3 t = std::abs(n.x) > 0.5f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
            glm::vec3 b1 = glm::normalize(glm::cross(n, t)), b2 = glm::cross(n, b1);
            Ray sr;
            sr.dir = glm::normalize(rr * std::cos(phi) * b1 + rr * std::sin(phi) * b2 + z * n);
            sr.origin = fx->accel->offsetOrigin(s, sr.dir);
            fx->secondary.push_back(sr);
        }
        // Whole packets only.
        fx->secondary.resize(fx->secondary.size() / 16 * 16);
        return fx;
    }();
    return *f;
}

enum class Layout { Single, Packet8, Packet16, Stream };

// Splits [0, n) into packet-aligned chunks over `threads` TBB workers (n is a multiple
// of 16, so packets never run past the end).
template <class F>
void forChunks(size_t n, int threads, F&& f) {
    tbb::task_arena arena(threads);
    arena.execute([&] {
        // Chunks of 256 rays (a multiple of every packet width); f sees one chunk at a time.
        tbb::parallel_for(tbb::blocked_range<size_t>(0, (n + 255) / 256), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t c = r.begin(); c != r.end(); ++c) f(c * 256, std::min(n, (c + 1) * 256));
        });
    });
}

// Ours: Accel (the same calls the tracers make) plus resolving the hit to a surface point.
void runRetroglass(benchmark::State& state, bool secondary, Layout layout, int threads) {
    const Fixture& fx = fixture();
    const std::vector<Ray>& rays = secondary ? fx.secondary : fx.primary;
    const Accel& accel = *fx.accel;
    for (auto _ : state) {
        forChunks(rays.size(), threads, [&](size_t begin, size_t end) {
            float sink = 0.0f;
            if (layout == Layout::Single) {
                // Each ray traversed alone by rtcIntersect1 and resolved with its Hit kept
                // beside the point, in groups of 16 (Accel::intersectSurfaces), as the
                // renderers do with their camera rays (CameraRowRays). Output kept
                // per thread, as for streams.
                static thread_local std::vector<rg::ray::SurfacePoint> points(256);
                static thread_local std::vector<Hit> hits(256);
                accel.intersectSurfaces(&rays[begin], points.data(), end - begin, hits.data());
                for (size_t i = 0; i < end - begin; ++i)
                    if (hits[i].valid()) sink += points[i].ns.x;
            } else if (layout == Layout::Stream) {
                // A stream traced and its hits resolved as a batch straight from Embree's
                // records (Accel::intersectStreamSurfaces), as a tracer consuming a stream
                // would. Output kept per thread: constructing 256 points per chunk would
                // zero 18 KB.
                static thread_local std::vector<rg::ray::SurfacePoint> points(256);
                accel.intersectStreamSurfaces(&rays[begin], points.data(), end - begin, !secondary);
                for (size_t i = 0; i < end - begin; ++i)
                    if (points[i].object != rg::ray::kNoHit) sink += points[i].ns.x;
            } else {
                Hit hits[16];
                static thread_local std::vector<rg::ray::SurfacePoint> points(16);
                const int w = layout == Layout::Packet8 ? 8 : 16;
                for (size_t i = begin; i < end; i += size_t(w)) {
                    if (w == 8) accel.intersect8(&rays[i], hits, 8);
                    else accel.intersect16(&rays[i], hits, 16);
                    accel.surfaces(&rays[i], hits, points.data(), size_t(w));
                    for (int k = 0; k < w; ++k)
                        if (hits[k].valid()) sink += points[k].ns.x;
                }
            }
            benchmark::DoNotOptimize(sink);
        });
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays.size()));
    state.SetLabel(secondary ? "secondary rays, teapot-in-room" : "primary rays, teapot-in-room");
}

// The peer: Embree alone on the same rays, laid out in its own structures before timing.
void runEmbree(benchmark::State& state, bool secondary, Layout layout, int threads) {
    const Fixture& fx = fixture();
    const std::vector<Ray>& rays = secondary ? fx.secondary : fx.primary;
    RTCScene scene = fx.accel->embreeScene();
    std::vector<RTCRayHit> single(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
        RTCRayHit& rh = single[i];
        rh.ray = {rays[i].origin.x, rays[i].origin.y, rays[i].origin.z, rays[i].tnear,
                  rays[i].dir.x,    rays[i].dir.y,    rays[i].dir.z,    0.0f,
                  rays[i].tfar,     ~0u,              0u,               0u};
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    }
    for (auto _ : state) {
        forChunks(rays.size(), threads, [&](size_t begin, size_t end) {
            RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            unsigned sink = 0;
            if (layout == Layout::Stream) {
                RTCRayHit batch[256];
                std::copy(single.begin() + long(begin), single.begin() + long(end), batch);
                ctx.flags = secondary ? RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT : RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
                rtcIntersect1M(scene, &ctx, batch, unsigned(end - begin), sizeof(RTCRayHit));
                sink += batch[0].hit.geomID;
            } else if (layout == Layout::Single) {
                for (size_t i = begin; i < end; ++i) {
                    RTCRayHit rh = single[i];  // fresh tfar each iteration
                    rtcIntersect1(scene, &ctx, &rh);
                    sink += rh.hit.geomID;
                }
            } else {
                const int w = layout == Layout::Packet8 ? 8 : 16;
                alignas(64) int valid[16];
                alignas(64) RTCRayHit16 p16;
                alignas(64) RTCRayHit8 p8;
                for (int k = 0; k < 16; ++k) valid[k] = -1;
                for (size_t i = begin; i < end; i += size_t(w)) {
                    for (int k = 0; k < w; ++k) {
                        const RTCRay& r = single[i + size_t(k)].ray;
                        if (w == 8) {
                            p8.ray.org_x[k] = r.org_x; p8.ray.org_y[k] = r.org_y; p8.ray.org_z[k] = r.org_z;
                            p8.ray.dir_x[k] = r.dir_x; p8.ray.dir_y[k] = r.dir_y; p8.ray.dir_z[k] = r.dir_z;
                            p8.ray.tnear[k] = r.tnear; p8.ray.tfar[k] = r.tfar; p8.ray.time[k] = 0.0f;
                            p8.ray.mask[k] = ~0u; p8.ray.id[k] = 0; p8.ray.flags[k] = 0;
                            p8.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                        } else {
                            p16.ray.org_x[k] = r.org_x; p16.ray.org_y[k] = r.org_y; p16.ray.org_z[k] = r.org_z;
                            p16.ray.dir_x[k] = r.dir_x; p16.ray.dir_y[k] = r.dir_y; p16.ray.dir_z[k] = r.dir_z;
                            p16.ray.tnear[k] = r.tnear; p16.ray.tfar[k] = r.tfar; p16.ray.time[k] = 0.0f;
                            p16.ray.mask[k] = ~0u; p16.ray.id[k] = 0; p16.ray.flags[k] = 0;
                            p16.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                        }
                    }
                    if (w == 8) {
                        rtcIntersect8(valid, scene, &ctx, &p8);
                        sink += p8.hit.geomID[0];
                    } else {
                        rtcIntersect16(valid, scene, &ctx, &p16);
                        sink += p16.hit.geomID[0];
                    }
                }
            }
            benchmark::DoNotOptimize(sink);
        });
    }
    state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(rays.size()));
    state.SetLabel("bare Embree " RTC_VERSION_STRING);
}

// Registered once `retroglass bench` has read its thread counts (harness.h).
const bool registered = addWorkloads([](const std::vector<int>& threadCounts) {
    const struct {
        const char* name;
        bool secondary;
    } workloads[] = {{"primary_coherent", false}, {"secondary_incoherent", true}};
    const struct {
        const char* name;
        Layout layout;
    } layouts[] = {{"single", Layout::Single},
                   {"packet8", Layout::Packet8},
                   {"packet16", Layout::Packet16},
                   {"stream", Layout::Stream}};
    for (const auto& wl : workloads)
        for (const auto& lay : layouts)
            for (int t : threadCounts) {
                const std::string suffix = std::string("/") + lay.name + "/threads:" + std::to_string(t);
                const bool sec = wl.secondary;
                const Layout l = lay.layout;
                // One thread runs on the calling thread (a task_arena of one slot), so its
                // CPU time is the work's time, and on a shared machine it does not count
                // the time the process waited for a core. All threads: wall time.
                auto* ours = benchmark::RegisterBenchmark(
                    (std::string(wl.name) + "/retroglass" + suffix).c_str(),
                    [sec, l, t](benchmark::State& s) { runRetroglass(s, sec, l, t); });
                auto* peer = benchmark::RegisterBenchmark(
                    (std::string(wl.name) + "/embree" + suffix).c_str(),
                    [sec, l, t](benchmark::State& s) { runEmbree(s, sec, l, t); });
                for (auto* b : {ours, peer}) {
                    b->Unit(benchmark::kMillisecond);
                    if (t > 1) b->UseRealTime();
                }
            }
});

}  // namespace
}  // namespace rg::bench
