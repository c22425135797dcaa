// One polygon, one 4D texture: the uncompressed §5 route.
#include "lf4d_renderer.h"

#include "core/error.h"
#include "gortler_renderer.h"
#include "vq.h"

namespace rg::lightfield {

LightFieldTexture4D::LightFieldTexture4D(std::shared_ptr<tex::TextureMemory> memory, const LightField& lf) {
    const Profile& p = memory->profile();
    p.require(Feature::Texture4D, "4D-texture rendering of a light field (Heidrich et al. 1999 §5)");
    if (lf.channels != 3) throw Error("lf 4D: only RGB light fields are drawn as a 4D texture");
    // The light field's [t][s][v][u] order is the 4D texture's (x, y, z, w) = (u, v, s, t).
    texture_ = memory->create({tex::TextureTarget::Texture4D, tex::TexelFormat::RGB8, lf.slab.U, lf.slab.V, lf.slab.S, lf.slab.T, 1});
    memory->upload(*texture_, 0, 0, lf.data);
}

LightField4DStats renderLightField4D(raster::Device& dev, const LightFieldTexture4D& tx, const LightSlab& s,
                                     const ray::Camera& camera) {
    const int w = dev.framebuffer().width(), h = dev.framebuffer().height();
    dev.setTransforms(glm::mat4(1.0f), viewMatrix(camera), projectionMatrix(camera, w, h));
    dev.setViewport({0, 0, w, h, 0.0f, 1.0f});
    dev.clear(true, {0, 0, 0, 0}, false, 1.0f);
    tex::TextureUnits& tu = dev.textureUnits();
    tex::SamplerState linear;
    linear.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                      tex::AddressMode::ClampToEdge};
    tex::TexGenState tg;
    tg.projected = true;
    tu.setTexGen(0, tg);
    tu.setColorTable(0, nullptr);
    tu.setTexture(0, tx.texture());
    tu.setSampler(0, linear);
    tu.setStage(0, tex::texEnvStage(tex::TexEnvMode::Replace, tex::BaseFormat::Rgb));
    raster::PipelineState st = additiveState();
    st.blend = 0;
    dev.setState(st);
    const glm::vec2 corner[6] = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
    std::vector<raster::Vertex> verts(6);
    for (int k = 0; k < 6; ++k) {
        verts[size_t(k)].position = glm::vec4(s.windowPoint(corner[k].x, corner[k].y), 1.0f);
        verts[size_t(k)].diffuse = {255, 255, 255, 255};
        verts[size_t(k)].tex[0] = window4DCoords(s, camera.eye, corner[k].x, corner[k].y);
    }
    const uint64_t f0 = dev.counters().fragmentsGenerated;
    dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, verts);
    return {dev.counters().fragmentsGenerated - f0};
}

}  // namespace rg::lightfield
