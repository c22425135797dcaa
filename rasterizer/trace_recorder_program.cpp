// Capture of the programmable device (docs/trace-format.md, version 2): at each command the
// ProgrammableDevice feeds the recorder, which writes the state the command reads where it
// differs from what the trace has said (render targets, program state, viewport, scissor,
// the units the fragment program declares), then the command.
#include <algorithm>
#include <cstring>

#include "core/error.h"
#include "rasterizer/program_registry.h"
#include "rasterizer/programmable_device.h"
#include "rasterizer/trace.h"
#include "trace_io.h"
#include "trace_recorder_impl.h"

namespace rg::raster {

using detail::ByteWriter;

namespace {

bool sameBytes(const void* a, const void* b, size_t n) { return std::memcmp(a, b, n) == 0; }

// ProgramState's fields (its padding byte is not state).
bool sameProgramState(const ProgramState& a, const ProgramState& b) {
    return a.cull == b.cull && a.depthTest == b.depthTest && a.depthWrite == b.depthWrite &&
           a.depthFunc == b.depthFunc && sameBytes(&a.pointSize, &b.pointSize, sizeof a.pointSize) &&
           a.blend == b.blend;
}

void writeSampler(ByteWriter& w, const tex::SamplerState& sa) {
    for (auto a : sa.address) w.u8(uint8_t(a));
    w.u8(uint8_t(sa.magFilter));
    w.u8(uint8_t(sa.minFilter));
    w.u8(uint8_t(sa.mipFilter));
    w.f32(sa.lodBias);
    w.f32(sa.minLod);
    w.f32(sa.maxLod);
    w.i32(sa.baseLevel);
    w.i32(sa.maxLevel);
    w.rgba(sa.borderColor);
}

// A sampler as the trace stores it: compared field by field, so padding plays no part.
bool sameSampler(const tex::SamplerState& a, const tex::SamplerState& b) {
    std::vector<uint8_t> x, y;
    ByteWriter wx{x}, wy{y};
    writeSampler(wx, a);
    writeSampler(wy, b);
    return x == y;
}

}  // namespace

uint64_t renderTargetValueBytes(const tex::TextureDesc& desc) {
    const tex::FormatInfo& fi = tex::formatInfo(desc.format);
    const bool one = desc.format == tex::TexelFormat::R16F || desc.format == tex::TexelFormat::R32F ||
                     fi.isDepth;
    const uint64_t perTexel = !fi.isFloat ? 4 : one ? 4 : 16;
    const int faces = desc.target == tex::TextureTarget::CubeMap ? 6 : 1;
    uint64_t n = 0;
    for (int l = 0; l < desc.levels; ++l) {
        const uint64_t w = uint64_t(std::max(1, desc.width >> l));
        const uint64_t h = desc.target == tex::TextureTarget::Texture1D ? 1 : uint64_t(std::max(1, desc.height >> l));
        n += w * h * uint64_t(faces) * perTexel;
    }
    return n;
}

std::vector<uint8_t> renderTargetValues(const tex::Texture& t) {
    std::vector<uint8_t> out;
    out.reserve(renderTargetValueBytes(t.desc()));
    ByteWriter w{out};
    for (int l = 0; l < t.levels(); ++l) {
        const auto& s = t.levelSize(l);
        const size_t count = size_t(s[0]) * size_t(s[1]) * size_t(s[2]) * size_t(s[3]);
        for (int f = 0; f < t.faces(); ++f) {
            if (!t.isFloat())
                w.raw(t.data8(l, f), count * sizeof(Rgba8));
            else if (t.singleChannel())
                w.raw(t.dataR(l, f), count * sizeof(float));
            else
                w.raw(t.dataF(l, f), count * sizeof(glm::vec4));
        }
    }
    return out;
}

uint64_t TraceRecorder::Impl::targetId(const std::shared_ptr<const tex::Texture>& target) {
    for (RenderTargetSeen& s : program.targets)
        if (s.address == target.get()) {
            if (!s.texture.expired()) return s.id;
            s.address = nullptr;  // that one is gone: this is a new texture at its address
        }
    const uint64_t id = program.nextTargetId++;
    program.targets.push_back({target, target.get(), id});
    const tex::TextureDesc& d = target->desc();
    size_t at = begin(TraceOp::RenderTarget);
    ByteWriter w{bytes};
    w.u64(id);
    w.u8(uint8_t(d.target));
    w.u8(uint8_t(d.format));
    w.i32(d.width);
    w.i32(d.height);
    w.i32(d.levels);
    // Its contents now, at the trace's first use, unless all zero (as created).
    std::vector<uint8_t> values = renderTargetValues(*target);
    const bool zero = std::all_of(values.begin(), values.end(), [](uint8_t b) { return b == 0; });
    w.u8(zero ? 0 : 1);
    if (!zero) w.raw(values.data(), values.size());
    end(at);
    return id;
}

void TraceRecorder::Impl::writeTargetHashes() {
    for (const RenderTargetSeen& s : program.targets) {
        const std::shared_ptr<const tex::Texture> t = s.texture.lock();
        if (!t || s.address != t.get()) continue;  // destroyed before the end: nothing to check
        const std::vector<uint8_t> values = renderTargetValues(*t);
        size_t at = begin(TraceOp::TargetHash);
        ByteWriter w{bytes};
        w.u64(s.id);
        w.u64(traceHash64(values.data(), values.size()));
        end(at);
    }
    program.detached = true;
}

void TraceRecorder::Impl::syncProgram(const ProgrammableDevice& dev, bool draw, uint32_t units) {
    ProgramSaid& p = program;
    ByteWriter w{bytes};
    const bool all = !p.known;
    p.known = true;

    // ---- render targets: the binding, then what setRenderTargets resets ----
    std::vector<TraceTargetBinding> colors;
    for (const ColorTarget& c : dev.colorTargets()) colors.push_back({targetId(c.texture), c.level, c.face});
    const DepthTarget& dt = dev.depthTarget();
    const TraceTargetBinding depth = dt.texture ? TraceTargetBinding{targetId(dt.texture), dt.level, dt.face}
                                                : TraceTargetBinding{};
    if (all || colors != p.colors || !(depth == p.depth)) {
        p.colors = colors;
        p.depth = depth;
        size_t at = begin(TraceOp::RenderTargets);
        w.u8(uint8_t(colors.size()));
        for (const TraceTargetBinding& b : colors) {
            w.u64(b.id);
            w.i32(b.level);
            w.i32(b.face);
        }
        w.u64(depth.id);
        w.i32(depth.level);
        w.i32(depth.face);
        end(at);
        // The replaying device's setRenderTargets resets the viewport to the whole target
        // and the scissor to off, as the capturing device's did.
        p.viewport = Viewport{0, 0, dev.targetWidth(), dev.targetHeight(), 0.0f, 1.0f};
        p.scissorOn = false;
    }

    if (draw && (!p.stateKnown || !sameProgramState(dev.state(), p.state))) {
        p.stateKnown = true;
        p.state = dev.state();
        const ProgramState& s = p.state;
        size_t at = begin(TraceOp::ProgramState);
        w.u8(uint8_t(s.cull));
        w.u8(s.depthTest);
        w.u8(s.depthWrite);
        w.u8(uint8_t(s.depthFunc));
        w.f32(s.pointSize);
        for (const TargetBlend& b : s.blend) {
            w.u8(b.enable);
            w.u8(uint8_t(b.src));
            w.u8(uint8_t(b.dst));
            w.u8(uint8_t(b.op));
            w.u8(b.writeMask);
        }
        end(at);
    }

    const Viewport& v = dev.viewport();
    if (!sameBytes(&v, &p.viewport, sizeof v)) {
        p.viewport = v;
        size_t at = begin(TraceOp::Viewport);
        w.i32(v.x); w.i32(v.y); w.i32(v.width); w.i32(v.height); w.f32(v.minZ); w.f32(v.maxZ);
        end(at);
    }

    const Rect* r = dev.scissor();
    if ((r != nullptr) != p.scissorOn || (r && !(*r == p.scissor))) {
        p.scissorOn = r != nullptr;
        if (r) p.scissor = *r;
        size_t at = begin(TraceOp::ProgramScissor);
        w.u8(r ? 1 : 0);
        const Rect rect = r ? *r : Rect{};
        w.i32(rect.x); w.i32(rect.y); w.i32(rect.width); w.i32(rect.height);
        end(at);
    }

    // ---- the units the fragment program reads: textures by content, targets by id ----
    for (int u = 0; u < kMaxProgramUnits; ++u) {
        if (!((units >> u) & 1u)) continue;
        const std::shared_ptr<const tex::Texture>& t = dev.texture(u);
        uint64_t id = 0;
        if (t && t->isRenderTarget()) {
            id = targetId(t);
        } else if (t) {
            id = detail::traceContentHash(*t) & ~(uint64_t{1} << 63);
            if (id == 0) id = 1;
            writeTexture(*t, id);
        }
        const tex::SamplerState& s = dev.sampler(u);
        if (p.unitKnown[size_t(u)] && p.unitTexture[size_t(u)] == id && sameSampler(s, p.unitSampler[size_t(u)]))
            continue;
        p.unitKnown[size_t(u)] = true;
        p.unitTexture[size_t(u)] = id;
        p.unitSampler[size_t(u)] = s;
        size_t at = begin(TraceOp::ProgramTexture);
        w.u8(uint8_t(u));
        w.u64(id);
        writeSampler(w, s);
        end(at);
    }
}

void TraceRecorder::attach(const ProgrammableDevice& dev) {
    Impl& m = *impl_;
    if (m.attached) throw Error("trace recorder: already attached to a device");
    m.attached = true;
    m.programmable = true;
    ByteWriter w{m.bytes};
    w.raw(kTraceMagic, 8);
    w.u32(kTraceVersionProgrammable);
    size_t at = m.begin(TraceOp::ProgrammableDevice);
    const std::string_view name = dev.profile().name;
    w.u8(uint8_t(name.size()));
    w.raw(name.data(), name.size());
    m.end(at);
}

void TraceRecorder::detach(const ProgrammableDevice&) {
    Impl& m = *impl_;
    if (m.finished || m.program.detached) return;
    m.writeTargetHashes();
}

void TraceRecorder::clearColor(const ProgrammableDevice& dev, int target, const glm::vec4& value) {
    impl_->syncProgram(dev, false, 0);
    size_t at = impl_->begin(TraceOp::ClearTarget);
    ByteWriter w{impl_->bytes};
    w.u8(uint8_t(target));
    w.raw(&value, sizeof value);  // 4 f32: x, y, z, w
    impl_->end(at);
}

void TraceRecorder::clearDepth(const ProgrammableDevice& dev, float value) {
    impl_->syncProgram(dev, false, 0);
    size_t at = impl_->begin(TraceOp::ClearDepth);
    ByteWriter w{impl_->bytes};
    w.f32(value);
    impl_->end(at);
}

void TraceRecorder::programDraw(const ProgrammableDevice& dev, std::type_index program,
                                std::span<const uint8_t> vertexProgram, std::span<const uint8_t> fragmentProgram,
                                uint32_t units, ProgramPrimitive primitive, std::span<const uint8_t> vertices,
                                uint32_t stride, std::span<const uint32_t> indices) {
    const RegisteredProgram* p = findProgram(program);
    if (!p)
        throw Error("trace capture: the draw's program is not registered (" + detail::programKeyName(program) +
                    "); register it with rg::raster::registerProgram<VP, FP, V>(\"name\") "
                    "(rasterizer/include/rasterizer/program_registry.h) before recording");
    impl_->syncProgram(dev, true, units);
    size_t at = impl_->begin(TraceOp::ProgramDraw);
    ByteWriter w{impl_->bytes};
    w.u8(uint8_t(p->name.size()));
    w.raw(p->name.data(), p->name.size());
    w.u8(uint8_t(primitive));
    w.u32(uint32_t(vertexProgram.size()));
    w.raw(vertexProgram.data(), vertexProgram.size());
    w.u32(uint32_t(fragmentProgram.size()));
    w.raw(fragmentProgram.data(), fragmentProgram.size());
    w.u32(stride);
    w.u32(uint32_t(vertices.size() / stride));
    w.u32(uint32_t(indices.size()));
    w.raw(vertices.data(), vertices.size());
    for (uint32_t i : indices) w.u32(i);
    impl_->end(at);
}

}  // namespace rg::raster
