#include "pem_precompute.h"

#include <algorithm>
#include <chrono>

#include <sys/resource.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "raycore/counters.h"
#include "raycore/tracer_whitted.h"
#include "texunit/cube_mapping.h"

namespace rg::pem {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

// User + system time of the whole process: on a shared machine the wall clock says more
// about the neighbours than about the work.
double processCpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

float clamp01(float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; }

// Keeps the rows of `m` whose pixel satisfies `keep`, with right-hand sides from `value`.
RenderingMatrix selectRows(const RenderingMatrix& m, const std::function<bool(int32_t)>& keep) {
    RenderingMatrix out;
    out.layout = m.layout;
    out.width = m.width;
    out.height = m.height;
    std::vector<Eigen::Triplet<double>> trip;
    using It = Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator;
    for (size_t r = 0; r < m.rowPixel.size(); ++r) {
        if (!keep(m.rowPixel[r])) continue;
        int nr = int(out.rowPixel.size());
        out.rowPixel.push_back(m.rowPixel[r]);
        for (It it(m.A, int(r)); it; ++it) trip.emplace_back(nr, int(it.col()), it.value());
    }
    out.A.resize(int64_t(out.rowPixel.size()), m.layout.count());
    out.A.setFromTriplets(trip.begin(), trip.end());
    return out;
}

// One channel to solve: rows of `m`, b from `value(pixel)`, result into texel channel `ch`.
struct SolveJob {
    const RenderingMatrix* m;
    std::function<float(int32_t)> value;
    MapTexels* out;
    int channel;
    InferenceStats stats;
};

}  // namespace

ray::PemLayerImages traceLayers(const ray::Accel& accel, const PemScene& scene,
                                const ray::Camera& camera, const PemSettings& settings) {
    ray::RenderOptions ro;
    ro.width = settings.width;
    ro.height = settings.height;
    ro.spp = settings.spp;
    ro.threads = settings.threads;
    std::vector<ray::Segment> segments;
    for (const PemPart& p : scene.parts) segments.push_back(p.segment);
    ray::PemLayerOptions lo;
    lo.localScope = ray::LocalScope::Object;  // the lid in the body is a self-reflection
    return ray::renderPemLayers(accel, camera, ro, segments, lo);
}

void groundTruthOf(const ray::PemLayerImages& layers, ray::Image& rgb, ray::Image& coverage) {
    const auto& first = layers.segments.at(0);
    rgb = ray::Image(first.coverage.width, first.coverage.height, 3);
    coverage = ray::Image(first.coverage.width, first.coverage.height, 1);
    for (const auto& s : layers.segments) {
        ray::Image c = s.composite();
        for (size_t i = 0; i < rgb.pixels.size(); ++i) rgb.pixels[i] += c.pixels[i];
        for (size_t i = 0; i < coverage.pixels.size(); ++i) coverage.pixels[i] += s.coverage.pixels[i];
    }
}

ViewSample precomputeView(const ray::Accel& accel, PemRenderer& renderer, int view,
                          const ray::Camera& camera, int emSize, const PemSettings& settings,
                          bool baselines) {
    ViewSample vs;
    vs.view = view;
    const PemScene& scene = renderer.scene();
    raster::Device& device = renderer.device();

    // ---- segmented ray tracing (001 §3, Figure 4) ---------------------------------------
    auto t0 = Clock::now();
    vs.layers = traceLayers(accel, scene, camera, settings);
    groundTruthOf(vs.layers, vs.groundTruth, vs.coverage);
    vs.raytraceSeconds = secondsSince(t0);

    // ---- inference per part and layer (001 §4) -------------------------------------------
    // The PEM's own maps (distant, local) first — their time is the paper's "EM inference"
    // per view — then, when asked, the baselines' maps (single EM, PTM).
    const int W = settings.width;
    const ray::Image& segId = vs.layers.segmentId;
    vs.parts.resize(scene.parts.size());
    struct PartProblems {
        RenderingMatrix mD, mLa, mLc, mI, mP;
    };
    std::vector<PartProblems> problems(scene.parts.size());
    auto at = [W](const ray::Image& im, int32_t px, int c) { return im.at(px % W, px / W, c); };
    auto runJobs = [&](std::vector<SolveJob>& jobs,
                       const std::vector<const RenderingMatrix*>& matrices) {
        // One system per distinct matrix, its channels solved together (one pass over the
        // matrix per step serves them all, on every core: inference.cpp); the systems are
        // built and solved side by side too. Each result depends only on its own inputs, so
        // the bytes cannot change with the thread count.
        tbb::task_arena arena(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic);
        arena.execute([&] {
            tbb::parallel_for(size_t(0), matrices.size(), [&](size_t si) {
                const InferenceSystem system(*matrices[si], settings.inference);
                std::vector<SolveJob*> mine;
                std::vector<std::vector<Eigen::VectorXd>> bs;
                for (SolveJob& job : jobs) {
                    if (job.m != matrices[si]) continue;
                    Eigen::VectorXd b(int64_t(job.m->rowPixel.size()));
                    for (size_t r = 0; r < job.m->rowPixel.size(); ++r)
                        b[int64_t(r)] = job.value(job.m->rowPixel[r]);
                    mine.push_back(&job);
                    bs.push_back({std::move(b)});
                }
                std::vector<InferenceStats> stats;
                const std::vector<Eigen::VectorXd> xs = system.solveChannels(bs, &stats);
                for (size_t k = 0; k < mine.size(); ++k) {
                    SolveJob& job = *mine[k];
                    job.stats = stats[k];
                    for (int64_t i = 0; i < xs[k].size(); ++i) {
                        uint8_t v = ray::quantize8(float(xs[k][i]));
                        Rgba8& t = job.out->texels[size_t(i)];
                        (job.channel == 0 ? t.r : job.channel == 1 ? t.g : job.channel == 2 ? t.b : t.a) = v;
                    }
                }
            });
        });
        for (const SolveJob& j : jobs) vs.stats.push_back(j.stats);
    };
    auto init = [](MapTexels& m, const TexelLayout& layout, uint8_t alphaFill) {
        m.layout = layout;
        m.texels.assign(size_t(layout.count()), Rgba8{0, 0, 0, alphaFill});
    };

    for (int stage = 0; stage < (baselines ? 2 : 1); ++stage) {
        auto ts = Clock::now();
        const double cpu0 = processCpuSeconds();
        std::vector<SolveJob> jobs;
        std::vector<const RenderingMatrix*> matrices;
        for (size_t p = 0; p < scene.parts.size(); ++p) {
            const ray::PemLayers& L = vs.layers.segments[p];
            PartProblems& P = problems[p];
            PartMaps& maps = vs.parts[p];
            auto inPart = [&segId, p](int32_t px) { return int(segId.pixels[size_t(px)]) == int(p); };
            auto alpha = [&, p](int32_t px) {
                return clamp01(at(vs.layers.segments[p].localAlpha, px, 0));
            };
            auto incident = [&, p, alpha](int32_t px, int c) {
                const ray::PemLayers& l = vs.layers.segments[p];
                float a = alpha(px);
                return clamp01(a * at(l.localColor, px, c) + (1.0f - a) * at(l.distant, px, c));
            };
            if (stage == 0) {
                P.mD = selectRows(buildMatrixByInstrumentedPass(device, renderer, camera, p,
                                                                EmLayer::Distant, emSize),
                                  inPart);
                RenderingMatrix mL = buildMatrixByInstrumentedPass(device, renderer, camera, p,
                                                                   EmLayer::Local, emSize);
                P.mLa = selectRows(mL, inPart);
                // Colour of the local layer only where some samples were local: elsewhere
                // α = 0 hides it and it must not pull the solution towards black.
                P.mLc = selectRows(mL, [&](int32_t px) {
                    return inPart(px) && alpha(px) > 0.5f / 255.0f;
                });
                init(maps.distant, P.mD.layout, 255);
                init(maps.local, P.mLa.layout, 0);
                matrices.insert(matrices.end(), {&P.mD, &P.mLa, &P.mLc});
                for (int c = 0; c < 3; ++c) {
                    jobs.push_back({&P.mD, [&L, at, c](int32_t px) { return clamp01(at(L.distant, px, c)); },
                                    &maps.distant, c, {}});
                    jobs.push_back({&P.mLc, [&L, at, c](int32_t px) { return clamp01(at(L.localColor, px, c)); },
                                    &maps.local, c, {}});
                }
                jobs.push_back({&P.mLa, alpha, &maps.local, 3, {}});
            } else {
                P.mI = selectRows(buildMatrixByInstrumentedPass(device, renderer, camera, p,
                                                                EmLayer::Infinite, emSize),
                                  inPart);
                P.mP = selectRows(buildMatrixByInstrumentedPass(device, renderer, camera, p,
                                                                EmLayer::Ptm, settings.ptmSize),
                                  inPart);
                init(maps.infinite, P.mI.layout, 255);
                init(maps.ptm, P.mP.layout, 255);
                matrices.insert(matrices.end(), {&P.mI, &P.mP});
                for (int c = 0; c < 3; ++c) {
                    jobs.push_back({&P.mI, [incident, c](int32_t px) { return incident(px, c); },
                                    &maps.infinite, c, {}});
                    jobs.push_back({&P.mP, [incident, c](int32_t px) { return incident(px, c); },
                                    &maps.ptm, c, {}});
                }
            }
        }
        runJobs(jobs, matrices);
        (stage == 0 ? vs.inferenceSeconds : vs.baselineSeconds) = secondsSince(ts);
        if (stage == 0) vs.inferenceCpuSeconds = processCpuSeconds() - cpu0;
    }
    return vs;
}

MapTexels traceStaticEm(const ray::Accel& accel, const PemScene& scene, int size,
                        const PemSettings& settings) {
    // The object's centre: area-weighted centroid over all its parts.
    ray::Mesh world = scene.scene.worldMesh(uint32_t(scene.object));
    glm::vec3 origin = areaWeightedCentroid(world.positions, world.indices);
    MapTexels map;
    map.layout = TexelLayout{size, 6};
    map.texels.assign(size_t(map.layout.count()), Rgba8{0, 0, 0, 255});
    std::vector<glm::vec3> level0(size_t(6) * size * size);
    const int n = 2;  // 2×2 samples per texel
    tbb::parallel_for(0, 6 * size, [&](int row) {
        int face = row / size, y = row % size;
        ray::RayCounts counts;
        for (int x = 0; x < size; ++x) {
            glm::vec3 sum(0.0f);
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    float s = (x + (sx + 0.5f) / n) / size, t = (y + (sy + 0.5f) / n) / size;
                    glm::vec3 d = glm::normalize(tex::cubeFaceDirection(tex::CubeFace(face), s, t));
                    ray::Ray r{origin, d, 0.0f, 1e30f};
                    ray::Hit hit;
                    // The object is left out of a static EM: continue through it.
                    for (int k = 0; k < 64; ++k) {
                        hit = accel.intersect(r);
                        if (!hit.valid() || hit.object != uint32_t(scene.object)) break;
                        r.tnear = hit.t + accel.epsilon();
                    }
                    sum += ray::whittedShade(accel, r, hit, 1, 8, counts);
                }
            level0[(size_t(face) * size + y) * size + x] = sum / float(n * n);
        }
    });
    // Box-filtered MIPMAPs in linear float, quantized per level.
    std::vector<glm::vec3> cur = level0;
    for (int l = 0; l < map.layout.levels(); ++l) {
        int s = map.layout.levelSize(l);
        for (int f = 0; f < 6; ++f)
            for (int y = 0; y < s; ++y)
                for (int x = 0; x < s; ++x) {
                    glm::vec3 c = cur[(size_t(f) * s + y) * s + x];
                    map.texels[size_t(map.layout.index(l, f, x, y))] = {
                        ray::quantize8(c.r), ray::quantize8(c.g), ray::quantize8(c.b), 255};
                }
        if (s == 1) break;
        int h = s / 2;
        std::vector<glm::vec3> next(size_t(6) * h * h);
        for (int f = 0; f < 6; ++f)
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < h; ++x) {
                    auto at = [&](int xx, int yy) { return cur[(size_t(f) * s + yy) * s + xx]; };
                    next[(size_t(f) * h + y) * h + x] =
                        (at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) +
                         at(2 * x + 1, 2 * y + 1)) * 0.25f;
                }
        cur = std::move(next);
    }
    return map;
}

std::shared_ptr<const tex::Texture> uploadMap(PemRenderer& renderer, const MapTexels& map) {
    return makeMapFromTexels(renderer.memory(), map.layout,
                             [&](int64_t i) { return map.texels[size_t(i)]; });
}

PemSample uploadSample(PemRenderer& renderer, const ViewSample& sample, EmMode mode) {
    PemSample s;
    for (const PartMaps& p : sample.parts) {
        switch (mode) {
            case EmMode::Layered:
                s.local.push_back(uploadMap(renderer, p.local));
                s.distant.push_back(uploadMap(renderer, p.distant));
                break;
            case EmMode::SingleInfinite: s.distant.push_back(uploadMap(renderer, p.infinite)); break;
            case EmMode::Ptm: s.ptm.push_back(uploadMap(renderer, p.ptm)); break;
            case EmMode::Static: throw Error("PEM: the static EM is not a per-view sample");
        }
    }
    return s;
}

}  // namespace rg::pem
