// Reading a trace: framing, then each record's payload with its value ranges checked
// (docs/trace-format.md). Nothing is drawn here; the fuzz target fuzz/fuzz_trace_reader.cpp
// runs this on arbitrary bytes.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>

#include "core/profile.h"
#include "rasterizer/program_registry.h"
#include "rasterizer/trace.h"
#include "trace_io.h"

namespace rg::raster {

using detail::ByteReader;

namespace {

template <class E>
E enumValue(uint8_t v, E count, const char* what) {
    if (v >= uint8_t(count))
        throw TraceError(std::string(what) + " " + std::to_string(v) + " is out of range");
    return E(v);
}

constexpr int kMaxTextureEdge = 1 << 15;

int checkedIndex(uint8_t v, int limit, const char* what) {
    if (v >= limit) throw TraceError(std::string(what) + " " + std::to_string(v) + " is out of range");
    return v;
}

void readRect(ByteReader& r, Rect& rect) {
    rect.x = r.i32(); rect.y = r.i32(); rect.width = r.i32(); rect.height = r.i32();
}

// A boolean field is 0 or 1 (docs/trace-format.md, "Encoding"): 2…255 mean nothing.
uint8_t readBool(ByteReader& r, const std::string& where, const char* what) {
    const uint8_t v = r.u8();
    if (v > 1) throw TraceError(where + ": " + what + " " + std::to_string(v) + " is not a boolean (0 or 1)");
    return v;
}

// A rectangle of a version-1 pixel command inside the w×h framebuffer (what the device
// refuses otherwise): sizes ≥ 0, every pixel inside.
void checkInside(const Rect& rect, int w, int h, const std::string& where, const char* what) {
    if (rect.width < 0 || rect.height < 0 || rect.x < 0 || rect.y < 0 || int64_t(rect.x) + rect.width > w ||
        int64_t(rect.y) + rect.height > h)
        throw TraceError(where + ": " + what + " (" + std::to_string(rect.x) + ", " + std::to_string(rect.y) + ") " +
                         std::to_string(rect.width) + "x" + std::to_string(rect.height) + " is not inside the " +
                         std::to_string(w) + "x" + std::to_string(h) + " framebuffer");
}

// A D3DTA_ argument: a source 0…4 (Diffuse, Current, Texture, TFactor, Specular) with the
// Complement (0x10) and AlphaReplicate (0x20) flags; nothing else.
uint8_t readStageArg(ByteReader& r, const std::string& where) {
    const uint8_t a = r.u8();
    if ((a & tex::arg::SourceMask) > tex::arg::Specular ||
        (a & ~(tex::arg::SourceMask | tex::arg::Complement | tex::arg::AlphaReplicate)) != 0)
        throw TraceError(where + ": stage argument " + std::to_string(a) + " is not a D3DTA_ value");
    return a;
}

void readSampler(ByteReader& r, tex::SamplerState& s) {
    for (auto& a : s.address) a = enumValue(r.u8(), tex::AddressMode(5), "address mode");
    s.magFilter = enumValue(r.u8(), tex::FilterMode(2), "mag filter");
    s.minFilter = enumValue(r.u8(), tex::FilterMode(2), "min filter");
    s.mipFilter = enumValue(r.u8(), tex::MipMode(3), "mip filter");
    s.lodBias = r.f32(); s.minLod = r.f32(); s.maxLod = r.f32();
    s.baseLevel = r.i32(); s.maxLevel = r.i32();
    s.borderColor = r.rgba();
}

std::string hex(unsigned v) {
    const char* digits = "0123456789abcdef";
    return std::string("0x") + digits[(v >> 4) & 15] + digits[v & 15];
}

// The record kinds of each device (docs/trace-format.md, "Records"): a trace holds one
// device's records only.
bool fixedFunctionRecord(TraceOp op) {
    switch (op) {
        case TraceOp::Device: case TraceOp::Framebuffer: case TraceOp::State: case TraceOp::Transforms:
        case TraceOp::Viewport: case TraceOp::Scissor: case TraceOp::Stage: case TraceOp::Sampler:
        case TraceOp::TextureFactor: case TraceOp::TexGen: case TraceOp::ColorTable: case TraceOp::PixelTexture:
        case TraceOp::Texture: case TraceOp::BindTexture: case TraceOp::BeginFrame: case TraceOp::BeginPass:
        case TraceOp::EndFrame: case TraceOp::Clear: case TraceOp::Draw: case TraceOp::DrawPixels:
        case TraceOp::CopyPixels: case TraceOp::ReadPixels: case TraceOp::End:
            return true;
        default: return false;
    }
}

bool programmableRecord(TraceOp op) {
    switch (op) {
        case TraceOp::ProgrammableDevice: case TraceOp::Texture: case TraceOp::RenderTarget:
        case TraceOp::RenderTargets: case TraceOp::ProgramState: case TraceOp::Viewport:
        case TraceOp::ProgramScissor: case TraceOp::ProgramTexture: case TraceOp::BeginFrame:
        case TraceOp::ClearTarget: case TraceOp::ClearDepth: case TraceOp::ProgramDraw: case TraceOp::TargetHash:
        case TraceOp::End:
            return true;
        default: return false;
    }
}

bool versionTwoRecord(TraceOp op) { return programmableRecord(op) && !fixedFunctionRecord(op); }

// ---- version 2: the programmable device's records ----------------------------------------

// Extent of a render target's level in x and y.
std::array<int, 2> targetLevelSize(const tex::TextureDesc& d, int level) {
    return {std::max(1, d.width >> level),
            d.target == tex::TextureTarget::Texture1D ? 1 : std::max(1, d.height >> level)};
}

TraceRenderTarget readRenderTarget(ByteReader& r, const std::string& where) {
    TraceRenderTarget t;
    t.id = r.u64();
    if (t.id == 0) throw TraceError(where + ": render target id 0 is reserved");
    tex::TextureDesc& d = t.desc;
    d.target = enumValue(r.u8(), tex::TextureTarget(5), "render target kind");
    if (d.target != tex::TextureTarget::Texture1D && d.target != tex::TextureTarget::Texture2D &&
        d.target != tex::TextureTarget::CubeMap)
        throw TraceError(where + ": a render target is 1D, 2D or a cube map");
    d.format = enumValue(r.u8(), tex::TexelFormat::Count, "texel format");
    using tex::TexelFormat;
    switch (d.format) {
        case TexelFormat::RGBA8: case TexelFormat::R16F: case TexelFormat::RGBA16F: case TexelFormat::R32F:
        case TexelFormat::RGBA32F: case TexelFormat::Depth24: case TexelFormat::Depth32F: break;
        default:
            throw TraceError(where + ": " + std::string(tex::formatInfo(d.format).name) +
                             " is not a render-target format");
    }
    d.width = r.i32();
    d.height = r.i32();
    d.levels = r.i32();
    if (d.width < 1 || d.width > kMaxTextureEdge || d.height < 1 || d.height > kMaxTextureEdge)
        throw TraceError(where + ": render target extent out of range");
    if (d.target == tex::TextureTarget::Texture1D && d.height != 1)
        throw TraceError(where + ": a 1D render target has height 1");
    if (d.target == tex::TextureTarget::CubeMap && d.width != d.height)
        throw TraceError(where + ": cube map faces are square");
    if (d.levels < 1 || d.levels > tex::fullChainLevels(d))
        throw TraceError(where + ": render target level count out of range");
    const uint8_t hasContents = r.u8();
    if (hasContents > 1) throw TraceError(where + ": render target contents flag out of range");
    if (hasContents) {
        const uint64_t n = renderTargetValueBytes(d);
        r.need(n);  // before allocating: a hostile extent cannot exhaust memory
        t.contents.resize(n);
        r.raw(t.contents.data(), n);
    }
    return t;
}

// A RenderTargets attachment: a defined render target's existing level and face.
TraceTargetBinding readBinding(ByteReader& r, const Trace& trace, bool depth, const std::string& where) {
    TraceTargetBinding b;
    b.id = r.u64();
    b.level = r.i32();
    b.face = r.i32();
    if (b.id == 0) {
        if (!depth) throw TraceError(where + ": a colour target with id 0");
        return b;
    }
    auto it = trace.renderTargets.find(b.id);
    if (it == trace.renderTargets.end())
        throw TraceError(where + ": binds a render target the trace has not defined");
    const tex::TextureDesc& d = it->second.desc;
    if (tex::formatInfo(d.format).isDepth != depth)
        throw TraceError(where + (depth ? ": the depth target has a colour format" : ": a colour target has a depth format"));
    const int faces = d.target == tex::TextureTarget::CubeMap ? 6 : 1;
    if (b.level < 0 || b.level >= d.levels || b.face < 0 || b.face >= faces)
        throw TraceError(where + ": render target level or face out of range");
    return b;
}

void readRenderTargets(ByteReader& r, Trace& trace, TraceCommand& c, const std::string& where) {
    const uint8_t n = r.u8();
    if (n > kMaxColorTargets) throw TraceError(where + ": more than " + std::to_string(kMaxColorTargets) + " colour targets");
    for (int i = 0; i < n; ++i) c.colorTargets.push_back(readBinding(r, trace, false, where));
    c.depthTarget = readBinding(r, trace, true, where);
    // All attachments one size, as the device requires.
    std::vector<TraceTargetBinding> all = c.colorTargets;
    if (c.depthTarget.id) all.push_back(c.depthTarget);
    if (all.empty()) throw TraceError(where + ": no render target bound");
    const auto size = targetLevelSize(trace.renderTargets.at(all[0].id).desc, all[0].level);
    for (const TraceTargetBinding& b : all)
        if (targetLevelSize(trace.renderTargets.at(b.id).desc, b.level) != size)
            throw TraceError(where + ": render targets of different sizes");
    if (!c.colorTargets.empty()) trace.image = c.colorTargets[0];
}

void readProgramState(ByteReader& r, ProgramState& s, const std::string& where) {
    s.cull = enumValue(r.u8(), CullMode(3), "cull mode");
    s.depthTest = readBool(r, where, "depthTest");
    s.depthWrite = readBool(r, where, "depthWrite");
    s.depthFunc = enumValue(r.u8(), CompareFunc(8), "depth func");
    s.pointSize = r.f32();
    if (!(s.pointSize > 0.0f) || !(s.pointSize <= 8192.0f))
        throw TraceError(where + ": point size outside (0, 8192]");
    for (TargetBlend& b : s.blend) {
        b.enable = readBool(r, where, "blend enable");
        b.src = enumValue(r.u8(), BlendFactor(13), "source blend factor");
        b.dst = enumValue(r.u8(), BlendFactor(13), "destination blend factor");
        // Source factors that set the destination's too: no meaning as a destination.
        if (b.dst == BlendFactor::BothSrcAlpha || b.dst == BlendFactor::BothInvSrcAlpha)
            throw TraceError(where + ": BOTHSRCALPHA / BOTHINVSRCALPHA as a destination blend factor");
        b.op = enumValue(r.u8(), BlendOp(5), "blend op");
        b.writeMask = r.u8();
        if (b.writeMask > kWriteRGBA) throw TraceError(where + ": colour write mask out of range");
    }
}

void readProgramDraw(ByteReader& r, TraceCommand& c, const std::string& where) {
    TraceProgramDraw& d = c.programDraw;
    const uint8_t n = r.u8();
    std::string name(n, '\0');
    r.raw(name.data(), n);
    d.program = findProgram(name);
    if (!d.program) {
        std::string known;
        for (const std::string& k : registeredProgramNames()) known += (known.empty() ? "" : ", ") + k;
        throw TraceError(where + ": program '" + name + "' is not registered in this program (registered: " +
                         (known.empty() ? "none" : known) +
                         "); the module that defines it must call registerProgram<VP, FP, V>(\"" + name +
                         "\") before the trace is read");
    }
    d.primitive = enumValue(r.u8(), ProgramPrimitive(4), "primitive");
    auto object = [&](std::vector<uint8_t>& out, uint32_t expected, const char* what) {
        const uint32_t size = r.u32();
        if (size != expected)
            throw TraceError(where + ": the " + what + " of program '" + name + "' is " + std::to_string(size) +
                             " bytes in the trace, but " + std::to_string(expected) +
                             " in this program (" + d.program->types + ")");
        out.resize(size);
        r.raw(out.data(), size);
    };
    object(d.vertexProgram, d.program->vertexProgramBytes, "vertex program");
    object(d.fragmentProgram, d.program->fragmentProgramBytes, "fragment program");
    const uint32_t stride = r.u32();
    if (stride != d.program->vertexBytes)
        throw TraceError(where + ": the vertices of program '" + name + "' are " + std::to_string(stride) +
                         " bytes each in the trace, but " + std::to_string(d.program->vertexBytes) +
                         " in this program (" + d.program->types + ")");
    d.vertexCount = r.u32();
    const uint32_t ni = r.u32();
    r.need(uint64_t(d.vertexCount) * stride + uint64_t(ni) * 4);
    d.vertices.resize(size_t(d.vertexCount) * stride);
    r.raw(d.vertices.data(), d.vertices.size());
    c.indices.resize(ni);
    r.raw(c.indices.data(), size_t(ni) * 4);
    for (uint32_t i : c.indices)
        if (i >= d.vertexCount) throw TraceError(where + ": index " + std::to_string(i) + " past the vertices");
}

}  // namespace

int Trace::passCount() const {
    return int(std::count_if(commands.begin(), commands.end(),
                             [](const TraceCommand& c) { return c.op == TraceOp::BeginPass; }));
}

Trace readTrace(std::span<const uint8_t> bytes) {
    Trace trace;
    ByteReader file{bytes, 0, "trace header"};
    char magic[8];
    file.raw(magic, 8);
    if (std::memcmp(magic, kTraceMagic, 8) != 0) throw TraceError("not a retroglass trace (bad magic)");
    trace.version = file.u32();
    if (trace.version != kTraceVersionFixedFunction && trace.version != kTraceVersionProgrammable)
        throw TraceError("trace version " + std::to_string(trace.version) + " (this reader knows 1 and " +
                         std::to_string(kTraceVersion) + ")");
    bool haveDevice = false, ended = false, hashes = false;
    uint64_t depthMax = 0;  // the Device record's depth format's largest value
    size_t index = 0;
    while (!ended) {
        if (file.remaining() == 0) throw TraceError("trace is truncated (no End record)");
        const uint8_t op = file.u8();
        const uint32_t len = file.u32();
        file.need(len);
        ByteReader r{bytes.subspan(file.pos, len), 0, "trace record"};
        file.pos += len;
        const size_t number = index++;
        const std::string where = "record " + std::to_string(number);
        // Which kinds may appear: those of the trace's version, and of its device.
        const TraceOp kind = TraceOp(op);
        if (!fixedFunctionRecord(kind) && !programmableRecord(kind))
            throw TraceError(where + ": unknown record kind " + std::to_string(op));
        if (trace.version == kTraceVersionFixedFunction && versionTwoRecord(kind))
            throw TraceError(where + ": record kind " + hex(op) + " is a version 2 record in a version 1 trace");
        if (!haveDevice && kind != TraceOp::Device && kind != TraceOp::ProgrammableDevice)
            throw TraceError(where + ": the first record must be Device or ProgrammableDevice");
        if (haveDevice && (trace.programmable ? !programmableRecord(kind) : !fixedFunctionRecord(kind)))
            throw TraceError(where + ": record kind " + hex(op) + " belongs to the other device (this trace is of " +
                             (trace.programmable ? "the ProgrammableDevice)" : "the fixed-function Device)"));
        if (hashes && kind != TraceOp::TargetHash && kind != TraceOp::End)
            throw TraceError(where + ": only TargetHash records may follow a TargetHash record");
        TraceCommand c;
        c.op = TraceOp(op);
        switch (TraceOp(op)) {
            case TraceOp::Device: {
                if (haveDevice) throw TraceError(where + ": a second Device record");
                haveDevice = true;
                const uint8_t n = r.u8();
                trace.profile.resize(n);
                r.raw(trace.profile.data(), n);
                trace.width = r.i32();
                trace.height = r.i32();
                trace.depth = enumValue(r.u8(), DepthFormat(3), "depth format");
                if (trace.width <= 0 || trace.height <= 0 || trace.width > 16384 || trace.height > 16384)
                    throw TraceError(where + ": framebuffer size out of range");
                r.done();
                try {
                    (void)profileByName(trace.profile);
                } catch (const Error&) {
                    throw TraceError(where + ": unknown profile '" + trace.profile + "'");
                }
                depthMax = trace.depth == DepthFormat::D16 ? 0xffffu : trace.depth == DepthFormat::D24 ? 0xffffffu : 0u;
                continue;
            }
            case TraceOp::Framebuffer: {
                // Only right after the Device record: the contents the first command finds.
                if (number != 1)
                    throw TraceError(where + ": a Framebuffer record may only be the second record");
                const size_t n = size_t(trace.width) * size_t(trace.height);
                trace.initialColor.resize(n);
                r.raw(trace.initialColor.data(), n * 4);
                if (trace.depth != DepthFormat::None) {
                    trace.initialDepth.resize(n);
                    r.raw(trace.initialDepth.data(), n * 4);
                    for (uint32_t z : trace.initialDepth)
                        if (z > depthMax)
                            throw TraceError(where + ": depth value " + std::to_string(z) + " above the " +
                                             std::to_string(depthMax) + " of the depth format");
                }
                r.done();
                continue;
            }
            case TraceOp::Texture: {
                TraceTexture t;
                t.id = r.u64();
                t.desc.target = enumValue(r.u8(), tex::TextureTarget(5), "texture target");
                t.desc.format = enumValue(r.u8(), tex::TexelFormat::Count, "texel format");
                t.desc.width = r.i32(); t.desc.height = r.i32(); t.desc.depth = r.i32();
                t.desc.size4 = r.i32(); t.desc.levels = r.i32();
                for (int e : {t.desc.width, t.desc.height, t.desc.depth, t.desc.size4})
                    if (e < 1 || e > kMaxTextureEdge) throw TraceError(where + ": texture extent out of range");
                if (t.desc.levels < 1 || t.desc.levels > 16)
                    throw TraceError(where + ": texture level count out of range");
                if (t.id == 0) throw TraceError(where + ": texture id 0 is reserved");
                {
                    // Dimensions the target does not use are 1; levels at most the full
                    // chain of the used ones; cube faces square (what TextureMemory refuses).
                    const std::array<int, 4> ext{t.desc.width, t.desc.height, t.desc.depth, t.desc.size4};
                    const int dims = detail::traceDims(t.desc);
                    for (int d = dims; d < 4; ++d)
                        if (ext[size_t(d)] != 1)
                            throw TraceError(where + ": texture extent " + std::to_string(ext[size_t(d)]) +
                                             " in dimension " + std::to_string(d) + ", which its target does not use "
                                             "(must be 1)");
                    if (t.desc.levels > tex::fullChainLevels(t.desc))
                        throw TraceError(where + ": " + std::to_string(t.desc.levels) + " levels, more than the full "
                                         "chain's " + std::to_string(tex::fullChainLevels(t.desc)));
                    if (t.desc.target == tex::TextureTarget::CubeMap && t.desc.width != t.desc.height)
                        throw TraceError(where + ": cube map faces are square");
                }
                const int faces = detail::traceFaces(t.desc);
                for (int l = 0; l < t.desc.levels; ++l) {
                    // Bounded per dimension by 2^15 and checked against the bytes left
                    // before allocating, so a hostile size cannot exhaust memory.
                    uint64_t n = 1;
                    const std::array<int, 4> base{t.desc.width, t.desc.height, t.desc.depth, t.desc.size4};
                    for (int d = 0; d < 4; ++d) {
                        n *= uint64_t(std::max(1, base[size_t(d)] >> l));
                        if (n > r.remaining()) throw TraceError(where + ": texture data ends early");
                    }
                    const uint64_t levelBytes = detail::traceLevelBytes(t.desc, l);
                    for (int f = 0; f < faces; ++f) {
                        r.need(levelBytes);
                        std::vector<uint8_t> data(levelBytes);
                        r.raw(data.data(), levelBytes);
                        t.levelFaces.push_back(std::move(data));
                    }
                }
                r.done();
                if (trace.renderTargets.count(t.id) || !trace.textures.emplace(t.id, std::move(t)).second)
                    throw TraceError(where + ": texture defined twice");
                continue;
            }
            // ---- version 2 ----
            case TraceOp::ProgrammableDevice: {
                if (haveDevice) throw TraceError(where + ": a second device record");
                haveDevice = true;
                trace.programmable = true;
                const uint8_t n = r.u8();
                trace.profile.resize(n);
                r.raw(trace.profile.data(), n);
                r.done();
                const Profile* p = nullptr;
                try {
                    p = &profileByName(trace.profile);
                } catch (const Error&) {
                    throw TraceError(where + ": unknown profile '" + trace.profile + "'");
                }
                if (!p->has(Feature::VertexProgram) || !p->has(Feature::FragmentProgram))
                    throw TraceError(where + ": profile '" + trace.profile + "' has no programmable pipeline");
                continue;
            }
            case TraceOp::RenderTarget: {
                TraceRenderTarget t = readRenderTarget(r, where);
                r.done();
                if (trace.textures.count(t.id) || trace.renderTargets.count(t.id))
                    throw TraceError(where + ": render target defined twice");
                trace.renderTargets.emplace(t.id, std::move(t));
                continue;
            }
            case TraceOp::TargetHash: {
                const uint64_t id = r.u64();
                const uint64_t h = r.u64();
                r.done();
                if (!trace.renderTargets.count(id))
                    throw TraceError(where + ": a hash of a render target the trace has not defined");
                if (!trace.targetHashes.emplace(id, h).second)
                    throw TraceError(where + ": a second hash of one render target");
                hashes = true;
                continue;
            }
            case TraceOp::RenderTargets: readRenderTargets(r, trace, c, where); break;
            case TraceOp::ProgramState: readProgramState(r, c.programState, where); break;
            case TraceOp::ProgramScissor: {
                const uint8_t on = r.u8();
                if (on > 1) throw TraceError(where + ": scissor flag out of range");
                c.scissorOn = on != 0;
                readRect(r, c.rect);
                break;
            }
            case TraceOp::ProgramTexture:
                c.unit = checkedIndex(r.u8(), kMaxProgramUnits, "texture unit");
                c.textureId = r.u64();
                if (c.textureId != 0 && !trace.textures.count(c.textureId) && !trace.renderTargets.count(c.textureId))
                    throw TraceError(where + ": binds a texture the trace has not defined");
                readSampler(r, c.sampler);
                break;
            case TraceOp::ClearTarget:
                c.unit = checkedIndex(r.u8(), kMaxColorTargets, "colour target");
                r.raw(&c.clearValue, sizeof c.clearValue);
                break;
            case TraceOp::ClearDepth: c.depthValue = r.f32(); break;
            case TraceOp::ProgramDraw: readProgramDraw(r, c, where); break;
            case TraceOp::State: {
                PipelineState& s = c.state;
                s.cull = enumValue(r.u8(), CullMode(3), "cull mode");
                s.shade = enumValue(r.u8(), ShadeMode(2), "shade mode");
                s.depthTest = readBool(r, where, "depthTest");
                s.depthWrite = readBool(r, where, "depthWrite");
                s.depthFunc = enumValue(r.u8(), CompareFunc(8), "depth func");
                s.alphaTest = readBool(r, where, "alphaTest");
                s.alphaFunc = enumValue(r.u8(), CompareFunc(8), "alpha func");
                s.alphaRef = r.u8();
                s.blend = readBool(r, where, "blend");
                s.srcBlend = enumValue(r.u8(), BlendFactor(13), "source blend factor");
                s.dstBlend = enumValue(r.u8(), BlendFactor(13), "destination blend factor");
                s.blendOp = enumValue(r.u8(), BlendOp(5), "blend op");
                s.colorWriteMask = r.u8();
                if (s.colorWriteMask > kWriteRGBA)
                    throw TraceError(where + ": colour write mask " + std::to_string(s.colorWriteMask) +
                                     " has bits beyond RGBA");
                s.scissorTest = readBool(r, where, "scissorTest");
                s.specularEnable = readBool(r, where, "specularEnable");
                s.perspectiveColor = readBool(r, where, "perspectiveColor");
                break;
            }
            case TraceOp::Transforms:
                r.raw(&c.world, 64); r.raw(&c.view, 64); r.raw(&c.projection, 64);
                break;
            case TraceOp::Viewport: {
                c.viewport.x = r.i32(); c.viewport.y = r.i32();
                c.viewport.width = r.i32(); c.viewport.height = r.i32();
                c.viewport.minZ = r.f32(); c.viewport.maxZ = r.f32();
                const Viewport& v = c.viewport;
                if (v.width <= 0 || v.height <= 0)
                    throw TraceError(where + ": viewport " + std::to_string(v.width) + "x" + std::to_string(v.height) +
                                     " is empty");
                // The programmable device's target is known only at the draw; a Device's
                // framebuffer from the first record.
                if (!trace.programmable)
                    checkInside({v.x, v.y, v.width, v.height}, trace.width, trace.height, where, "viewport");
                if (!(v.minZ >= 0.0f && v.minZ <= 1.0f && v.maxZ >= 0.0f && v.maxZ <= 1.0f))
                    throw TraceError(where + ": viewport depth range outside [0, 1]");
                break;
            }
            case TraceOp::Scissor:
                readRect(r, c.rect);
                if (c.rect.width < 0 || c.rect.height < 0) throw TraceError(where + ": scissor size is negative");
                break;
            case TraceOp::Stage: {
                c.unit = checkedIndex(r.u8(), tex::kMaxStages, "stage");
                tex::StageState& s = c.stage;
                s.colorOp = enumValue(r.u8(), tex::TextureOp::Count, "colour op");
                s.colorArg1 = readStageArg(r, where);
                s.colorArg2 = readStageArg(r, where);
                s.colorArg0 = readStageArg(r, where);
                s.alphaOp = enumValue(r.u8(), tex::TextureOp::Count, "alpha op");
                if (tex::colourOnlyOp(s.alphaOp))
                    throw TraceError(where + ": D3DTOP_" + std::string(tex::textureOpName(s.alphaOp)) +
                                     " has no meaning as an alpha op");
                s.alphaArg1 = readStageArg(r, where);
                s.alphaArg2 = readStageArg(r, where);
                s.alphaArg0 = readStageArg(r, where);
                s.texCoordIndex = uint8_t(checkedIndex(r.u8(), tex::kMaxTexCoordSets, "texture coordinate index"));
                s.colorScaleShift = uint8_t(checkedIndex(r.u8(), 3, "colour scale shift"));
                s.alphaScaleShift = uint8_t(checkedIndex(r.u8(), 3, "alpha scale shift"));
                break;
            }
            case TraceOp::Sampler:
                c.unit = checkedIndex(r.u8(), tex::kMaxStages, "stage");
                readSampler(r, c.sampler);
                break;
            case TraceOp::TextureFactor: c.color = r.rgba(); break;
            case TraceOp::TexGen: {
                c.unit = checkedIndex(r.u8(), tex::kMaxTexCoordSets, "coordinate set");
                c.texGen.mode = enumValue(r.u8(), tex::TexGenMode(9), "texgen mode");
                r.raw(&c.texGen.planes, sizeof c.texGen.planes);
                c.texGen.matrixEnabled = readBool(r, where, "matrixEnabled") != 0;
                r.raw(&c.texGen.matrix, sizeof c.texGen.matrix);
                c.texGen.projected = readBool(r, where, "projected") != 0;
                break;
            }
            case TraceOp::ColorTable: {
                c.unit = checkedIndex(r.u8(), tex::kMaxStages, "stage");
                if (readBool(r, where, "colour table present")) {
                    auto t = std::make_shared<tex::ColorTable>();
                    t->format = enumValue(r.u8(), tex::BaseFormat(6), "colour table format");
                    const uint32_t n = r.u32();
                    if (n > 65536) throw TraceError(where + ": colour table too large");
                    r.need(size_t(n) * 4);
                    t->entries.resize(n);
                    r.raw(t->entries.data(), size_t(n) * 4);
                    c.colorTable = std::move(t);
                }
                break;
            }
            case TraceOp::PixelTexture:
                c.pixelTexture.enabled = readBool(r, where, "pixel texture enabled") != 0;
                c.pixelTexture.mode = enumValue(r.u8(), tex::PixelTexGenMode(2), "pixel texgen mode");
                c.pixelTexture.stage = uint8_t(checkedIndex(r.u8(), tex::kMaxStages, "stage"));
                break;
            case TraceOp::BindTexture:
                c.unit = checkedIndex(r.u8(), tex::kMaxStages, "stage");
                c.textureId = r.u64();
                if (c.textureId != 0 && !trace.textures.count(c.textureId))
                    throw TraceError(where + ": binds a texture the trace has not defined");
                break;
            case TraceOp::BeginFrame: case TraceOp::EndFrame: break;
            case TraceOp::BeginPass: {
                const uint32_t n = r.u32();
                r.need(n);
                c.label.resize(n);
                r.raw(c.label.data(), n);
                break;
            }
            case TraceOp::Clear: {
                const uint8_t flags = r.u8();
                if (flags > 3) throw TraceError(where + ": clear flags out of range");
                c.clearColor = flags & 1;
                c.clearDepth = flags & 2;
                c.color = r.rgba();
                c.depthValue = r.f32();
                if (c.clearDepth && !(c.depthValue >= 0.0f && c.depthValue <= 1.0f))
                    throw TraceError(where + ": depth clear value outside [0, 1]");
                break;
            }
            case TraceOp::Draw: {
                c.primitive = enumValue(r.u8(), Primitive(3), "primitive");
                c.space = enumValue(r.u8(), VertexSpace(2), "vertex space");
                const int sets = r.u8();
                if (sets > tex::kMaxTexCoordSets) throw TraceError(where + ": too many coordinate sets");
                const uint32_t nv = r.u32(), ni = r.u32();
                const uint64_t stride = 36 + 16 * uint64_t(sets);
                r.need(nv * stride + uint64_t(ni) * 4);
                c.vertices.resize(nv);
                for (Vertex& v : c.vertices) {
                    r.raw(&v.position, 16);
                    r.raw(&v.normal, 12);
                    v.diffuse = r.rgba();
                    v.specular = r.rgba();
                    for (int s = 0; s < sets; ++s) r.raw(&v.tex[size_t(s)], 16);
                }
                c.indices.resize(ni);
                r.raw(c.indices.data(), size_t(ni) * 4);
                for (uint32_t i : c.indices)
                    if (i >= nv)
                        throw TraceError(where + ": index " + std::to_string(i) + " past the " + std::to_string(nv) +
                                         " vertices");
                break;
            }
            case TraceOp::DrawPixels: {
                readRect(r, c.rect);
                const uint32_t n = r.u32();
                if (c.rect.width < 0 || c.rect.height < 0 || uint64_t(n) != uint64_t(c.rect.width) * uint64_t(c.rect.height))
                    throw TraceError(where + ": " + std::to_string(n) + " pixels for a " + std::to_string(c.rect.width) +
                                     "x" + std::to_string(c.rect.height) + " rectangle");
                r.need(uint64_t(n) * 4);
                c.pixels.resize(n);
                r.raw(c.pixels.data(), size_t(n) * 4);
                break;
            }
            case TraceOp::CopyPixels:
                readRect(r, c.rect);
                c.dstX = r.i32();
                c.dstY = r.i32();
                checkInside(c.rect, trace.width, trace.height, where, "copyPixels source");
                break;
            case TraceOp::ReadPixels:
                readRect(r, c.rect);
                c.textureId = r.u64();
                checkInside(c.rect, trace.width, trace.height, where, "readPixels rectangle");
                break;
            case TraceOp::End:
                ended = true;
                break;
            default:
                throw TraceError(where + ": unknown record kind " + std::to_string(op));
        }
        r.done();
        if (!ended) trace.commands.push_back(std::move(c));
    }
    if (file.remaining() != 0) throw TraceError("bytes after the End record");
    if (trace.programmable && trace.image.id) {
        const auto size = targetLevelSize(trace.renderTargets.at(trace.image.id).desc, trace.image.level);
        trace.width = size[0];
        trace.height = size[1];
    }
    return trace;
}

Trace readTraceFile(const std::filesystem::path& file) {
    std::ifstream f(file, std::ios::binary);
    if (!f) throw TraceError("cannot open trace '" + file.string() + "'");
    std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    try {
        return readTrace(bytes);
    } catch (const TraceError& e) {
        throw TraceError(file.string() + ": " + e.what());
    }
}

}  // namespace rg::raster
