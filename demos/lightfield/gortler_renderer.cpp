// The Gortler reconstruction on the emulated SGI device (Heidrich et al. 1999 §3).
#include "gortler_renderer.h"

#include <glm/gtc/matrix_transform.hpp>
#include <tbb/task_group.h>

#include "core/error.h"
#include "core/tsan_annotations.h"

namespace rg::lightfield {

namespace {

// The two triangles of cell (a, b) under the fixed diagonal (a, b)–(a+1, b+1).
std::array<StTriangle, 2> cellTriangles(int a, int b) {
    return {StTriangle{{glm::ivec2(a, b), glm::ivec2(a + 1, b), glm::ivec2(a + 1, b + 1)}},
            StTriangle{{glm::ivec2(a, b), glm::ivec2(a + 1, b + 1), glm::ivec2(a, b + 1)}}};
}

}  // namespace

std::vector<StTriangle> eyePointTriangles(const LightSlab& s, int i, int j, Triangulation tri) {
    std::vector<StTriangle> out;
    for (int a = i - 1; a <= i; ++a)
        for (int b = j - 1; b <= j; ++b) {
            if (a < 0 || b < 0 || a + 1 >= s.S || b + 1 >= s.T) continue;
            if (tri == Triangulation::FixedDiagonal) {
                for (const StTriangle& t : cellTriangles(a, b))
                    for (const glm::ivec2& v : t.v)
                        if (v == glm::ivec2(i, j)) {
                            out.push_back(t);
                            break;
                        }
            } else {
                // The cell split by the diagonal through (i, j): the triangle of the two
                // corners adjacent to (i, j), each with (i, j).
                const glm::ivec2 e(i, j);
                const glm::ivec2 o(a == i ? a + 1 : a, b == j ? b + 1 : b);  // the opposite corner
                out.push_back(StTriangle{{e, glm::ivec2(o.x, e.y), o}});
                out.push_back(StTriangle{{e, o, glm::ivec2(e.x, o.y)}});
            }
        }
    return out;
}

double hatWeight(const LightSlab& s, int i, int j, glm::vec2 st, Triangulation tri) {
    for (const StTriangle& t : eyePointTriangles(s, i, j, tri)) {
        glm::dvec2 p[3];
        int self = 0;
        for (int k = 0; k < 3; ++k) {
            const glm::vec3 e = s.eyePoint(t.v[size_t(k)].x, t.v[size_t(k)].y);
            p[k] = glm::dvec2(e.x, e.y);
            if (t.v[size_t(k)] == glm::ivec2(i, j)) self = k;
        }
        const glm::dvec2 q(st);
        const double area = (p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y);
        double bary[3];
        for (int k = 0; k < 3; ++k) {
            const glm::dvec2& a = p[(k + 1) % 3];
            const glm::dvec2& b = p[(k + 2) % 3];
            bary[k] = ((b.x - a.x) * (q.y - a.y) - (q.x - a.x) * (b.y - a.y)) / area;
        }
        if (bary[0] >= -1e-12 && bary[1] >= -1e-12 && bary[2] >= -1e-12) return bary[self];
    }
    return 0.0;
}

glm::mat4 viewMatrix(const ray::Camera& c) { return glm::lookAtRH(c.eye, c.target, c.up); }

glm::mat4 projectionMatrix(const ray::Camera& c, int width, int height) {
    return glm::perspectiveRH_ZO(glm::radians(c.fovYDegrees), float(width) / float(height), 0.05f, 100.0f);
}

// A group's upload in flight on a TBB task. TSan cannot see the task_group's fork and
// join inside libtbb: the upload's end and the wait state them on `edge`.
struct SliceTextures::Pending {
    tbb::task_group group;
    int edge = 0;
    void wait() {
        group.wait();
        RG_TSAN_ACQUIRE(&edge);
    }
};

SliceTextures::SliceTextures(std::shared_ptr<tex::TextureMemory> memory, const LightField& lf)
    : memory_(std::move(memory)), lf_(&lf) {
    const tex::TextureDesc d{tex::TextureTarget::Texture2D, lf.channels == 4 ? tex::TexelFormat::RGBA8 : tex::TexelFormat::RGB8,
                             lf.slab.U, lf.slab.V, 1, 1, 1};
    const uint64_t all = uint64_t(lf.slab.S) * lf.slab.T * lf.sliceBytes();
    resident_ = memory_->residentBytes() + all <= memory_->profile().textureMemoryBytes;
    if (resident_) {
        for (int j = 0; j < lf.slab.T; ++j)
            for (int i = 0; i < lf.slab.S; ++i) {
                auto t = memory_->create(d);
                memory_->upload(*t, 0, 0, std::span<const uint8_t>(lf.slice(i, j), lf.sliceBytes()));
                slices_.push_back(std::move(t));
            }
    } else {
        // Two groups' worth of slices, refilled per eye point (fewer when the light field
        // has fewer slices than that: it did not fit, so it has at least two).
        const int slots = std::min(2 * kGroup, lf.slab.S * lf.slab.T);
        for (int k = 0; k < slots; ++k) stream_.push_back(memory_->create(d));
    }
}

SliceTextures::~SliceTextures() {
    // An upload in flight must finish before the slots go; its error, if any, has no one
    // left to report to (the frame that asked for it already ended by an exception).
    try {
        settle();
    } catch (...) {
    }
}

uint64_t SliceTextures::sliceBytes() const { return lf_->sliceBytes(); }

void SliceTextures::upload(int slot, const glm::ivec2& ij) {
    memory_->upload(*stream_[size_t(slot)], 0, 0,
                    std::span<const uint8_t>(lf_->slice(ij.x, ij.y), lf_->sliceBytes()));
}

void SliceTextures::uploadGroup(size_t group, bool async) {
    const size_t begin = group * kGroup, end = std::min(order_.size(), begin + kGroup);
    const int half = int(group % 2) * kGroup;
    groupsUploaded_ = group + 1;
    auto run = [this, begin, end, half] {
        for (size_t e = begin; e < end; ++e) upload(half + int(e - begin), order_[e]);
    };
    if (!async) {
        run();
        return;
    }
    pending_ = std::make_unique<Pending>();
    RG_TSAN_RELEASE(&pending_->edge);
    pending_->group.run([run, edge = &pending_->edge] {
        RG_TSAN_ACQUIRE(edge);
        run();
        RG_TSAN_RELEASE(edge);
    });
}

void SliceTextures::beginSequence(std::vector<glm::ivec2> order, bool overlap) {
    settle();
    if (resident_) return;
    order_ = std::move(order);
    cursor_ = 0;
    groupsUploaded_ = 0;
    // Two groups need 2·kGroup slots.
    overlap_ = overlap && stream_.size() == size_t(2 * kGroup);
}

void SliceTextures::settle() {
    if (pending_) {
        pending_->wait();
        pending_.reset();
    }
    order_.clear();
    cursor_ = 0;
}

std::shared_ptr<const tex::Texture> SliceTextures::slice(int i, int j) {
    const int k = j * lf_->slab.S + i;
    if (resident_) return slices_[size_t(k)];
    if (cursor_ < order_.size() && order_[cursor_] == glm::ivec2(i, j) &&
        stream_.size() == size_t(2 * kGroup)) {
        const size_t e = cursor_++;
        if (e % kGroup == 0) {
            // A group starts: its uploads have finished (or, at the first, happen now);
            // the next group's start, on another thread when overlapping, into the other
            // half, which held the group just drawn.
            const size_t g = e / kGroup;
            if (pending_) {
                pending_->wait();
                pending_.reset();
            }
            if (groupsUploaded_ <= g) uploadGroup(g, false);
            if (e + kGroup < order_.size() && groupsUploaded_ <= g + 1) uploadGroup(g + 1, overlap_);
        }
        const int slot = int((e / kGroup) % 2) * kGroup + int(e % kGroup);
        return stream_[size_t(slot)];
    }
    // Off the sequence: end it, then upload now into the next slot in turn.
    settle();
    const int slot = next_;
    next_ = (next_ + 1) % int(stream_.size());
    upload(slot, {i, j});
    return stream_[size_t(slot)];
}

glm::vec2 windowCoords(const LightSlab& s, const glm::vec3& eye, const glm::vec3& p) {
    const float t = (s.uvZ - eye.z) / (p.z - eye.z);
    const glm::vec3 w = eye + t * (p - eye);
    return {(w.x - s.uvMin.x) / (s.uvMax.x - s.uvMin.x), (w.y - s.uvMin.y) / (s.uvMax.y - s.uvMin.y)};
}

raster::PipelineState additiveState() {
    raster::PipelineState st;
    st.cull = raster::CullMode::None;
    st.depthTest = 0;
    st.depthWrite = 0;
    st.blend = 1;
    st.srcBlend = raster::BlendFactor::One;
    st.dstBlend = raster::BlendFactor::One;
    return st;
}

GortlerStats renderGortler(raster::Device& dev, SliceTextures& slices, const LightField& lf,
                           const ray::Camera& camera, const GortlerOptions& o) {
    const LightSlab& s = lf.slab;
    const int w = dev.framebuffer().width(), h = dev.framebuffer().height();
    dev.setTransforms(glm::mat4(1.0f), viewMatrix(camera), projectionMatrix(camera, w, h));
    dev.setViewport({0, 0, w, h, 0.0f, 1.0f});
    if (o.clear) dev.clear(true, {0, 0, 0, 0}, false, 1.0f);
    dev.setState(additiveState());
    tex::TextureUnits& tu = dev.textureUnits();
    tex::SamplerState sampler;
    sampler.magFilter = sampler.minFilter = o.filter;
    sampler.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                       tex::AddressMode::ClampToEdge};
    tu.setSampler(0, sampler);
    tex::TexGenState tg;
    tg.projected = true;  // GL divides by q; q = 1
    tu.setTexGen(0, tg);
    tu.setStage(0, tex::texEnvStage(tex::TexEnvMode::Modulate, lf.channels == 4 ? tex::BaseFormat::Rgba : tex::BaseFormat::Rgb));
    GortlerStats stats;
    std::vector<raster::Vertex> verts;
    // The eye points with polygons, in order; when the slices are swapped, the next group's
    // uploads overlap this group's draws on a second thread (SliceTextures), unless the
    // device runs on one thread.
    std::vector<std::pair<glm::ivec2, std::vector<StTriangle>>> points;
    for (int j = 0; j < s.T; ++j)
        for (int i = 0; i < s.S; ++i) {
            std::vector<StTriangle> tris = eyePointTriangles(s, i, j, o.triangulation);
            if (!tris.empty()) points.push_back({{i, j}, std::move(tris)});
        }
    {
        std::vector<glm::ivec2> order;
        for (const auto& p : points) order.push_back(p.first);
        slices.beginSequence(std::move(order), dev.options().threads != 1);
    }
    // The eye points' draws in one batch (raster::Device::beginBatch): a few triangles
    // each, they would otherwise pay the device's fork and join per draw. Swapped slices
    // end the batch at each group's start, before slice() refills the slots the group
    // two back was drawn from (and, overlapping, starts the next group's uploads).
    raster::DrawBatch batch(dev);
    for (size_t e = 0; e < points.size(); ++e) {
        const int i = points[e].first.x, j = points[e].first.y;
        const std::vector<StTriangle>& tris = points[e].second;
        if (!slices.resident() && e > 0 && e % SliceTextures::kGroup == 0) {
            dev.endBatch();
            dev.beginBatch();
        }
        {
            verts.clear();
            for (const StTriangle& t : tris)
                for (const glm::ivec2& g : t.v) {
                    raster::Vertex v;
                    const glm::vec3 p = s.eyePoint(g.x, g.y);
                    v.position = glm::vec4(p, 1.0f);
                    const uint8_t wgt = g == glm::ivec2(i, j) ? 255 : 0;
                    v.diffuse = {wgt, wgt, wgt, wgt};
                    const glm::vec2 uv = windowCoords(s, camera.eye, p);
                    v.tex[0] = glm::vec4(uv, 0.0f, 1.0f);
                    verts.push_back(v);
                }
            tu.setTexture(0, slices.slice(i, j));
            dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, verts);
            ++stats.eyePoints;
            stats.triangles += int(tris.size());
        }
    }
    batch.end();
    slices.settle();
    stats.uploadBytes = slices.resident() ? 0 : uint64_t(stats.eyePoints) * slices.sliceBytes();
    return stats;
}

}  // namespace rg::lightfield
