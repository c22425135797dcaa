#include "hybrid_renderer.h"

#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "pem_renderer.h"
#include "texunit/stages.h"

namespace rg::hybrid {

using raster::BlendFactor;
using raster::CompareFunc;
using tex::TextureOp;
namespace arg = tex::arg;

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}
const char* termName(int term) { return term == 0 ? "reflection" : "refraction"; }
}  // namespace

glm::mat4 viewProjection(const ray::Camera& camera, int width, int height) {
    return pem::projectionMatrix(camera, width, height) * pem::viewMatrix(camera);
}

tex::SamplerState HybridRenderer::layerSampler() { return pem::PemRenderer::cubeSampler(); }

uint64_t HybridRenderer::sampleBytes(const std::vector<LensLayers>& layers) {
    uint64_t bytes = 0;
    for (const LensLayers& L : layers)
        for (int l = 0; l < L.layers(); ++l)
            if (!L.shares(l)) bytes += uint64_t(L.layout(l).count()) * 4;  // a shared map once
    return bytes;
}

HybridRenderer::HybridRenderer(raster::Device& device, std::shared_ptr<tex::TextureMemory> memory,
                               LensScene& scene, std::vector<LensLayers> layers, int subsample,
                               TessellationSettings tessellation)
    : device_(device),
      memory_(std::move(memory)),
      scene_(scene),
      layers_(std::move(layers)),
      subsample_(std::max(1, subsample)),
      tess_(tessellation) {
    if (layers_.size() != scene_.objects().size())
        throw Error("hybrid: one set of layers per lens object is needed");
    device_.textureUnits().setTextureMemory(memory_);
    lerpInPass_ = device_.profile().maxTextureStages >= 3;
    const int sets = device_.profile().maxTexCoordSets;
    for (size_t i = 0; i < layers_.size(); ++i) {
        const LensObject& lens = scene_.objects()[i];
        const int n = layers_[i].layers();
        if (n <= 0)
            throw Error("hybrid: lens object '" + lens.name + "' has no EM layer");
        const int needed = (lens.twoTerms ? 2 : 1) * n;
        if (needed > sets)
            throw Error("hybrid: lens object '" + lens.name + "' has " + std::to_string(n) +
                        " layers; " + std::to_string(needed) + " texture-coordinate sets (terms × "
                        "layers) exceed the " + std::string(device_.profile().name) + "'s " +
                        std::to_string(sets));
    }
    meshes_.resize(layers_.size());
    vertices_.resize(layers_.size());
    indices_.resize(layers_.size());
    used_.resize(layers_.size());
    fg_.resize(layers_.size());
}

void HybridRenderer::setCamera() {
    const auto& fb = device_.framebuffer();
    device_.setTransforms(glm::mat4(1.0f), pem::viewMatrix(camera_),
                          pem::projectionMatrix(camera_, fb.width(), fb.height()));
    device_.setViewport({0, 0, fb.width(), fb.height(), 0.0f, 1.0f});
}

void HybridRenderer::prepare(const ray::Camera& camera, bool counting) {
    camera_ = camera;
    const auto& fb = device_.framebuffer();
    ScreenSpace screen;
    screen.viewProjection = viewProjection(camera, fb.width(), fb.height());
    screen.width = fb.width();
    screen.height = fb.height();
    screen.eye = camera.eye;
    counts_ = FrameCounts{};
    texgenS_ = 0;
    tbb::task_arena arena(tess_.threads > 0 ? tess_.threads : tbb::task_arena::automatic);
    for (size_t i = 0; i < layers_.size(); ++i) {
        const LensObject& lens = scene_.objects()[i];
        const ray::Accel& local = counting ? scene_.countingLocal(i) : *lens.local;
        const ray::Accel& vis = counting ? scene_.countingVisibility() : scene_.visibility();
        meshes_[i] = tessellateAdaptively(lens, local, vis, screen, tess_);
        const AdaptiveMesh& mesh = meshes_[i];
        for (size_t k = 0; k < counts_.rays.n.size(); ++k) counts_.rays.n[k] += mesh.stats.rays.n[k];
        counts_.verticesTraced += mesh.stats.verticesTraced();
        counts_.trianglesOut += mesh.stats.outputTriangles;
        counts_.maxLevel = std::max(counts_.maxLevel, mesh.stats.maxLevel);

        // ---- texture coordinates and F·G per vertex -----------------------------------
        auto t0 = Clock::now();
        const LensLayers& L = layers_[i];
        const int n = L.layers();
        const int terms = lens.twoTerms ? 2 : 1;
        // The vertices the triangles use, numbered afresh: Device::draw transforms every
        // vertex of the array, and the back faces' ones and the unused are half of them.
        std::vector<uint32_t>& used = used_[i];
        std::vector<uint32_t> slot(mesh.positions.size(), ~0u);
        used.clear();
        indices_[i].resize(mesh.indices.size());
        for (size_t k = 0; k < mesh.indices.size(); ++k) {
            uint32_t& s = slot[mesh.indices[k]];
            if (s == ~0u) {
                s = uint32_t(used.size());
                used.push_back(mesh.indices[k]);
            }
            indices_[i][k] = s;
        }
        auto& vs = vertices_[i];
        vs.resize(used.size());
        for (int t = 0; t < 2; ++t) fg_[i][size_t(t)].assign(used.size(), Rgba8{0, 0, 0, 255});
        arena.execute([&] {
            tbb::parallel_for(size_t(0), used.size(), [&](size_t c) {
                const size_t v = used[c];
                raster::Vertex& vx = vs[c];
                vx.position = glm::vec4(mesh.positions[v], 1.0f);
                vx.normal = mesh.normals[v];
                vx.diffuse = {255, 255, 255, 255};
                if (!mesh.traced[v]) return;
                const ray::PathSummary* paths[2] = {&mesh.traces[v].paths.reflect,
                                                    &mesh.traces[v].paths.refract};
                for (int t = 0; t < terms; ++t) {
                    // A path that died (depth budget, TIR at the first interface) has
                    // F·G = 0; its coordinates follow the other term's exit, else the
                    // view ray, so that they stay near its neighbours'.
                    const ray::PathSummary* p = paths[t]->valid ? paths[t]
                                                : paths[1 - t]->valid ? paths[1 - t] : nullptr;
                    const glm::vec3 o = p ? p->exitRay.origin : mesh.positions[v];
                    const glm::vec3 d = p ? p->exitRay.dir
                                          : glm::normalize(mesh.positions[v] - camera.eye);
                    for (int l = 0; l < n; ++l)
                        vx.tex[size_t(t * n + l)] = L.shells[size_t(l)].texCoord(o, d);
                    if (paths[t]->valid) {
                        const glm::vec3 fg = glm::clamp(paths[t]->F * paths[t]->G, 0.0f, 1.0f);
                        fg_[i][size_t(t)][c] = {uint8_t(std::lround(fg.r * 255.0f)),
                                                uint8_t(std::lround(fg.g * 255.0f)),
                                                uint8_t(std::lround(fg.b * 255.0f)), 255};
                    }
                }
            });
        });
        texgenS_ += since(t0);
    }
}

void drawAlphaClear(raster::Device& device_, const std::string& label) {
    // 000 §5: "a polygon that multiplies the framebuffer's rgb values by 1 and its alpha
    // by 0": src·ZERO + dst·SRCCOLOR with src = (255, 255, 255, 0); mulDiv255(x, 255) = x.
    device_.beginPass(label);
    raster::PipelineState st;
    st.cull = raster::CullMode::None;
    st.depthTest = 0;
    st.depthWrite = 0;
    st.blend = 1;
    st.srcBlend = BlendFactor::Zero;
    st.dstBlend = BlendFactor::SrcColor;
    device_.setState(st);
    // Every stage disabled: D3D7 then passes the diffuse colour through (stage 0's
    // D3DTOP_DISABLE), which is what SELECTARG1(DIFFUSE) would give, and the device takes
    // its untextured path: the polygon's constant colour blended span by span instead of
    // a stage cascade per quad over the whole screen (2 ms of the interactive frame each).
    tex::TextureUnits& tu = device_.textureUnits();
    for (int s = 0; s < device_.profile().maxTextureStages; ++s) tu.setStage(s, {});
    const float w = float(device_.framebuffer().width()), h = float(device_.framebuffer().height());
    raster::Vertex q[4];
    const glm::vec2 corners[4] = {{0, 0}, {w, 0}, {w, h}, {0, h}};
    for (int k = 0; k < 4; ++k) {
        q[k].position = glm::vec4(corners[k], 0.0f, 1.0f);
        q[k].diffuse = {255, 255, 255, 0};
    }
    const uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    device_.draw(raster::Primitive::TriangleList, raster::VertexSpace::Pretransformed, q, idx);
}

void HybridRenderer::draw(const SampleMaps& a, const SampleMaps* b, float wB) {
    if (b && !(wB >= 0.0f && wB <= 1.0f)) throw Error("hybrid: blend weight outside [0, 1]");
    device_.beginFrame();
    setCamera();
    raster::PipelineState st;
    st.cull = raster::CullMode::CW;  // back faces (clockwise in window space) culled
    device_.setState(st);
    device_.clear(true, {0, 0, 0, 0}, true, 1.0f);
    tex::TextureUnits& tu = device_.textureUnits();
    counts_.layerPasses = 0;
    counts_.alphaClears = 0;
    struct Sequence {
        int term;
        const SampleMaps* maps;
        float weight;
    };
    for (size_t i = 0; i < layers_.size(); ++i) {
        const LensObject& lens = scene_.objects()[i];
        const LensLayers& L = layers_[i];
        const int n = L.layers();
        const AdaptiveMesh& mesh = meshes_[i];
        if (mesh.indices.empty()) continue;
        std::vector<Sequence> seqs;
        for (int t = 0; t < (lens.twoTerms ? 2 : 1); ++t) {
            seqs.push_back({t, &a, b && !lerpInPass_ ? 1.0f - wB : 1.0f});
            if (b && !lerpInPass_) seqs.push_back({t, b, wB});
        }
        auto& vs = vertices_[i];
        for (size_t k = 0; k < seqs.size(); ++k) {
            const Sequence& q = seqs[k];
            if (q.maps->maps.size() != layers_.size() || q.maps->maps[i].size() != size_t(n))
                throw Error("hybrid: sample " + std::to_string(q.maps->view) +
                            " has no maps for lens object '" + lens.name + "'");
            const bool lerp = b && lerpInPass_;
            if (lerp && (b->maps.size() != layers_.size() || b->maps[i].size() != size_t(n)))
                throw Error("hybrid: sample " + std::to_string(b->view) +
                            " has no maps for lens object '" + lens.name + "'");
            const std::string sample =
                lerp ? "samples " + std::to_string(a.view) + " and " + std::to_string(b->view) +
                           " lerped (weight " + std::to_string(wB).substr(0, 4) + ")"
                     : "sample " + std::to_string(q.maps->view) +
                           (b ? " (weight " + std::to_string(q.weight).substr(0, 4) + ")" : "");
            if (k > 0) {
                drawAlphaClear(device_, "alpha clear before " + lens.name + " " +
                                            termName(q.term) + ", " + sample);
                ++counts_.alphaClears;
            }
            for (size_t v = 0; v < vs.size(); ++v) vs[v].diffuse = fg_[i][size_t(q.term)][v];
            tex::StageState s0;
            s0.colorOp = TextureOp::Modulate;
            s0.colorArg1 = arg::Texture;
            s0.colorArg2 = arg::Diffuse;
            s0.alphaOp = TextureOp::SelectArg1;
            s0.alphaArg1 = arg::Texture;
            tex::StageState s1, s2;
            if (lerp) {
                // Stage 1 lerps to sample b's texel by TFACTOR.a, stage 2 applies F·G.
                s0.colorOp = TextureOp::SelectArg1;
                s1.colorOp = TextureOp::BlendFactorAlpha;
                s1.colorArg1 = arg::Texture;
                s1.colorArg2 = arg::Current;
                s1.alphaOp = TextureOp::BlendFactorAlpha;
                s1.alphaArg1 = arg::Texture;
                s1.alphaArg2 = arg::Current;
                s2.colorOp = TextureOp::Modulate;
                s2.colorArg1 = arg::Current;
                s2.colorArg2 = arg::Diffuse;
                s2.alphaOp = TextureOp::SelectArg1;
                s2.alphaArg1 = arg::Current;
                tu.setTextureFactor({0, 0, 0, uint8_t(std::lround(wB * 255.0f))});
            } else if (b) {
                s1.colorOp = TextureOp::Modulate;
                s1.colorArg1 = arg::Current;
                s1.colorArg2 = arg::TFactor;
                s1.alphaOp = TextureOp::SelectArg1;
                s1.alphaArg1 = arg::Current;
                const uint8_t w8 = uint8_t(std::lround(q.weight * 255.0f));
                tu.setTextureFactor({w8, w8, w8, 255});
            }
            for (int l = 0; l < n; ++l) {
                const Shell& shell = L.shells[size_t(l)];
                device_.beginPass(lens.name + " " + termName(q.term) + ", L" + std::to_string(l + 1) +
                                  " (" + shellKindName(shell.kind) + ", r " +
                                  std::to_string(L.assignment.layers.at(size_t(l)).radius).substr(0, 5) +
                                  "), " + sample);
                raster::PipelineState ps = st;
                if (k == 0 && l == 0) {
                    ps.depthFunc = CompareFunc::LessEqual;
                    ps.depthWrite = 1;
                    ps.blend = 0;
                } else {
                    ps.depthFunc = CompareFunc::Equal;
                    ps.depthWrite = 0;
                    ps.blend = 1;
                    ps.srcBlend = BlendFactor::InvDestAlpha;
                    ps.dstBlend = BlendFactor::One;
                }
                device_.setState(ps);
                s0.texCoordIndex = uint8_t(q.term * n + l);
                tu.setStage(0, s0);
                tu.setSampler(0, layerSampler());
                tu.setTexture(0, q.maps->maps[i][size_t(l)]);
                s1.texCoordIndex = s0.texCoordIndex;
                tu.setStage(1, s1);
                if (lerp) {
                    tu.setSampler(1, layerSampler());
                    tu.setTexture(1, b->maps[i][size_t(l)]);
                    tu.setStage(2, s2);
                }
                for (int s = lerp ? 3 : 2; s < device_.profile().maxTextureStages; ++s) tu.setStage(s, {});
                device_.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed,
                             vs, indices_[i]);
                ++counts_.layerPasses;
            }
        }
    }
    device_.endFrame();
    for (int s = 0; s < device_.profile().maxTextureStages; ++s) {
        tu.setStage(s, {});
        tu.setTexture(s, nullptr);
    }
}

FrameTimes HybridRenderer::render(const ray::Camera& camera, const SampleMaps& a,
                                  const SampleMaps* b, float wB) {
    FrameTimes t;
    prepare(camera);
    for (const AdaptiveMesh& m : meshes_) {
        t.vertexRaysS += m.stats.traceSeconds;
        t.tessellationS += m.stats.tessellateSeconds;
    }
    t.texgenS = texgenS_;
    auto t0 = Clock::now();
    draw(a, b, wB);
    t.drawS = since(t0);
    t0 = Clock::now();
    (void)displayImage();
    t.downsampleS = since(t0);
    return t;
}

ray::Image HybridRenderer::displayImage(ray::Image* coverage) const {
    const raster::Framebuffer& fb = device_.framebuffer();
    const int s = subsample_, W = fb.width() / s, H = fb.height() / s;
    ray::Image out(W, H, 3);
    if (coverage) *coverage = ray::Image(W, H, 1);
    const uint32_t far = fb.depthMax();
    const float inv = 1.0f / float(s * s * 255);
    const auto color = fb.color();
    const auto depth = fb.depth();
    // Rows over the renderer's threads, each pixel written straight into the image (a
    // call of Image::setRgb per pixel and one thread made this 2 % of the interactive
    // frame). The same float operations per pixel: the same bytes on any thread count.
    tbb::task_arena arena(tess_.threads > 0 ? tess_.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(0, H, [&](int y) {
            float* row = out.pixels.data() + size_t(y) * size_t(W) * 3;
            float* cov = coverage ? coverage->pixels.data() + size_t(y) * size_t(W) : nullptr;
            for (int x = 0; x < W; ++x) {
                int r = 0, g = 0, bl = 0, drawn = 0;
                for (int sy = 0; sy < s; ++sy)
                    for (int sx = 0; sx < s; ++sx) {
                        const size_t i =
                            size_t(y * s + sy) * size_t(fb.width()) + size_t(x * s + sx);
                        r += color[i].r;
                        g += color[i].g;
                        bl += color[i].b;
                        drawn += depth.empty() ? 0 : depth[i] < far ? 1 : 0;
                    }
                const glm::vec3 v = glm::vec3(float(r), float(g), float(bl)) * inv;
                row[3 * x] = v.r;
                row[3 * x + 1] = v.g;
                row[3 * x + 2] = v.b;
                if (cov) cov[x] = float(drawn) / float(s * s);
            }
        });
    });
    return out;
}

void HybridRenderer::drawLevels() {
    device_.beginFrame();
    setCamera();
    raster::PipelineState st;
    st.cull = raster::CullMode::CW;
    st.shade = raster::ShadeMode::Flat;
    device_.setState(st);
    device_.clear(true, {0, 0, 0, 0}, true, 1.0f);
    // Every stage disabled: D3D7 passes the diffuse colour through (stage 0's
    // D3DTOP_DISABLE), the level's flat shade, and the device draws it untextured.
    tex::TextureUnits& tu = device_.textureUnits();
    for (int s = 0; s < device_.profile().maxTextureStages; ++s) tu.setStage(s, {});
    for (size_t i = 0; i < meshes_.size(); ++i) {
        const AdaptiveMesh& m = meshes_[i];
        device_.beginPass(scene_.objects()[i].name + ": subdivision level (Figure 5)");
        // Unshared vertices so each triangle is flat in its own level's shade.
        std::vector<raster::Vertex> vs;
        vs.reserve(m.indices.size());
        for (size_t t = 0; t < m.indices.size() / 3; ++t) {
            const int level = m.triangleLevel[t];
            const uint8_t shade = uint8_t(std::max(40, 235 - 28 * level));
            for (int k = 0; k < 3; ++k) {
                raster::Vertex v;
                v.position = glm::vec4(m.positions[m.indices[3 * t + size_t(k)]], 1.0f);
                v.diffuse = {shade, shade, shade, 255};
                vs.push_back(v);
            }
        }
        if (!vs.empty())
            device_.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, vs);
    }
    device_.endFrame();
    tu.setStage(0, {});
}

pem::IsolatingRendering HybridRenderer::isolating(size_t lens, int term, int layer) {
    pem::IsolatingRendering r;
    r.layout = layers_.at(lens).layout(layer);
    r.subsample = subsample_;
    r.sampler = layerSampler();
    r.render = [this, lens, term, layer](const std::shared_ptr<const tex::Texture>& texture,
                                         const tex::SamplerState& sampler) {
        auto& vs = vertices_.at(lens);
        device_.beginFrame();
        setCamera();
        tex::TextureUnits& tu = device_.textureUnits();
        for (int s = 0; s < device_.profile().maxTextureStages; ++s) tu.setStage(s, {});
        raster::PipelineState st;
        st.cull = raster::CullMode::CW;
        st.colorWriteMask = 0;
        device_.setState(st);
        device_.clear(true, {0, 0, 0, 0}, true, 1.0f);
        device_.beginPass("isolate: depth of " + scene_.objects()[lens].name);
        device_.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, vs,
                     indices_.at(lens));
        device_.beginPass("isolate: " + scene_.objects()[lens].name + " " + termName(term) +
                          " L" + std::to_string(layer + 1) + " texels");
        st.colorWriteMask = raster::kWriteRGBA;
        st.depthFunc = CompareFunc::Equal;
        st.depthWrite = 0;
        device_.setState(st);
        tex::StageState s0;
        s0.colorOp = TextureOp::SelectArg1;
        s0.colorArg1 = arg::Texture;
        s0.alphaOp = TextureOp::SelectArg1;
        s0.alphaArg1 = arg::Texture;
        s0.texCoordIndex = uint8_t(term * layers_.at(lens).layers() + layer);
        tu.setStage(0, s0);
        tu.setSampler(0, sampler);
        tu.setTexture(0, texture);
        device_.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, vs,
                     indices_.at(lens));
        device_.endFrame();
        tu.setStage(0, {});
        tu.setTexture(0, nullptr);
    };
    return r;
}

std::shared_ptr<const tex::Texture> HybridRenderer::uploadMap(size_t lens, int layer,
                                                              const std::vector<Rgba8>& texels) {
    const pem::TexelLayout layout = layers_.at(lens).layout(layer);
    if (int64_t(texels.size()) != layout.count())
        throw Error("hybrid: a layer map of the wrong size");
    return pem::makeMapFromTexels(*memory_, layout,
                                  [&](int64_t i) { return texels[size_t(i)]; });
}

}  // namespace rg::hybrid
