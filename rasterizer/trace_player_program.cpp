// Replay of a programmable (version 2) trace: a fresh ProgrammableDevice of the trace's
// profile, driven record by record (docs/trace-format.md, "Playing a trace").
#include <cstring>
#include <map>
#include <memory>

#include "core/error.h"
#include "core/profile.h"
#include "rasterizer/program_registry.h"
#include "rasterizer/programmable_device.h"
#include "rasterizer/trace.h"
#include "texunit/format.h"
#include "trace_io.h"

namespace rg::raster {

namespace {

// Writes a render target's stored values (renderTargetValues() layout) into it.
void setTargetValues(tex::Texture& t, std::span<const uint8_t> values) {
    size_t at = 0;
    auto take = [&](void* dst, size_t n) {
        std::memcpy(dst, values.data() + at, n);
        at += n;
    };
    for (int l = 0; l < t.levels(); ++l) {
        const auto& s = t.levelSize(l);
        const size_t count = size_t(s[0]) * size_t(s[1]) * size_t(s[2]) * size_t(s[3]);
        for (int f = 0; f < t.faces(); ++f) {
            if (!t.isFloat())
                take(t.renderData8(l, f), count * sizeof(Rgba8));
            else if (t.singleChannel())
                take(t.renderDataR(l, f), count * sizeof(float));
            else
                take(t.renderDataF(l, f), count * sizeof(glm::vec4));
        }
    }
}

// The stored values of one level and face (what the image hash covers).
std::vector<uint8_t> levelValues(const tex::Texture& t, int level, int face) {
    const auto& s = t.levelSize(level);
    const size_t count = size_t(s[0]) * size_t(s[1]) * size_t(s[2]) * size_t(s[3]);
    std::vector<uint8_t> out;
    auto put = [&](const void* p, size_t n) {
        const auto* b = static_cast<const uint8_t*>(p);
        out.insert(out.end(), b, b + n);
    };
    if (!t.isFloat())
        put(t.data8(level, face), count * sizeof(Rgba8));
    else if (t.singleChannel())
        put(t.dataR(level, face), count * sizeof(float));
    else
        put(t.dataF(level, face), count * sizeof(glm::vec4));
    return out;
}

}  // namespace

ReplayResult detail::replayProgrammableTrace(const Trace& trace, const ReplayOptions& options,
                                             const std::shared_ptr<TraceRecorder>& recorder) {
    const Profile& profile = profileByName(trace.profile);
    if (options.stopAfterPass >= 0)
        throw TraceError("--pass " + std::to_string(options.stopAfterPass) +
                         ": a programmable trace has no passes; replay it without --pass");
    // Declared before the device, so that they outlive it: a recorder attached to the
    // device hashes the targets when the device detaches it.
    tex::TextureMemory memory(profile);
    std::map<uint64_t, std::shared_ptr<tex::Texture>> made;  // textures and render targets
    ProgrammableDevice dev(profile, {options.path, options.threads});

    // Textures and render targets are created at their first use, once per id.
    auto texture = [&](uint64_t id) -> std::shared_ptr<tex::Texture> {
        if (id == 0) return nullptr;
        if (auto it = made.find(id); it != made.end()) return it->second;
        std::shared_ptr<tex::Texture> tx;
        if (auto rt = trace.renderTargets.find(id); rt != trace.renderTargets.end()) {
            tx = memory.createRenderTarget(rt->second.desc);
            if (!rt->second.contents.empty()) setTargetValues(*tx, rt->second.contents);
        } else {
            const TraceTexture& t = trace.textures.at(id);
            tx = memory.create(t.desc);
            const int faces = tx->faces();
            for (int l = 0; l < t.desc.levels; ++l)
                for (int f = 0; f < faces; ++f) memory.upload(*tx, l, f, t.levelFaces.at(size_t(l * faces + f)));
        }
        made.emplace(id, tx);
        return tx;
    };

    if (recorder) dev.setRecorder(recorder);
    for (const TraceCommand& c : trace.commands) {
        switch (c.op) {
            case TraceOp::RenderTargets: {
                std::vector<ColorTarget> colors;
                for (const TraceTargetBinding& b : c.colorTargets) colors.push_back({texture(b.id), b.level, b.face});
                DepthTarget depth;
                if (c.depthTarget.id) depth = {texture(c.depthTarget.id), c.depthTarget.level, c.depthTarget.face};
                dev.setRenderTargets(colors, depth);
                break;
            }
            case TraceOp::ProgramState: dev.setState(c.programState); break;
            case TraceOp::Viewport: dev.setViewport(c.viewport); break;
            case TraceOp::ProgramScissor: dev.setScissor(c.scissorOn ? &c.rect : nullptr); break;
            case TraceOp::ProgramTexture: dev.setTexture(c.unit, texture(c.textureId), c.sampler); break;
            case TraceOp::BeginFrame: dev.beginFrame(); break;
            case TraceOp::ClearTarget: dev.clearColor(c.unit, c.clearValue); break;
            case TraceOp::ClearDepth: dev.clearDepth(c.depthValue); break;
            case TraceOp::ProgramDraw: {
                const TraceProgramDraw& d = c.programDraw;
                d.program->draw(dev, d.vertexProgram, d.fragmentProgram, d.primitive, d.vertices, c.indices);
                break;
            }
            default: break;  // the reader admits no other kinds in a programmable trace
        }
    }
    if (recorder) dev.setRecorder(nullptr);

    ReplayResult result;
    // Every target the capture hashed against what the replay left in it.
    for (const auto& [id, hash] : trace.targetHashes) {
        ++result.targetChecks;
        const std::shared_ptr<tex::Texture> t = texture(id);
        const std::vector<uint8_t> values = renderTargetValues(*t);
        if (traceHash64(values.data(), values.size()) != hash) ++result.targetMismatches;
    }
    // The image: colour target 0 of the last binding, as RGBA8 and hashed as stored.
    if (trace.image.id) {
        const std::shared_ptr<tex::Texture> t = texture(trace.image.id);
        const int level = trace.image.level, face = trace.image.face;
        const auto& s = t->levelSize(level);
        result.framebuffer = Framebuffer(s[0], s[1], DepthFormat::None);
        Rgba8* out = result.framebuffer.color().data();
        const size_t count = size_t(s[0]) * size_t(s[1]);
        for (size_t i = 0; i < count; ++i) {
            const int x = int(i % size_t(s[0])), y = int(i / size_t(s[0]));
            out[i] = t->isFloat() ? tex::floatToRgba8(t->texelFloat(level, face, x, y, 0, 0))
                                  : t->texel8(level, face, x, y, 0, 0);
        }
        if (options.hash) {
            const std::vector<uint8_t> values = levelValues(*t, level, face);
            result.hash = sha256Hex(values.data(), values.size());
        }
    } else if (options.hash) {
        result.hash = sha256Hex(nullptr, 0);
    }
    return result;
}

}  // namespace rg::raster
