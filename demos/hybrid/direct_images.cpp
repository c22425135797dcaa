#include "direct_images.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "core/error.h"
#include "hybrid_precompute.h"
#include "pem_renderer.h"
#include "raycore/tracer_whitted.h"

namespace rg::hybrid {

using raster::CompareFunc;
using tex::TextureOp;
namespace arg = tex::arg;

DirectSource resolveDirectSource(const LensObject& lens, DirectSource source) {
    if (source != DirectSource::Auto) return source;
    // 000 §4.3: "Direct images from the lens object center tend to work better for
    // reflective objects while direct images from the viewpoint are better suited for
    // refractive (transparent) objects."
    return lens.twoTerms ? DirectSource::Viewpoint : DirectSource::Center;
}

std::vector<ray::Camera> directCameras(const LensObject& lens, DirectSource source,
                                       const ray::Camera& sample) {
    if (resolveDirectSource(lens, source) == DirectSource::Viewpoint) {
        ray::Camera c = sample;
        c.name = "direct from the viewpoint";
        return {c};
    }
    // Four around the vertical (90° apart, 90° vertical field, wider horizontally at the
    // device's aspect), one up, one down: every direction is in at least one of them.
    std::vector<ray::Camera> out;
    const glm::vec3 o = lens.origin;
    const glm::vec3 around[4] = {{1, 0, 0}, {0, 0, 1}, {-1, 0, 0}, {0, 0, -1}};
    for (const glm::vec3& d : around)
        out.push_back({"direct from the centre", o, o + d, {0, 1, 0}, 90.0f});
    out.push_back({"direct from the centre (up)", o, o + glm::vec3(0, 1, 0), {0, 0, -1}, 90.0f});
    out.push_back({"direct from the centre (down)", o, o - glm::vec3(0, 1, 0), {0, 0, 1}, 90.0f});
    return out;
}

float directConfidenceScale(const Shell& shell, int emSize, float texels) {
    const float size = float(std::max(1, emSize));
    if (shell.kind == ShellKind::Quad) {
        const float extent = std::max(shell.uMax - shell.uMin, shell.vMax - shell.vMin);
        return texels * extent / (2.0f * size);
    }
    // Sphere and cylinder alike: the radius is the distance a face's 90° spans at.
    return texels * shell.radius * (0.5f * std::numbers::pi_v<float>) / size;
}

float directConfidence(float distance, float d0) {
    if (!(d0 > 0.0f)) return 1.0f;
    return std::clamp(distance / d0, 0.0f, 1.0f);
}

// ---- the records' points -----------------------------------------------------------------

RecordPoints::RecordPoints(float cell) : cell_(cell > 0.0f ? cell : 1.0f) {}

int64_t RecordPoints::key(int x, int y, int z) const {
    // 21 bits per axis (±1M cells), enough for any scene at any d0 we use.
    auto k = [](int v) { return int64_t(uint32_t(v + (1 << 20)) & 0x1FFFFFu); };
    return (k(x) << 42) | (k(y) << 21) | k(z);
}

void RecordPoints::add(const glm::vec3& p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
    const glm::vec3 q = glm::floor(p / cell_);
    cells_[key(int(q.x), int(q.y), int(q.z))].push_back(p);
    ++count_;
}

float RecordPoints::nearest(const glm::vec3& p) const {
    float best2 = cell_ * cell_;
    const glm::vec3 q = glm::floor(p / cell_);
    // A point within cell_ of p lies in one of the 27 cells around p's own.
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                auto it = cells_.find(key(int(q.x) + dx, int(q.y) + dy, int(q.z) + dz));
                if (it == cells_.end()) continue;
                for (const glm::vec3& r : it->second) {
                    const glm::vec3 d = r - p;
                    best2 = std::min(best2, glm::dot(d, d));
                }
            }
    return std::sqrt(best2);
}

bool layerPoint(const Shell& shell, const glm::vec3& origin, const glm::vec3& dir, bool hit,
                const glm::vec3& hitPoint, glm::vec3& out) {
    if (hit) {
        out = hitPoint;
        return true;
    }
    bool forced = false;
    out = shell.intersect(origin, dir, &forced);
    return !(forced && shell.kind == ShellKind::Quad);
}

// A quad's texture covers its rectangle only: a ray meeting the plane outside it would
// land, clamped, on the edge texels with the colour of whatever lies far off there.
namespace {
bool onTexture(const Shell& shell, const glm::vec3& origin, const glm::vec3& dir) {
    if (shell.cube()) return true;
    bool forced = false;
    const glm::vec4 st = shell.texCoord(origin, dir, &forced);
    return !forced && st.x >= 0.0f && st.x <= 1.0f && st.y >= 0.0f && st.y <= 1.0f;
}
}  // namespace

// ---- b and c ------------------------------------------------------------------------------

DirectImage traceDirectImage(const LensScene& scene, size_t lensIndex, const LensLayers& layers,
                             const ray::Camera& camera, const PrecomputeSettings& S,
                             const std::vector<RecordPoints>& records,
                             const DirectImageOptions& options) {
    const LensObject& lens = scene.objects().at(lensIndex);
    const ray::Accel& accel = scene.accel();
    const ray::Scene& sc = accel.scene();
    const int W = S.width, H = S.height, n = std::max(1, S.subsample), nl = layers.layers();
    if (int(records.size()) != nl) throw Error("hybrid: direct images need the records of every layer");
    const std::vector<int>& layerOfObject = layers.assignment.layerOfObject;
    auto layerOf = [&](uint32_t object) {
        if (object == ray::kNoHit) return layerOfObject.empty() ? -1 : layerOfObject.back();
        return object < layerOfObject.size() ? layerOfObject[object] : -1;
    };
    std::vector<float> d0(static_cast<size_t>(nl));
    for (int l = 0; l < nl; ++l)
        d0[size_t(l)] = directConfidenceScale(layers.shells[size_t(l)], layers.emSize,
                                              options.confidenceTexels);
    DirectImage out;
    out.camera = camera;
    out.b.assign(size_t(nl), ray::Image(W, H, 4));
    out.confidence.assign(size_t(nl), ray::Image(W, H, 1));
    const float inv = 1.0f / float(n * n);
    tbb::parallel_for(0, H, [&](int y) {
        ray::RayCounts counts;
        std::vector<glm::vec4> sum(static_cast<size_t>(nl));
        std::vector<float> conf(static_cast<size_t>(nl));
        std::vector<uint8_t> forced(static_cast<size_t>(nl));
        for (int x = 0; x < W; ++x) {
            std::fill(sum.begin(), sum.end(), glm::vec4(0.0f));
            std::fill(conf.begin(), conf.end(), 0.0f);
            std::fill(forced.begin(), forced.end(), uint8_t(0));
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    const glm::vec2 f = ray::samplePosition(x, y, sx, sy, n);
                    const ray::Ray r = ray::primaryRay(camera, W, H, f.x, f.y);
                    // Every front-facing hit but the lens object's: the environment
                    // "without the lens object", the first of each layer kept (000 §4.1).
                    std::vector<ray::Hit> along;
                    for (const ray::Hit& h : accel.allIntersections(r, true))
                        if (h.object != lens.object) along.push_back(h);
                    std::vector<int> firstOfLayer(static_cast<size_t>(nl), -1);
                    for (size_t k = 0; k < along.size(); ++k) {
                        const int l = layerOf(along[k].object);
                        if (l >= 0 && l < nl && firstOfLayer[size_t(l)] < 0) firstOfLayer[size_t(l)] = int(k);
                    }
                    const int envLayer = layerOf(ray::kNoHit);
                    for (int l = 0; l < nl; ++l) {
                        const int k = firstOfLayer[size_t(l)];
                        glm::vec3 color(0.0f), hitPoint(0.0f);
                        bool hit = false;
                        if (k >= 0) {
                            const ray::Hit& h = along[size_t(k)];
                            hit = true;
                            hitPoint = r.origin + h.t * r.dir;
                            color = ray::whittedShade(accel, r, h, 0, S.maxDepth, counts);
                        } else if (along.empty() && l == envLayer) {
                            hit = false;  // the environment: colour, but no point of its own
                            color = sc.environment.lookup(r.dir);
                            sum[size_t(l)] += glm::vec4(glm::clamp(color, 0.0f, 1.0f), 1.0f);
                        }
                        if (hit) sum[size_t(l)] += glm::vec4(glm::clamp(color, 0.0f, 1.0f), 1.0f);
                        glm::vec3 p;
                        const Shell& shell = layers.shells[size_t(l)];
                        if (!layerPoint(shell, r.origin, r.dir, hit, hitPoint, p) ||
                            !onTexture(shell, r.origin, r.dir)) {
                            forced[size_t(l)] = 1;
                            continue;
                        }
                        conf[size_t(l)] += directConfidence(records[size_t(l)].nearest(p), d0[size_t(l)]);
                    }
                }
            for (int l = 0; l < nl; ++l) {
                const glm::vec4 v = sum[size_t(l)] * inv;
                for (int c = 0; c < 4; ++c) out.b[size_t(l)].at(x, y, c) = std::isfinite(v[c]) ? v[c] : 0.0f;
                out.confidence[size_t(l)].at(x, y, 0) = forced[size_t(l)] ? 0.0f : conf[size_t(l)] * inv;
            }
        }
    });
    return out;
}

// ---- A: the shell seen from the camera ------------------------------------------------------

pem::IsolatingRendering directIsolating(raster::Device& device, const ray::Camera& camera,
                                        const Shell& shell, const pem::TexelLayout& layout,
                                        int subsample) {
    pem::IsolatingRendering r;
    r.layout = layout;
    r.subsample = std::max(1, subsample);
    r.sampler = HybridRenderer::layerSampler();
    r.render = [&device, camera, shell](const std::shared_ptr<const tex::Texture>& texture,
                                        const tex::SamplerState& sampler) {
        const auto& fb = device.framebuffer();
        const int DW = fb.width(), DH = fb.height();
        // A grid of 4-subpixel cells one cell beyond the edges; each vertex at unit distance
        // along its camera ray (beyond the near plane at 0.1), carrying the shell coordinate
        // of that ray (000 §5: hit − origin, unnormalised; (s, t) on a quad).
        constexpr int kCell = 4;
        const int gx = DW / kCell + 3, gy = DH / kCell + 3;
        std::vector<raster::Vertex> vs(size_t(gx) * size_t(gy));
        for (int j = 0; j < gy; ++j)
            for (int i = 0; i < gx; ++i) {
                const float px = float((i - 1) * kCell), py = float((j - 1) * kCell);
                const ray::Ray ray = ray::primaryRay(camera, DW, DH, px, py);
                const glm::vec3 d = glm::normalize(ray.dir);
                raster::Vertex& v = vs[size_t(j) * size_t(gx) + size_t(i)];
                v.position = glm::vec4(ray.origin + d, 1.0f);
                v.tex[0] = shell.texCoord(ray.origin, d);
            }
        std::vector<uint32_t> idx;
        for (int j = 0; j + 1 < gy; ++j)
            for (int i = 0; i + 1 < gx; ++i) {
                const uint32_t a = uint32_t(j * gx + i), b = a + 1, c = a + uint32_t(gx), d = c + 1;
                idx.insert(idx.end(), {a, c, b, b, c, d});
            }
        device.beginFrame();
        device.setTransforms(glm::mat4(1.0f), pem::viewMatrix(camera),
                             pem::projectionMatrix(camera, DW, DH));
        device.setViewport({0, 0, DW, DH, 0.0f, 1.0f});
        tex::TextureUnits& tu = device.textureUnits();
        for (int s = 0; s < device.profile().maxTextureStages; ++s) tu.setStage(s, {});
        raster::PipelineState st;
        st.cull = raster::CullMode::None;
        st.colorWriteMask = 0;
        device.setState(st);
        device.clear(true, {0, 0, 0, 0}, true, 1.0f);
        device.beginPass("isolate: depth of the direct image's shell");
        device.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, vs, idx);
        device.beginPass("isolate: direct image texels");
        st.colorWriteMask = raster::kWriteRGBA;
        st.depthFunc = CompareFunc::Equal;
        st.depthWrite = 0;
        device.setState(st);
        tex::StageState s0;
        s0.colorOp = TextureOp::SelectArg1;
        s0.colorArg1 = arg::Texture;
        s0.alphaOp = TextureOp::SelectArg1;
        s0.alphaArg1 = arg::Texture;
        s0.texCoordIndex = 0;
        tu.setStage(0, s0);
        tu.setSampler(0, sampler);
        tu.setTexture(0, texture);
        device.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, vs, idx);
        device.endFrame();
        tu.setStage(0, {});
        tu.setTexture(0, nullptr);
    };
    return r;
}

}  // namespace rg::hybrid
