// The retroglass side of the impostor_secant and impostor_height workloads
// (bench/impostor_peers_workload.h): the inputs on a geforce8800 programmable device bound as
// ImpostorRenderer::drawGlass binds them, and one frame = clear, then every draw through
// GlassFP or GlassHeightFP, in one batch. Shared by the benchmark and tests/peer (which compares it with
// llvmpipe's frame and with the renderer's own).
#pragma once

#include <cstring>
#include <memory>
#include <span>
#include <vector>

#include "core/profile.h"
#include "impostor_peers_workload.h"
#include "rasterizer/programmable_device.h"
#include "texunit/texture.h"

namespace rg::bench::impostor_peers {

struct ImpostorPeerScene {
    const Inputs& in;
    tex::TextureMemory memory{profile(ProfileId::GeForce8800)};
    std::vector<std::shared_ptr<tex::Texture>> env, refractors, heights;
    std::shared_ptr<tex::Texture> target, depth;
    raster::ProgrammableDevice device;
    tex::SamplerState point;

    explicit ImpostorPeerScene(const Inputs& inputs, int threads, Path path = Path::Fast)
        : in(inputs), device(profile(ProfileId::GeForce8800), raster::DeviceOptions{path, threads}) {
        // The cubes as render targets of the renderer's format, filled with the frame's
        // texels (already binary16 values: the device stores what it rendered).
        auto cube = [&](const Cube& c) {
            tex::TextureDesc d;
            d.target = tex::TextureTarget::CubeMap;
            d.format = tex::TexelFormat::RGBA16F;
            d.width = d.height = c.size;
            auto t = memory.createRenderTarget(d);
            for (int f = 0; f < 6; ++f)
                std::memcpy(t->renderDataF(0, f), c.faces[size_t(f)].data(),
                            c.faces[size_t(f)].size() * sizeof(glm::vec4));
            return t;
        };
        for (const Cube& c : in.env) env.push_back(cube(c));
        for (const Cube& c : in.refractors) refractors.push_back(cube(c));
        // The height maps uploaded as the renderer uploads them (RGBA32F, one level).
        for (const HeightMap& h : in.heights) {
            tex::TextureDesc d;
            d.format = tex::TexelFormat::RGBA32F;
            d.width = d.height = h.size;
            auto t = memory.create(d);
            memory.upload(*t, 0, 0,
                          std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(h.texels.data()),
                                                   h.texels.size() * sizeof(glm::vec4)));
            heights.push_back(t);
        }
        tex::TextureDesc td;
        td.width = kWidth;
        td.height = kHeight;
        target = memory.createRenderTarget(td);
        td.format = tex::TexelFormat::Depth24;
        depth = memory.createRenderTarget(td);
        raster::ColorTarget ct{target};
        device.setRenderTargets({&ct, 1}, raster::DepthTarget{depth});
        point.magFilter = point.minFilter = tex::FilterMode::Nearest;
        point.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                         tex::AddressMode::ClampToEdge};
    }

    void frame() {
        device.clearColor(0, glm::vec4(0.0f));
        device.clearDepth(1.0f);
        raster::ProgramState st;
        st.cull = raster::CullMode::CW;  // the camera view's back faces (ImpostorRenderer::cameraView)
        st.depthTest = st.depthWrite = 1;
        device.setState(st);
        impostors::WorldVP vp;
        vp.viewProj = in.viewProj;
        impostors::GlassConstants k;
        for (int c = 0; c < 3; ++c) k.eye[c] = in.eye[c];
        k.iterations = in.iterations;
        // The draws as one batch, as ImpostorRenderer's glass pass issues them (and as
        // llvmpipe defers a frame's draws to its scene).
        raster::ProgramBatch batch(device);
        for (const Draw& d : in.draws) {
            k.self = d.frame;
            const std::span<const impostors::ImpostorVertex> vertices(in.vertices.data() + d.firstVertex, d.vertexCount);
            const std::span<const uint32_t> indices(in.indices.data() + d.firstIndex, d.indexCount);
            device.setTexture(impostors::kUnitEnv, env[size_t(d.env)], point);
            if (in.exit == Exit::Secant) {
                device.setTexture(impostors::kUnitRefractor, refractors[size_t(d.refractor)], point);
                impostors::GlassFP<false, false> fp;
                fp.k = k;
                impostors::drawTriangles(device, vp, fp, vertices, indices);
            } else {
                device.setTexture(impostors::kUnitHeight, heights[size_t(d.refractor)], point);
                impostors::GlassHeightFP<false, false> fp;
                fp.h.k = k;
                fp.h.self = in.heights[size_t(d.refractor)].frame;
                impostors::drawHeightGlass(device, vp, fp, vertices, indices);
            }
        }
        batch.end();
    }

    // The target's RGBA8 bytes, row 0 at the top.
    std::vector<uint8_t> image() {
        const Rgba8* p = target->renderData8(0, 0);
        std::vector<uint8_t> out(size_t(kWidth) * kHeight * 4);
        std::memcpy(out.data(), p, out.size());
        return out;
    }
};

}  // namespace rg::bench::impostor_peers
