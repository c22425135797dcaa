// The retroglass side of the tir_final_pass workload (bench/tir_final_pass_workload.h): the
// inputs on a geforce8800 programmable device bound as TirRenderer's pass 4 binds them, and
// one frame = clear, then the refractor through TirFP. Shared by the benchmark and
// tests/peer (which compares it with llvmpipe's frame and with the renderer's own).
#pragma once

#include <cstring>
#include <memory>
#include <span>
#include <vector>

#include "core/profile.h"
#include "rasterizer/programmable_device.h"
#include "texunit/texture.h"
#include "tir_final_pass_workload.h"

namespace rg::bench::tir_final_pass {

struct TirFinalPassScene {
    const Inputs& in;
    tex::TextureMemory memory{profile(ProfileId::GeForce8800)};
    std::shared_ptr<tex::Texture> back, front, nearby, env, target, depth;
    raster::ProgrammableDevice device;

    explicit TirFinalPassScene(const Inputs& inputs, int threads, Path path = Path::Fast)
        : in(inputs), device(profile(ProfileId::GeForce8800), raster::DeviceOptions{path, threads}) {
        // The maps and the environment as render targets of pass 1–3's formats, filled with
        // the frame's texels (already binary16 values: the device stores what it rendered).
        tex::TextureDesc md;
        md.format = tex::TexelFormat::RGBA16F;
        md.width = kWidth;
        md.height = kHeight;
        auto map = [&](const std::vector<glm::vec4>& texels) {
            auto t = memory.createRenderTarget(md);
            std::memcpy(t->renderDataF(0, 0), texels.data(), texels.size() * sizeof(glm::vec4));
            return t;
        };
        back = map(in.back);
        front = map(in.front);
        nearby = map(in.nearby);
        tex::TextureDesc ed = md;
        ed.target = tex::TextureTarget::CubeMap;
        ed.width = ed.height = in.envSize;
        env = memory.createRenderTarget(ed);
        for (int f = 0; f < 6; ++f)
            std::memcpy(env->renderDataF(0, f), in.env[size_t(f)].data(),
                        in.env[size_t(f)].size() * sizeof(glm::vec4));
        tex::TextureDesc td;
        td.width = kWidth;
        td.height = kHeight;
        target = memory.createRenderTarget(td);
        td.format = tex::TexelFormat::Depth24;
        depth = memory.createRenderTarget(td);

        raster::ColorTarget ct{target};
        device.setRenderTargets({&ct, 1}, raster::DepthTarget{depth});
        // Pass 4's units and samplers (TirRenderer::render).
        tex::SamplerState point;
        point.magFilter = point.minFilter = tex::FilterMode::Nearest;
        point.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                         tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge};
        device.setTexture(tir::kUnitBack, back, point);
        device.setTexture(tir::kUnitFront, front, point);
        device.setTexture(tir::kUnitNearby, nearby, point);
        device.setTexture(tir::kUnitEnv, env, tex::SamplerState{});  // bilinear, face edges clamp
    }

    void frame() {
        device.clearColor(0, glm::vec4(0.0f));
        device.clearDepth(1.0f);
        raster::ProgramState st;
        st.cull = raster::CullMode::CW;  // the refractor's front faces, as pass 4
        st.depthTest = st.depthWrite = 1;
        device.setState(st);
        tir::TirFP fp;
        fp.k = in.k;
        device.draw(in.vp, fp, raster::ProgramPrimitive::TriangleList,
                    std::span<const tir::TirVertex>(in.vertices), std::span<const uint32_t>(in.indices));
    }

    // The target's RGBA8 bytes, row 0 at the top.
    std::vector<uint8_t> image() {
        const Rgba8* p = target->renderData8(0, 0);
        std::vector<uint8_t> out(size_t(kWidth) * kHeight * 4);
        std::memcpy(out.data(), p, out.size());
        return out;
    }
};

}  // namespace rg::bench::tir_final_pass
