// Replay: a fresh Device of the trace's profile, driven record by record
// (docs/trace-format.md, "Playing a trace").
#include <algorithm>

#include "core/profile.h"
#include "rasterizer/device.h"
#include "rasterizer/trace.h"
#include "trace_io.h"

namespace rg::raster {

ReplayResult replayTrace(const Trace& trace, const ReplayOptions& options,
                         std::shared_ptr<TraceRecorder> recorder) {
    if (trace.programmable) return detail::replayProgrammableTrace(trace, options, recorder);
    // A copy: the explanation replays of `retroglass conform` change its subpixel bits.
    Profile profile = profileByName(trace.profile);
    if (options.subpixelBits > 0) {
        if (options.subpixelBits > 8)
            throw TraceError("replay: " + std::to_string(options.subpixelBits) +
                             " subpixel bits (at most 8: the integer widths of docs/hardware.md)");
        profile.subpixelBits = options.subpixelBits;
    }
    Device dev(profile, trace.width, trace.height, trace.depth, {options.path, options.threads});
    if (!trace.initialColor.empty())
        std::copy(trace.initialColor.begin(), trace.initialColor.end(), dev.framebuffer().color().begin());
    // Without a Framebuffer record the capture started all zero, depth included
    // (docs/trace-format.md, "Framebuffer"): the recorder leaves the record out only then.
    // A fresh Device starts its depth at the far value, so it is zeroed here, not left.
    if (!trace.initialDepth.empty())
        std::copy(trace.initialDepth.begin(), trace.initialDepth.end(), dev.framebuffer().depth().begin());
    else
        std::fill(dev.framebuffer().depth().begin(), dev.framebuffer().depth().end(), 0u);
    if (options.stopAfterPass >= trace.passCount())
        throw TraceError("--pass " + std::to_string(options.stopAfterPass) + ": the trace has " +
                         std::to_string(trace.passCount()) + " passes (0.." +
                         std::to_string(trace.passCount() - 1) + ")");

    // Textures are created on first bind, once per content hash, in the profile's memory.
    auto memory = std::make_shared<tex::TextureMemory>(profile);
    dev.textureUnits().setTextureMemory(memory);
    std::map<uint64_t, std::shared_ptr<const tex::Texture>> made;
    auto texture = [&](uint64_t id) -> std::shared_ptr<const tex::Texture> {
        if (id == 0) return nullptr;
        if (auto it = made.find(id); it != made.end()) return it->second;
        const TraceTexture& t = trace.textures.at(id);
        std::shared_ptr<tex::Texture> tx = memory->create(t.desc);
        const int faces = tx->faces();
        for (int l = 0; l < t.desc.levels; ++l)
            for (int f = 0; f < faces; ++f)
                memory->upload(*tx, l, f, t.levelFaces.at(size_t(l * faces + f)));
        made.emplace(id, tx);
        return tx;
    };

    if (options.fragmentObserver) dev.setFragmentObserver(options.fragmentObserver);
    if (recorder) dev.setRecorder(recorder);
    ReplayResult result;
    tex::TextureUnits& tu = dev.textureUnits();
    for (const TraceCommand& c : trace.commands) {
        if (options.stopAfterPass >= 0 && result.passes > options.stopAfterPass &&
            (c.op == TraceOp::BeginPass || c.op == TraceOp::EndFrame))
            break;  // pass K has ended: its state is what the caller asked for
        switch (c.op) {
            case TraceOp::State: dev.setState(c.state); break;
            case TraceOp::Transforms: dev.setTransforms(c.world, c.view, c.projection); break;
            case TraceOp::Viewport: dev.setViewport(c.viewport); break;
            case TraceOp::Scissor: dev.setScissor(c.rect); break;
            case TraceOp::Stage: tu.setStage(c.unit, c.stage); break;
            case TraceOp::Sampler: tu.setSampler(c.unit, c.sampler); break;
            case TraceOp::TextureFactor: tu.setTextureFactor(c.color); break;
            case TraceOp::TexGen: tu.setTexGen(c.unit, c.texGen); break;
            case TraceOp::ColorTable: tu.setColorTable(c.unit, c.colorTable); break;
            case TraceOp::PixelTexture: tu.setPixelTexture(c.pixelTexture); break;
            case TraceOp::BindTexture: tu.setTexture(c.unit, texture(c.textureId)); break;
            case TraceOp::BeginFrame: dev.beginFrame(); break;
            case TraceOp::BeginPass:
                dev.beginPass(c.label);
                ++result.passes;
                break;
            case TraceOp::EndFrame: dev.endFrame(); break;
            case TraceOp::Clear: dev.clear(c.clearColor, c.color, c.clearDepth, c.depthValue); break;
            case TraceOp::Draw: dev.draw(c.primitive, c.space, c.vertices, c.indices); break;
            case TraceOp::DrawPixels:
                dev.drawPixels(c.rect.x, c.rect.y, c.rect.width, c.rect.height, c.pixels);
                break;
            case TraceOp::CopyPixels:
                dev.copyPixels(c.rect.x, c.rect.y, c.rect.width, c.rect.height, c.dstX, c.dstY);
                break;
            case TraceOp::ReadPixels: {
                std::vector<Rgba8> px = dev.readPixels(c.rect.x, c.rect.y, c.rect.width, c.rect.height);
                ++result.readBacks;
                if (traceHash64(px.data(), px.size() * sizeof(Rgba8)) != c.textureId)
                    ++result.readBackMismatches;
                break;
            }
            default: break;
        }
    }
    if (recorder) dev.setRecorder(nullptr);
    result.framebuffer = dev.framebuffer();
    if (options.hash) result.hash = framebufferHash(result.framebuffer);
    return result;
}

}  // namespace rg::raster
