#include "hybrid_precompute.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "raycore/tracer_two_term.h"

namespace rg::hybrid {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}
float clamp01(float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; }
}  // namespace

// ---- the clustering pass ------------------------------------------------------------------

ClusterPass clusterPass(const LensScene& scene, size_t lens, const std::vector<ray::Camera>& views,
                        const PrecomputeSettings& S) {
    const LensObject& L = scene.objects().at(lens);
    const uint32_t objectCount = uint32_t(scene.scene().objects.size());
    ClusterPass out;
    ray::RenderOptions ro;
    ro.width = S.clusterWidth;
    ro.height = S.clusterHeight;
    ro.spp = 1;
    ro.maxDepth = S.maxDepth;
    ro.threads = S.threads;
    ray::LensRecordOptions lo;
    lo.lensObject = L.object;
    for (const ray::Camera& cam : views) {
        std::vector<ray::LensRecordRow> rows(size_t(ro.height));
        ray::compileLensRecords(scene.accel(), cam, ro, lo,
                                [&](const ray::LensRecordRow& r) { rows[size_t(r.y)] = r; });
        // In row order, so the record order (and the rays' numbering) is fixed.
        uint32_t ray = uint32_t(out.records.empty() ? 0 : out.records.back().ray + 1);
        for (const ray::LensRecordRow& row : rows)
            for (const ray::LensSampleRecord& s : row.samples) {
                ++out.samples;
                for (int term = 0; term < 2; ++term) {
                    if (!s.path[term].valid) continue;
                    const ray::Ray& exit = s.path[term].exitRay;
                    for (uint32_t h = 0; h < s.hitCount[term]; ++h) {
                        const ray::LensHit& hit = row.hits[s.firstHit[term] + h];
                        ClusterRecord c;
                        c.ray = ray;
                        if (hit.object == ray::kNoHit) {
                            c.object = objectCount;
                            c.distance = std::numeric_limits<float>::infinity();
                        } else {
                            c.object = hit.object;
                            c.distance = glm::length(hit.p - L.origin);
                        }
                        out.records.push_back(c);
                        out.points.push_back(hit.p);
                        out.rayOrigins.push_back(exit.origin);
                        out.rayDirs.push_back(exit.dir);
                    }
                    ++ray;
                }
            }
    }
    return out;
}

LensLayers buildLayers(const LensScene& scene, size_t lens, const ClusterPass& pass, int k,
                       const ShellChoice& choice, int emSize) {
    const LensObject& L = scene.objects().at(lens);
    const ray::Scene& sc = scene.scene();
    const uint32_t objectCount = uint32_t(sc.objects.size());
    if (k <= 0)
        throw Error("hybrid: lens object '" + L.name + "': the layer count must be at least 1");
    LensLayers out;
    out.emSize = emSize;
    out.assignment = clusterLayers(pass.records, k, objectCount);
    const int n = int(out.assignment.layers.size());
    // The frontmost intersection of each ray per layer: the points the shell fits.
    std::vector<std::vector<size_t>> front(static_cast<size_t>(n));
    std::vector<uint32_t> seen(size_t(n), ~0u);
    for (size_t i = 0; i < pass.records.size(); ++i) {
        const ClusterRecord& r = pass.records[i];
        if (r.object >= objectCount) continue;
        const int l = out.assignment.layerOfObject[r.object];
        if (l < 0 || seen[size_t(l)] == r.ray) continue;
        seen[size_t(l)] = r.ray;
        front[size_t(l)].push_back(i);
    }
    for (int l = 0; l < n; ++l) {
        const LayerInfo& info = out.assignment.layers[size_t(l)];
        std::vector<glm::vec3> pts, ro, rd;
        glm::vec3 resultant(0.0f);
        double horizontal = 0;
        float yMin = std::numeric_limits<float>::infinity(), yMax = -yMin;
        for (size_t i : front[size_t(l)]) {
            pts.push_back(pass.points[i]);
            ro.push_back(pass.rayOrigins[i]);
            rd.push_back(pass.rayDirs[i]);
            const glm::vec3 d = pass.points[i] - L.origin;
            if (glm::length(d) > 0) resultant += glm::normalize(d);
            horizontal += std::sqrt(d.x * d.x + d.z * d.z);
            yMin = std::min(yMin, pass.points[i].y);
            yMax = std::max(yMax, pass.points[i].y);
        }
        const float meanResultant = pts.empty() ? 0.0f : glm::length(resultant) / float(pts.size());
        bool tall = !info.objects.empty();
        for (uint32_t o : info.objects) {
            ray::Mesh m = sc.worldMesh(o);
            ray::Bounds b = ray::computeBounds(m);
            const glm::vec3 e = b.hi - b.lo;
            tall = tall && e.y > std::max(e.x, e.z);
        }
        ShellKind kind = ShellKind::Sphere;
        if (size_t(l) < choice.kinds.size()) {
            kind = choice.kinds[size_t(l)];
        } else if (l + 1 < n) {
            if (meanResultant >= 0.6f) kind = ShellKind::Quad;
            else if (meanResultant <= 0.3f && tall) kind = ShellKind::Cylinder;
        }
        if (pts.empty()) kind = ShellKind::Sphere;
        Shell s;
        switch (kind) {
            case ShellKind::Sphere: s = sphereShell(L.origin, float(info.radius)); break;
            case ShellKind::Cylinder:
                s = cylinderShell(L.origin, float(horizontal / double(pts.size())), yMin, yMax);
                break;
            case ShellKind::Quad: s = fitQuad(L.origin, pts, ro, rd); break;
        }
        out.shells.push_back(s);
    }
    return out;
}

// ---- b images -----------------------------------------------------------------------------

LayerImages layerImages(const LensScene& scene, size_t lens, const LensLayers& layers,
                        const ray::Camera& camera, const PrecomputeSettings& S,
                        const RecordOptions& options) {
    const LensObject& L = scene.objects().at(lens);
    const int W = S.width, H = S.height, n = std::max(1, S.subsample), nl = layers.layers();
    LayerImages out;
    out.b.resize(size_t(nl));
    for (auto& terms : out.b)
        for (auto& im : terms) im = ray::Image(W, H, 4);
    for (auto& c : out.confidence) c = ray::Image(W, H, 1);
    out.coverage = ray::Image(W, H, 1);
    if (options.collectPoints) out.points.resize(size_t(nl));
    ray::RenderOptions ro;
    ro.width = W;
    ro.height = H;
    ro.spp = n;
    ro.maxDepth = S.maxDepth;
    ro.threads = S.threads;
    ray::LensRecordOptions lo;
    lo.lensObject = L.object;
    lo.incomingContinuation = options.incomingContinuation;
    lo.outgoingContinuation = options.outgoingContinuation;
    lo.layerOfObject = layers.assignment.layerOfObject;
    std::mutex mutex;
    const float inv = 1.0f / float(n * n);
    ray::compileLensRecords(scene.accel(), camera, ro, lo, [&](const ray::LensRecordRow& row) {
        const int y = row.y;
        int64_t records = 0, occluded = 0, hits = 0;
        size_t s = 0;
        std::vector<glm::vec3> dirs[2];
        std::vector<std::vector<glm::vec3>> points(options.collectPoints ? size_t(nl) : 0);
        while (s < row.samples.size()) {
            const int x = row.samples[s].x;
            int reached = 0, valid[2] = {0, 0};
            dirs[0].clear();
            dirs[1].clear();
            std::vector<glm::vec4> sum(size_t(nl) * 2, glm::vec4(0.0f));
            for (; s < row.samples.size() && row.samples[s].x == x; ++s) {
                const ray::LensSampleRecord& r = row.samples[s];
                ++reached;
                ++records;
                occluded += r.occluded ? 1 : 0;
                for (int term = 0; term < 2; ++term) {
                    if (!r.path[term].valid) continue;
                    ++valid[term];
                    dirs[term].push_back(r.path[term].exitRay.dir);
                    for (uint32_t h = 0; h < r.hitCount[term]; ++h) {
                        const ray::LensHit& hit = row.hits[r.firstHit[term] + h];
                        if (hit.layer < 0 || hit.layer >= nl) continue;
                        ++hits;
                        glm::vec4& acc = sum[size_t(hit.layer) * 2 + size_t(term)];
                        acc += glm::vec4(clamp01(hit.color.r), clamp01(hit.color.g),
                                         clamp01(hit.color.b), 1.0f);
                    }
                    if (options.collectPoints) {
                        const ray::Ray& exit = r.path[term].exitRay;
                        for (int l = 0; l < nl; ++l) {
                            bool hit = false;
                            glm::vec3 hp(0.0f), p;
                            for (uint32_t h = 0; h < r.hitCount[term] && !hit; ++h) {
                                const ray::LensHit& lh = row.hits[r.firstHit[term] + h];
                                if (lh.layer == l && std::isfinite(lh.t)) hit = true, hp = lh.p;
                            }
                            if (layerPoint(layers.shells[size_t(l)], exit.origin, exit.dir, hit, hp, p))
                                points[size_t(l)].push_back(p);
                        }
                    }
                }
            }
            for (int l = 0; l < nl; ++l)
                for (int term = 0; term < 2; ++term) {
                    const glm::vec4 v = sum[size_t(l) * 2 + size_t(term)] * inv;
                    ray::Image& im = out.b[size_t(l)][size_t(term)];
                    for (int c = 0; c < 4; ++c) im.at(x, y, c) = v[c];
                }
            for (int term = 0; term < 2; ++term)
                out.confidence[size_t(term)].at(x, y, 0) =
                    valid[term] == n * n ? ray::pathConfidence(dirs[term]) : 0.0f;
            out.coverage.at(x, y, 0) = float(reached) * inv;
        }
        std::lock_guard lock(mutex);
        for (size_t l = 0; l < points.size(); ++l)
            out.points[l].insert(out.points[l].end(), points[l].begin(), points[l].end());
        out.records += records;
        out.occludedRecords += occluded;
        out.hits += hits;
    });
    return out;
}

// ---- inference ----------------------------------------------------------------------------

namespace {

// The rows of `m` whose pixel has confidence > 0, and that confidence per kept row.
pem::RenderingMatrix confidentRows(const pem::RenderingMatrix& m, const ray::Image& conf,
                                   Eigen::VectorXd& c) {
    pem::RenderingMatrix out;
    out.layout = m.layout;
    out.width = m.width;
    out.height = m.height;
    std::vector<Eigen::Triplet<double>> trip;
    std::vector<double> cs;
    using It = Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator;
    for (size_t r = 0; r < m.rowPixel.size(); ++r) {
        const int32_t px = m.rowPixel[r];
        const float w = conf.pixels[size_t(px)];
        if (!(w > 0.0f)) continue;
        const int nr = int(out.rowPixel.size());
        out.rowPixel.push_back(px);
        cs.push_back(w);
        for (It it(m.A, int(r)); it; ++it) trip.emplace_back(nr, int(it.col()), it.value());
    }
    out.A.resize(int64_t(out.rowPixel.size()), m.layout.count());
    out.A.setFromTriplets(trip.begin(), trip.end());
    c = Eigen::Map<Eigen::VectorXd>(cs.data(), int64_t(cs.size()));
    return out;
}

struct Block {
    pem::RenderingMatrix m;
    Eigen::VectorXd confidence;
    std::array<Eigen::VectorXd, 4> b;
    bool direct = false;  // a direct image's rows (000 §4.3)
};

}  // namespace

SampleSolution inferSample(HybridRenderer& renderer, int view,
                           const std::vector<ray::Camera>& views, const PrecomputeSettings& S,
                           const RecordOptions& options) {
    SampleSolution sol;
    sol.view = view;
    sol.views = int(views.size());
    LensScene& scene = renderer.scene();
    const size_t lensCount = scene.objects().size();
    sol.maps.resize(lensCount);
    // blocks[lens][layer]: every (view, term) with rows.
    std::vector<std::vector<std::vector<Block>>> blocks(lensCount);
    for (size_t i = 0; i < lensCount; ++i) blocks[i].resize(size_t(renderer.layers(i).layers()));
    const float keepTau = renderer.tessellation().tau;
    renderer.tessellation().tau = S.tau;
    std::vector<std::vector<RecordPoints>> records;  // [lens][layer], over every view
    for (size_t vi = 0; vi < views.size(); ++vi) {
        const ray::Camera& cam = views[vi];
        auto t0 = Clock::now();
        std::vector<LayerImages> images(lensCount);
        RecordOptions ro = options;
        ro.collectPoints = options.directImages;
        for (size_t i = 0; i < lensCount; ++i) {
            images[i] = layerImages(scene, i, renderer.layers(i), cam, S, ro);
            if (options.directImages) {
                if (records.empty()) records.resize(lensCount);
                const LensLayers& L = renderer.layers(i);
                if (records[i].empty())
                    for (int l = 0; l < L.layers(); ++l)
                        records[i].emplace_back(directConfidenceScale(
                            L.shells[size_t(l)], L.emSize, options.direct.confidenceTexels));
                for (int l = 0; l < L.layers(); ++l)
                    for (const glm::vec3& p : images[i].points[size_t(l)]) records[i][size_t(l)].add(p);
                images[i].points.clear();
            }
        }
        sol.recordsS += since(t0);
        t0 = Clock::now();
        renderer.prepare(cam);
        for (size_t i = 0; i < lensCount; ++i) {
            const LensObject& lens = scene.objects()[i];
            const int nl = renderer.layers(i).layers();
            for (int term = 0; term < (lens.twoTerms ? 2 : 1); ++term)
                for (int l = 0; l < nl; ++l) {
                    pem::RenderingMatrix full = pem::buildMatrixByInstrumentedPass(
                        renderer.device(), renderer.memory(), renderer.isolating(i, term, l));
                    Block blk;
                    blk.m = confidentRows(full, images[i].confidence[size_t(term)], blk.confidence);
                    if (blk.m.rowPixel.empty()) continue;
                    const ray::Image& b = images[i].b[size_t(l)][size_t(term)];
                    for (int c = 0; c < 4; ++c) {
                        blk.b[size_t(c)].resize(int64_t(blk.m.rowPixel.size()));
                        for (size_t r = 0; r < blk.m.rowPixel.size(); ++r)
                            blk.b[size_t(c)][int64_t(r)] =
                                b.pixels[size_t(blk.m.rowPixel[r]) * 4 + size_t(c)];
                    }
                    blocks[i][size_t(l)].push_back(std::move(blk));
                }
        }
        sol.matrixS += since(t0);
        if (vi == 0) sol.images = std::move(images);
    }
    renderer.tessellation().tau = keepTau;

    // ---- 000 §4.3: direct images of the environment, without the lens object ------------
    if (options.directImages) {
        auto t1 = Clock::now();
        for (size_t i = 0; i < lensCount; ++i) {
            const LensLayers& L = renderer.layers(i);
            for (const ray::Camera& cam :
                 directCameras(scene.objects()[i], options.direct.source, views.at(0))) {
                const DirectImage d = traceDirectImage(scene, i, L, cam, S, records.at(i), options.direct);
                ++sol.directImages;
                for (int l = 0; l < L.layers(); ++l) {
                    const pem::RenderingMatrix full = pem::buildMatrixByInstrumentedPass(
                        renderer.device(), renderer.memory(),
                        directIsolating(renderer.device(), cam, L.shells[size_t(l)], L.layout(l),
                                        renderer.subsample()));
                    Block blk;
                    blk.m = confidentRows(full, d.confidence[size_t(l)], blk.confidence);
                    if (blk.m.rowPixel.empty()) continue;
                    blk.direct = true;
                    const ray::Image& b = d.b[size_t(l)];
                    for (int c = 0; c < 4; ++c) {
                        blk.b[size_t(c)].resize(int64_t(blk.m.rowPixel.size()));
                        for (size_t r = 0; r < blk.m.rowPixel.size(); ++r)
                            blk.b[size_t(c)][int64_t(r)] =
                                b.pixels[size_t(blk.m.rowPixel[r]) * 4 + size_t(c)];
                    }
                    blocks[i][size_t(l)].push_back(std::move(blk));
                }
            }
        }
        sol.directS = since(t1);
    }

    // ---- solve every layer's four channels (in parallel: independent systems) -----------
    auto t0 = Clock::now();
    struct Job {
        size_t lens;
        int layer;
    };
    std::vector<Job> jobs;
    for (size_t i = 0; i < lensCount; ++i)
        for (int l = 0; l < renderer.layers(i).layers(); ++l) {
            LayerMap& map = (sol.maps[i].resize(size_t(renderer.layers(i).layers())), sol.maps[i][size_t(l)]);
            map.layout = renderer.layers(i).layout(l);
            map.texels.assign(size_t(map.layout.count()), Rgba8{0, 0, 0, 0});
            const LensLayers& L = renderer.layers(i);
            if (L.shares(l)) {
                // 000 §4.3: the shared layer's equations join its owner's system.
                auto& owner = blocks.at(L.sharedLens).at(size_t(L.sharedOwnerLayer));
                for (Block& b : blocks[i][size_t(l)]) owner.push_back(std::move(b));
                blocks[i][size_t(l)].clear();
                continue;
            }
            jobs.push_back({i, l});
        }
    tbb::parallel_for(size_t(0), jobs.size(), [&](size_t j) {
        const auto& bl = blocks[jobs[j].lens][size_t(jobs[j].layer)];
        LayerMap& map = sol.maps[jobs[j].lens][size_t(jobs[j].layer)];
        if (bl.empty()) return;  // the layer is never seen: transparent
        std::vector<pem::WeightedMatrix> wm;
        for (const Block& b : bl) {
            wm.push_back({&b.m, b.confidence});
            map.rows += b.m.A.rows();
            if (b.direct) map.directRows += b.m.A.rows();
        }
        const pem::InferenceSystem system(wm, S.inference);
        // Unconstrained texels of the finest level: no row reaches them.
        const int64_t finest = map.layout.levelOffset(1);
        std::vector<uint8_t> reached(size_t(finest), 0);
        for (const Block& b : bl)
            for (int k = 0; k < b.m.A.outerSize(); ++k)
                for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(b.m.A, k); it; ++it)
                    if (it.col() < finest && it.value() > 0) reached[size_t(it.col())] = 1;
        map.unconstrained = std::count(reached.begin(), reached.end(), uint8_t(0));
        double residual = 0;
        // The four channels together: one pass over the normal matrix per step serves them
        // all (pem/inference.cpp), each the same bits as solved alone.
        std::vector<std::vector<Eigen::VectorXd>> rhs(4);
        for (int c = 0; c < 4; ++c)
            for (const Block& b : bl) rhs[size_t(c)].push_back(b.b[size_t(c)]);
        std::vector<pem::InferenceStats> stats;
        const std::vector<Eigen::VectorXd> xs = system.solveChannels(rhs, &stats);
        for (int c = 0; c < 4; ++c) {
            const Eigen::VectorXd& x = xs[size_t(c)];
            residual += stats[size_t(c)].residual / 4.0;
            for (int64_t t = 0; t < x.size(); ++t) {
                const uint8_t v = ray::quantize8(float(x[t]));
                Rgba8& tx = map.texels[size_t(t)];
                (c == 0 ? tx.r : c == 1 ? tx.g : c == 2 ? tx.b : tx.a) = v;
            }
        }
        map.residual = residual;
    });
    for (size_t i = 0; i < lensCount; ++i) {
        const LensLayers& L = renderer.layers(i);
        for (int l = 0; l < L.layers(); ++l)
            if (L.shares(l)) sol.maps[i][size_t(l)] = sol.maps[L.sharedLens][size_t(L.sharedOwnerLayer)];
    }
    sol.solveS = since(t0);
    return sol;
}

SampleMaps uploadSample(HybridRenderer& renderer, const SampleSolution& solution) {
    SampleMaps s;
    s.view = solution.view;
    s.maps.resize(solution.maps.size());
    for (size_t i = 0; i < solution.maps.size(); ++i) {
        const LensLayers& L = renderer.layers(i);
        for (size_t l = 0; l < solution.maps[i].size(); ++l)
            s.maps[i].push_back(L.shares(int(l)) && L.sharedLens < i
                                    ? s.maps[L.sharedLens].at(size_t(L.sharedOwnerLayer))
                                    : renderer.uploadMap(i, int(l), solution.maps[i][l].texels));
    }
    return s;
}

std::string whyDistantLayersCannotBeShared(const std::vector<LensLayers>& layers) {
    if (layers.size() < 2) return {};
    const LensLayers& owner = layers[0];
    const int ownerLayer = owner.layers() - 1;
    if (ownerLayer < 0 || !owner.shells[size_t(ownerLayer)].cube())
        return "hybrid: shared distant layers need a cube shell outermost";
    for (size_t i = 1; i < layers.size(); ++i)
        if (layers[i].layers() < 1 || layers[i].emSize != owner.emSize)
            return "hybrid: shared distant layers need layers of one EM size";
    return {};
}

void shareDistantLayers(std::vector<LensLayers>& layers) {
    if (layers.size() < 2) return;
    if (const std::string why = whyDistantLayersCannotBeShared(layers); !why.empty()) throw Error(why);
    const LensLayers& owner = layers[0];
    const int ownerLayer = owner.layers() - 1;
    for (size_t i = 1; i < layers.size(); ++i) {
        LensLayers& L = layers[i];
        const int l = L.layers() - 1;
        L.shells[size_t(l)] = owner.shells[size_t(ownerLayer)];
        L.sharedLayer = l;
        L.sharedLens = 0;
        L.sharedOwnerLayer = ownerLayer;
    }
}

}  // namespace rg::hybrid
