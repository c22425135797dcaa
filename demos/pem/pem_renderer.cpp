#include "pem_renderer.h"

#include <chrono>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "core/error.h"
#include "texunit/stages.h"

namespace rg::pem {

using raster::BlendFactor;
using raster::CompareFunc;
using tex::TextureOp;
namespace arg = tex::arg;

const char* emModeName(EmMode mode) {
    switch (mode) {
        case EmMode::Layered: return "layered_pem";
        case EmMode::SingleInfinite: return "single_infinite_pem";
        case EmMode::Static: return "static_em";
        case EmMode::Ptm: return "ptm";
    }
    return "?";
}

glm::mat4 viewMatrix(const ray::Camera& c) { return glm::lookAtRH(c.eye, c.target, c.up); }

glm::mat4 projectionMatrix(const ray::Camera& c, int width, int height) {
    // Direct3D clip volume 0 ≤ z ≤ w; the same vertical field of view as the ray
    // tracer's pinhole (camera.h), so both images line up pixel for pixel.
    return glm::perspectiveRH_ZO(glm::radians(c.fovYDegrees), float(width) / float(height), 0.1f,
                                 100.0f);
}

tex::SamplerState PemRenderer::cubeSampler() {
    tex::SamplerState s;
    s.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                 tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge};
    s.magFilter = tex::FilterMode::Linear;
    s.minFilter = tex::FilterMode::Linear;
    s.mipFilter = tex::MipMode::Linear;  // trilinear: every inferred MIPMAP level is used
    return s;
}

tex::SamplerState PemRenderer::fresnelSampler() {
    tex::SamplerState s = cubeSampler();
    s.mipFilter = tex::MipMode::None;
    return s;
}

PemRenderer::PemRenderer(raster::Device& device, const PemScene& scene)
    : device_(device), scene_(scene) {
    memory_ = std::make_shared<tex::TextureMemory>(device.profile());
    // Upload bytes per frame show in the device's counters (texture download was the
    // paper viewer's bottleneck, 001 §6).
    device.textureUnits().setTextureMemory(memory_);
    const ray::Material& m =
        scene.scene.materials.at(scene.scene.objects.at(size_t(scene.object)).material);
    fresnel_ = makeFresnelTexture(*memory_, m.fresnel == ray::MirrorFresnel::Schlick
                                                ? m.reflectance
                                                : glm::vec3(1.0f));
    for (const PemPart& p : scene.parts) {
        vertices_.emplace_back(p.positions.size());
        all_.push_back(p.indices);
        std::vector<uint32_t> off;
        for (size_t t = 0; t < p.onHull.size(); ++t)
            if (!p.onHull[t])
                off.insert(off.end(), p.indices.begin() + 3 * t, p.indices.begin() + 3 * t + 3);
        offHull_.push_back(std::move(off));
    }
}

void PemRenderer::setCameraTransforms(const ray::Camera& camera) {
    const auto& fb = device_.framebuffer();
    device_.setTransforms(glm::mat4(1.0f), viewMatrix(camera),
                          projectionMatrix(camera, fb.width(), fb.height()));
    device_.setViewport({0, 0, fb.width(), fb.height(), 0.0f, 1.0f});
}

void PemRenderer::prepare(const ray::Camera& camera, EmMode mode) {
    for (size_t i = 0; i < scene_.parts.size(); ++i) {
        generateEmTexCoords(scene_.parts[i], camera.eye, coords_);
        auto& vs = vertices_[i];
        const PemPart& p = scene_.parts[i];
        for (size_t v = 0; v < vs.size(); ++v) {
            vs[v].position = glm::vec4(p.positions[v], 1.0f);
            vs[v].normal = p.normals[v];
            vs[v].diffuse = {255, 255, 255, 255};
            vs[v].tex[0] = mode == EmMode::Layered ? coords_.distant[v] : coords_.infinite[v];
            vs[v].tex[1] = coords_.local[v];
            vs[v].tex[2] = coords_.fresnel[v];
            vs[v].tex[3] = glm::vec4(p.atlasUv[v], 0.0f, 1.0f);
        }
    }
}

void PemRenderer::drawAll(size_t part, bool offHullOnly) {
    const auto& idx = offHullOnly ? offHull_[part] : all_[part];
    if (idx.empty()) return;
    device_.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed,
                 vertices_[part], idx);
}

FrameTiming PemRenderer::render(const ray::Camera& camera, EmMode mode, const PemSample& a,
                                const PemSample* b, float w) {
    using Clock = std::chrono::steady_clock;
    FrameTiming timing;
    auto t0 = Clock::now();
    prepare(camera, mode);
    auto t1 = Clock::now();

    if (mode == EmMode::Static && b) throw Error("PEM: a static EM has no second sample");
    device_.beginFrame();
    setCameraTransforms(camera);
    raster::PipelineState st;
    // Back faces culled, as a Direct3D 7 application would: the mesh winds counter-
    // clockwise seen from outside, which is clockwise in window space (y down).
    st.cull = raster::CullMode::CW;
    st.depthTest = 1;
    st.depthWrite = 1;
    st.depthFunc = CompareFunc::LessEqual;
    device_.setState(st);
    device_.clear(true, {0, 0, 0, 255}, true, 1.0f);

    tex::TextureUnits& tu = device_.textureUnits();
    auto cubeStage = [&](int stage, int set, TextureOp op, uint8_t alphaArg) {
        tex::StageState s;
        s.colorOp = op;
        s.colorArg1 = arg::Texture;
        s.colorArg2 = arg::Current;
        s.alphaOp = op == TextureOp::SelectArg1 ? TextureOp::SelectArg1 : op;
        s.alphaArg1 = alphaArg;
        s.alphaArg2 = arg::Current;
        s.texCoordIndex = uint8_t(set);
        tu.setStage(stage, s);
        tu.setSampler(stage, cubeSampler());
    };
    auto fresnelStage = [&](int stage) {
        tex::StageState s;
        s.colorOp = TextureOp::Modulate;
        s.colorArg1 = arg::Texture;
        s.colorArg2 = arg::Current;
        s.alphaOp = TextureOp::SelectArg2;  // keep α from the EM stage
        s.alphaArg1 = arg::Texture;
        s.alphaArg2 = arg::Current;
        s.texCoordIndex = 2;
        tu.setStage(stage, s);
        tu.setSampler(stage, fresnelSampler());
        tu.setTexture(stage, fresnel_);
    };
    auto disableFrom = [&](int stage) {
        for (int s = stage; s < device_.profile().maxTextureStages; ++s) tu.setStage(s, {});
    };
    const size_t parts = scene_.parts.size();
    // The map a pass-1 draw of part p reads, and the coordinate set indexing it.
    const int baseSet = mode == EmMode::Ptm ? 3 : 0;
    auto baseOf = [&](const PemSample& s, size_t p) -> const std::shared_ptr<const tex::Texture>& {
        if (mode == EmMode::Ptm) return s.ptm.at(p);
        if (mode == EmMode::Static) return s.distant.at(0);
        return s.distant.at(p);
    };

    if (!b) {
        // ---- pass 1: D·F -------------------------------------------------------------
        device_.beginPass("reflector: distant EM x Fresnel");
        cubeStage(0, baseSet, TextureOp::SelectArg1, arg::Texture);
        fresnelStage(1);
        disableFrom(2);
        for (size_t p = 0; p < parts; ++p) {
            tu.setTexture(0, baseOf(a, p));
            drawAll(p, false);
        }
        ++timing.reflectorPasses;
        if (mode == EmMode::Layered) {
            // ---- pass 2: (L·F) over, α_L -----------------------------------------------
            device_.beginPass("reflector: local EM over, x Fresnel");
            raster::PipelineState s2 = st;
            s2.depthFunc = CompareFunc::Equal;
            s2.depthWrite = 0;
            s2.blend = 1;
            s2.srcBlend = BlendFactor::SrcAlpha;
            s2.dstBlend = BlendFactor::InvSrcAlpha;
            device_.setState(s2);
            cubeStage(0, 1, TextureOp::SelectArg1, arg::Texture);
            fresnelStage(1);
            for (size_t p = 0; p < parts; ++p) {
                tu.setTexture(0, a.local.at(p));
                drawAll(p, true);
            }
            ++timing.reflectorPasses;
        }
    } else {
        if (w < 0.0f || w > 1.0f) throw Error("PEM: blend weight outside [0, 1]");
        uint8_t wa = uint8_t(std::lround(w * 255.0f));
        tu.setTextureFactor({0, 0, 0, wa});
        // ---- pass 1: lerp(D_i, D_j) ------------------------------------------------------
        device_.beginPass("reflector: distant EMs blended between samples");
        cubeStage(0, baseSet, TextureOp::SelectArg1, arg::Texture);
        cubeStage(1, baseSet, TextureOp::BlendFactorAlpha, arg::Texture);
        disableFrom(2);
        for (size_t p = 0; p < parts; ++p) {
            tu.setTexture(0, baseOf(a, p));
            tu.setTexture(1, baseOf(*b, p));
            drawAll(p, false);
        }
        ++timing.reflectorPasses;
        raster::PipelineState s2 = st;
        s2.depthFunc = CompareFunc::Equal;
        s2.depthWrite = 0;
        s2.blend = 1;
        if (mode == EmMode::Layered) {
            // ---- pass 2: lerp(L_i, L_j) over -------------------------------------------
            device_.beginPass("reflector: local EMs blended, over");
            s2.srcBlend = BlendFactor::SrcAlpha;
            s2.dstBlend = BlendFactor::InvSrcAlpha;
            device_.setState(s2);
            cubeStage(0, 1, TextureOp::SelectArg1, arg::Texture);
            cubeStage(1, 1, TextureOp::BlendFactorAlpha, arg::Texture);
            for (size_t p = 0; p < parts; ++p) {
                tu.setTexture(0, a.local.at(p));
                tu.setTexture(1, b->local.at(p));
                drawAll(p, true);
            }
            ++timing.reflectorPasses;
        }
        // ---- pass 3: × F ---------------------------------------------------------------
        device_.beginPass("reflector: x Fresnel (modulate framebuffer)");
        s2.srcBlend = BlendFactor::DestColor;
        s2.dstBlend = BlendFactor::Zero;
        device_.setState(s2);
        tex::StageState f;
        f.colorOp = TextureOp::SelectArg1;
        f.colorArg1 = arg::Texture;
        f.alphaOp = TextureOp::SelectArg1;
        f.alphaArg1 = arg::Texture;
        f.texCoordIndex = 2;
        tu.setStage(0, f);
        tu.setSampler(0, fresnelSampler());
        tu.setTexture(0, fresnel_);
        disableFrom(1);
        for (size_t p = 0; p < parts; ++p) drawAll(p, false);
        ++timing.reflectorPasses;
    }
    device_.endFrame();
    disableFrom(0);
    auto t2 = Clock::now();
    timing.texgenMs = std::chrono::duration<double, std::milli>(t1 - t0).count();
    timing.drawMs = std::chrono::duration<double, std::milli>(t2 - t1).count();
    return timing;
}

}  // namespace rg::pem
