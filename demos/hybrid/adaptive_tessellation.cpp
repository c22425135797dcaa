// 000 §5: vertex ray paths, adaptive 1-to-4/3/2 subdivision, the edge hash and t-junction
// removal.
#include "adaptive_tessellation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"

namespace rg::hybrid {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}
}  // namespace

bool pathsDiffer(const ray::PathSummary& a, const ray::PathSummary& b, float cosThreshold) {
    if (a.valid != b.valid) return true;
    if (!a.valid) return false;
    if (a.length != b.length || a.events != b.events) return true;
    return glm::dot(a.exitRay.dir, b.exitRay.dir) < cosThreshold;
}

bool tracesDiffer(const VertexTrace& a, const VertexTrace& b, float cosThreshold) {
    return pathsDiffer(a.paths.reflect, b.paths.reflect, cosThreshold) ||
           pathsDiffer(a.paths.refract, b.paths.refract, cosThreshold);
}

VertexTrace traceVertex(const glm::vec3& p, const glm::vec3& nIn, const glm::vec3& eye,
                        const ray::Accel& local, const ray::Material& material,
                        const ray::Accel& visibility, int maxDepth, ray::RayCounts& counts) {
    VertexTrace out;
    const glm::vec3 toP = p - eye;
    const float dist = glm::length(toP);
    if (!(dist > 0.0f)) return out;
    const glm::vec3 d = toP / dist;
    // ---- one visibility ray per vertex (000 §5) --------------------------------------
    ray::Ray vis;
    vis.origin = eye;
    vis.dir = d;
    vis.tfar = dist - 16.0f * visibility.epsilon() * (1.0f + dist);
    counts.add(ray::RayKind::Primary);
    out.visible = !(vis.tfar > 0.0f && visibility.occluded(vis));
    // ---- the two greedy paths, local geometry only -----------------------------------
    glm::vec3 n = nIn;
    const float dn = glm::dot(d, n);
    if (dn > -0.02f) {
        const glm::vec3 tilted = n - (dn + 0.02f) * d;
        const float len = glm::length(tilted);
        n = len > 0.0f ? tilted / len : -d;
    }
    ray::SurfacePoint s;
    s.p = p;
    s.ng = n;
    s.ns = n;
    s.frontFace = true;
    s.object = 0;
    s.material = &material;
    out.paths = ray::traceLensPaths(local, d, s, maxDepth, counts);
    return out;
}

// ---- the edge hash -----------------------------------------------------------------------

EdgeHash::EdgeHash(size_t expected) {
    size_t cap = 16;
    while (cap < expected * 2) cap <<= 1;
    keys_.assign(cap, ~uint64_t(0));
    values_.assign(cap, kNone);
}

namespace {
inline size_t slotOf(uint64_t k, size_t mask) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    return size_t(k) & mask;
}
}  // namespace

uint32_t EdgeHash::find(uint32_t a, uint32_t b) const {
    const uint64_t k = key(a, b);
    const size_t mask = keys_.size() - 1;
    for (size_t i = slotOf(k, mask);; i = (i + 1) & mask) {
        if (keys_[i] == k) return values_[i];
        if (keys_[i] == ~uint64_t(0)) return kNone;
    }
}

void EdgeHash::insert(uint32_t a, uint32_t b, uint32_t midpoint) {
    if ((size_ + 1) * 2 > keys_.size()) grow();
    const uint64_t k = key(a, b);
    const size_t mask = keys_.size() - 1;
    for (size_t i = slotOf(k, mask);; i = (i + 1) & mask) {
        if (keys_[i] == ~uint64_t(0)) {
            keys_[i] = k;
            values_[i] = midpoint;
            ++size_;
            return;
        }
        if (keys_[i] == k) throw Error("hybrid: edge hash: an edge inserted twice");
    }
}

void EdgeHash::grow() {
    std::vector<uint64_t> keys = std::move(keys_);
    std::vector<uint32_t> values = std::move(values_);
    keys_.assign(keys.size() * 2, ~uint64_t(0));
    values_.assign(keys.size() * 2, kNone);
    size_ = 0;
    const size_t mask = keys_.size() - 1;
    for (size_t j = 0; j < keys.size(); ++j) {
        if (keys[j] == ~uint64_t(0)) continue;
        size_t i = slotOf(keys[j], mask);
        while (keys_[i] != ~uint64_t(0)) i = (i + 1) & mask;
        keys_[i] = keys[j];
        values_[i] = values[j];
        ++size_;
    }
}

void EdgeHash::edgeVertices(uint32_t a, uint32_t b, std::vector<uint32_t>& out) const {
    const uint32_t m = find(a, b);
    if (m == kNone) {
        out.push_back(a);
        return;
    }
    edgeVertices(a, m, out);
    edgeVertices(m, b, out);
}

// ---- t-junction removal ------------------------------------------------------------------

void triangulateRing(const std::vector<uint32_t>& ringIn, const std::vector<uint8_t>& maskIn,
                     const std::vector<glm::vec3>& positions, std::vector<uint32_t>& out) {
    std::vector<uint32_t> ring = ringIn;
    std::vector<uint8_t> mask = maskIn;
    auto angleAt = [&](uint32_t a, uint32_t b, uint32_t c) {  // angle at b
        glm::vec3 u = glm::normalize(positions[a] - positions[b]);
        glm::vec3 v = glm::normalize(positions[c] - positions[b]);
        return std::acos(std::clamp(glm::dot(u, v), -1.0f, 1.0f));
    };
    while (ring.size() > 3) {
        const size_t m = ring.size();
        int best = -1;
        float bestQuality = -1.0f;
        for (size_t i = 0; i < m; ++i) {
            const size_t p = (i + m - 1) % m, q = (i + 1) % m;
            if (mask[p] & mask[i] & mask[q]) continue;  // collinear: no area
            // What is left must still enclose area.
            uint8_t rest = 0xff;
            for (size_t j = 0; j < m; ++j)
                if (j != i) rest &= mask[j];
            if (rest) continue;
            const float quality = std::min({angleAt(ring[p], ring[i], ring[q]),
                                            angleAt(ring[i], ring[q], ring[p]),
                                            angleAt(ring[q], ring[p], ring[i])});
            if (quality > bestQuality) bestQuality = quality, best = int(i);
        }
        if (best < 0) throw Error("hybrid: t-junction removal found no ear (a degenerate leaf)");
        const size_t i = size_t(best), p = (i + m - 1) % m, q = (i + 1) % m;
        out.insert(out.end(), {ring[p], ring[i], ring[q]});
        // The ear's cut p–q is a new side: its ends keep their own edges, which is right
        // (a line meets a triangle's boundary in two points unless it holds an edge).
        ring.erase(ring.begin() + std::ptrdiff_t(i));
        mask.erase(mask.begin() + std::ptrdiff_t(i));
    }
    if (!(mask[0] & mask[1] & mask[2])) out.insert(out.end(), {ring[0], ring[1], ring[2]});
}

// ---- the subdivision ---------------------------------------------------------------------

namespace {

struct Tri {
    uint32_t v[3];
    uint8_t level;
};

struct Projector {
    const ScreenSpace& s;
    // Window position in device pixels; w ≤ 0 (behind the eye) gives NaN, "long".
    glm::vec2 operator()(const glm::vec3& p) const {
        glm::vec4 c = s.viewProjection * glm::vec4(p, 1.0f);
        if (!(c.w > 1e-6f)) return glm::vec2(std::numeric_limits<float>::quiet_NaN());
        return {(c.x / c.w * 0.5f + 0.5f) * float(s.width),
                (0.5f - c.y / c.w * 0.5f) * float(s.height)};
    }
};

}  // namespace

AdaptiveMesh tessellateAdaptively(const LensObject& lens, const ray::Accel& local,
                                  const ray::Accel& visibility, const ScreenSpace& screen,
                                  const TessellationSettings& S) {
    if (!(S.tau > 0.0f)) throw Error("hybrid: the subdivision threshold τ must be > 0");
    AdaptiveMesh mesh;
    TessellationStats& st = mesh.stats;
    mesh.positions = lens.positions;
    mesh.normals = lens.normals;
    mesh.positionId = lens.positionId;
    uint32_t positionCount = lens.positionCount;
    mesh.traces.resize(mesh.positions.size());
    mesh.traced.assign(mesh.positions.size(), 0);
    const float cosThreshold = std::cos(S.exitAngleDegrees * std::numbers::pi_v<float> / 180.0f);
    const ray::Material& material = lens.material();
    const Projector project{screen};
    std::vector<glm::vec2> win(mesh.positions.size());
    tbb::task_arena arena(S.threads > 0 ? S.threads : tbb::task_arena::automatic);

    // Traces the listed vertices in parallel (000 §5: "Ray tracing at vertices").
    std::vector<ray::RayCounts> partial;
    auto traceAll = [&](const std::vector<uint32_t>& list) {
        auto t0 = Clock::now();
        constexpr size_t kGrain = 64;
        const size_t chunks = (list.size() + kGrain - 1) / kGrain;
        partial.assign(chunks, ray::RayCounts{});
        arena.execute([&] {
            tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
                const size_t end = std::min(list.size(), (c + 1) * kGrain);
                for (size_t k = c * kGrain; k < end; ++k) {
                    const uint32_t v = list[k];
                    mesh.traces[v] = traceVertex(mesh.positions[v], mesh.normals[v], screen.eye,
                                                 local, material, visibility, S.maxDepth,
                                                 partial[c]);
                    mesh.traced[v] = 1;
                    win[v] = project(mesh.positions[v]);
                }
            });
        });
        for (const ray::RayCounts& c : partial)
            for (size_t k = 0; k < c.n.size(); ++k) st.rays.n[k] += c.n[k];
        st.traceSeconds += since(t0);
    };

    // ---- front faces mark their vertices "to be ray traced" -------------------------------
    auto t0 = Clock::now();
    std::vector<Tri> active;
    const size_t baseTris = lens.indices.size() / 3;
    st.baseTriangles = int64_t(baseTris);
    std::vector<uint8_t> mark(mesh.positions.size(), 0);
    for (size_t t = 0; t < baseTris; ++t) {
        const uint32_t* v = &lens.indices[3 * t];
        const uint32_t* pid = lens.positionId.data();
        if (pid[v[0]] == pid[v[1]] || pid[v[1]] == pid[v[2]] || pid[v[0]] == pid[v[2]])
            continue;  // a sliver once welded
        const glm::vec3 &a = mesh.positions[v[0]], &b = mesh.positions[v[1]],
                        &c = mesh.positions[v[2]];
        const glm::vec3 n = glm::cross(b - a, c - a);
        if (!(glm::dot(n, screen.eye - a) > 0.0f)) continue;
        active.push_back({{v[0], v[1], v[2]}, 0});
        mark[v[0]] = mark[v[1]] = mark[v[2]] = 1;
    }
    st.frontTriangles = int64_t(active.size());
    std::vector<uint32_t> toTrace;
    for (uint32_t v = 0; v < mark.size(); ++v)
        if (mark[v]) toTrace.push_back(v);
    st.baseVerticesTraced = int64_t(toTrace.size());
    st.tessellateSeconds += since(t0);
    traceAll(toTrace);

    // Two hashes: vertex pairs → the midpoint vertex of that side of the edge, and
    // position pairs → the midpoint position. Across a crease the two sides have vertices
    // of their own (their own normals, their own paths) at shared positions. They start
    // small and grow with the edges split: sized for every front triangle up front they
    // took megabytes, and t-junction removal's lookups (six per leaf, nearly all misses
    // where few triangles split) went out to L3 for each.
    EdgeHash hash, positionHash;
    // Positions at an end of a split edge. A vertex pair has a midpoint (in `hash`) only
    // if its position pair has one (in `positionHash`), so an edge with an end not marked
    // here has none on either side: t-junction removal skips both lookups for it.
    std::vector<uint8_t> splitEnd(positionCount, 0);
    std::vector<Tri> leaves;
    std::vector<uint8_t> split;
    auto newVertex = [&](uint32_t a, uint32_t b, uint32_t pm) {
        const uint32_t m = uint32_t(mesh.positions.size());
        mesh.positions.push_back(0.5f * (mesh.positions[a] + mesh.positions[b]));
        glm::vec3 nrm = mesh.normals[a] + mesh.normals[b];
        const float len = glm::length(nrm);
        mesh.normals.push_back(len > 0.0f ? nrm / len : mesh.normals[a]);
        mesh.positionId.push_back(pm);
        mesh.traces.emplace_back();
        mesh.traced.push_back(0);
        win.emplace_back();
        hash.insert(a, b, m);
        return m;
    };
    auto midpoint = [&](uint32_t a, uint32_t b, std::vector<uint32_t>& fresh) {
        uint32_t m = hash.find(a, b);
        if (m != EdgeHash::kNone) return m;
        const uint32_t pa = mesh.positionId[a], pb = mesh.positionId[b];
        uint32_t pm = positionHash.find(pa, pb);
        if (pm == EdgeHash::kNone) {
            pm = positionCount++;
            positionHash.insert(pa, pb, pm);
            splitEnd[pa] = splitEnd[pb] = 1;
            splitEnd.push_back(0);  // position pm's entry
        }
        m = newVertex(a, b, pm);
        fresh.push_back(m);
        return m;
    };
    while (!active.empty()) {
        // ---- decide: which triangles split, along which edges (parallel, read-only) -----
        t0 = Clock::now();
        split.assign(active.size(), 0);
        arena.execute([&] {
            tbb::parallel_for(size_t(0), active.size(), [&](size_t i) {
                const Tri& t = active[i];
                const VertexTrace *a = &mesh.traces[t.v[0]], *b = &mesh.traces[t.v[1]],
                                  *c = &mesh.traces[t.v[2]];
                if (!a->visible && !b->visible && !c->visible) {
                    split[i] = 0x10;  // occluded
                    return;
                }
                if (!tracesDiffer(*a, *b, cosThreshold) && !tracesDiffer(*b, *c, cosThreshold) &&
                    !tracesDiffer(*c, *a, cosThreshold)) {
                    split[i] = 0x20;  // the paths agree
                    return;
                }
                if (t.level >= S.maxLevel) {
                    split[i] = 0x40;
                    return;
                }
                uint8_t longEdges = 0;
                for (int e = 0; e < 3; ++e) {
                    const glm::vec2 d = win[t.v[(e + 1) % 3]] - win[t.v[e]];
                    const float len = std::sqrt(d.x * d.x + d.y * d.y);
                    if (!(len < S.tau)) longEdges |= uint8_t(1u << e);  // NaN: long
                }
                split[i] = longEdges ? longEdges : 0x80;  // 0x80: edges below τ
            });
        });
        // ---- split: midpoints through the edge hash (serial: deterministic numbering) ---
        std::vector<Tri> next;
        std::vector<uint32_t> fresh;
        for (size_t i = 0; i < active.size(); ++i) {
            const Tri& t = active[i];
            const uint8_t s = split[i];
            if (s & 0xf0) {
                leaves.push_back(t);
                if (s == 0x10) ++st.leavesOccluded;
                else if (s == 0x20) ++st.leavesSame;
                else if (s == 0x40) ++st.leavesCapped;
                else ++st.leavesSmall;
                continue;
            }
            const uint8_t lv = uint8_t(t.level + 1);
            st.maxLevel = std::max(st.maxLevel, int(lv));
            const int longCount = (s & 1) + ((s >> 1) & 1) + ((s >> 2) & 1);
            if (longCount == 3) {
                ++st.splits4;
                const uint32_t v0 = t.v[0], v1 = t.v[1], v2 = t.v[2];
                const uint32_t m0 = midpoint(v0, v1, fresh), m1 = midpoint(v1, v2, fresh),
                               m2 = midpoint(v2, v0, fresh);
                next.push_back({{v0, m0, m2}, lv});
                next.push_back({{m0, v1, m1}, lv});
                next.push_back({{m2, m1, v2}, lv});
                next.push_back({{m0, m1, m2}, lv});
            } else if (longCount == 1) {
                ++st.splits2;
                const int r = s == 1 ? 0 : s == 2 ? 1 : 2;  // rotate: the long edge first
                const uint32_t v0 = t.v[r], v1 = t.v[(r + 1) % 3], v2 = t.v[(r + 2) % 3];
                const uint32_t m0 = midpoint(v0, v1, fresh);
                next.push_back({{v0, m0, v2}, lv});
                next.push_back({{m0, v1, v2}, lv});
            } else {
                ++st.splits3;
                const int shortEdge = !(s & 1) ? 0 : !(s & 2) ? 1 : 2;
                const int r = (shortEdge + 1) % 3;  // rotate: the short edge last (v2 → v0)
                const uint32_t v0 = t.v[r], v1 = t.v[(r + 1) % 3], v2 = t.v[(r + 2) % 3];
                const uint32_t m0 = midpoint(v0, v1, fresh), m1 = midpoint(v1, v2, fresh);
                next.push_back({{m0, v1, m1}, lv});
                // The quad v0 m0 m1 v2 along its shorter diagonal.
                if (glm::length(mesh.positions[v0] - mesh.positions[m1]) <=
                    glm::length(mesh.positions[m0] - mesh.positions[v2])) {
                    next.push_back({{v0, m0, m1}, lv});
                    next.push_back({{v0, m1, v2}, lv});
                } else {
                    next.push_back({{v0, m0, v2}, lv});
                    next.push_back({{m0, m1, v2}, lv});
                }
            }
        }
        st.midpointsTraced += int64_t(fresh.size());
        st.tessellateSeconds += since(t0);
        traceAll(fresh);
        active = std::move(next);
    }

    // ---- t-junction removal (Figure 6c) ---------------------------------------------------
    t0 = Clock::now();
    // This side's vertices along edge (a, b), a up to b excluded, by recursive queries.
    // Where only the other side of a crease split the edge, this side makes its own
    // vertex there (traced below with the others of its kind).
    std::vector<uint32_t> creaseFresh;
    // (A generic lambda that calls itself, not a std::function: this runs for every edge
    // of every leaf, and the indirect call kept the compiler from inlining the lookups.)
    auto alongImpl = [&](auto& self, uint32_t a, uint32_t b, std::vector<uint32_t>& out) -> void {
        if (!splitEnd[mesh.positionId[a]] || !splitEnd[mesh.positionId[b]]) {
            out.push_back(a);
            return;
        }
        uint32_t m = hash.find(a, b);
        if (m == EdgeHash::kNone) {
            const uint32_t pm = positionHash.find(mesh.positionId[a], mesh.positionId[b]);
            if (pm == EdgeHash::kNone) {
                out.push_back(a);
                return;
            }
            m = newVertex(a, b, pm);
            creaseFresh.push_back(m);
        }
        self(self, a, m, out);
        self(self, m, b, out);
    };
    auto along = [&](uint32_t a, uint32_t b, std::vector<uint32_t>& out) {
        alongImpl(alongImpl, a, b, out);
    };
    std::vector<uint32_t> ring, chain;
    std::vector<uint8_t> mask;
    for (const Tri& t : leaves) {
        mesh.leaves.insert(mesh.leaves.end(), {t.v[0], t.v[1], t.v[2]});
        ring.clear();
        mask.clear();
        for (int e = 0; e < 3; ++e) {
            chain.clear();
            along(t.v[e], t.v[(e + 1) % 3], chain);
            for (size_t k = 0; k < chain.size(); ++k) {
                ring.push_back(chain[k]);
                // A corner lies on this edge and the one before it.
                mask.push_back(uint8_t(k == 0 ? (1u << e) | (1u << ((e + 2) % 3)) : 1u << e));
            }
        }
        const size_t before = mesh.indices.size();
        if (ring.size() == 3) {
            mesh.indices.insert(mesh.indices.end(), {t.v[0], t.v[1], t.v[2]});
        } else {
            ++st.tjunctionPolygons;
            triangulateRing(ring, mask, mesh.positions, mesh.indices);
        }
        for (size_t k = before; k < mesh.indices.size(); k += 3) mesh.triangleLevel.push_back(t.level);
    }
    st.tessellateSeconds += since(t0);
    st.creaseVertices = int64_t(creaseFresh.size());
    st.midpointsTraced += int64_t(creaseFresh.size());
    if (!creaseFresh.empty()) traceAll(creaseFresh);
    st.outputTriangles = int64_t(mesh.indices.size() / 3);
    return mesh;
}

}  // namespace rg::hybrid
