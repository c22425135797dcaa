// Reading a trace: framing, then each record's payload with its value ranges checked
// (docs/trace-format.md). Nothing is drawn here; the fuzz target fuzz/fuzz_trace_reader.cpp
// runs this on arbitrary bytes.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>

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
    if (trace.version != kTraceVersion)
        throw TraceError("trace version " + std::to_string(trace.version) + " (this reader knows " +
                         std::to_string(kTraceVersion) + ")");
    bool haveDevice = false, ended = false;
    size_t index = 0;
    while (!ended) {
        if (file.remaining() == 0) throw TraceError("trace is truncated (no End record)");
        const uint8_t op = file.u8();
        const uint32_t len = file.u32();
        file.need(len);
        ByteReader r{bytes.subspan(file.pos, len), 0, "trace record"};
        file.pos += len;
        const std::string where = "record " + std::to_string(index++);
        if (!haveDevice && op != uint8_t(TraceOp::Device))
            throw TraceError(where + ": the first record must be Device");
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
                continue;
            }
            case TraceOp::Framebuffer: {
                const size_t n = size_t(trace.width) * size_t(trace.height);
                trace.initialColor.resize(n);
                r.raw(trace.initialColor.data(), n * 4);
                if (trace.depth != DepthFormat::None) {
                    trace.initialDepth.resize(n);
                    r.raw(trace.initialDepth.data(), n * 4);
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
                if (!trace.textures.emplace(t.id, std::move(t)).second)
                    throw TraceError(where + ": texture defined twice");
                continue;
            }
            case TraceOp::State: {
                PipelineState& s = c.state;
                s.cull = enumValue(r.u8(), CullMode(3), "cull mode");
                s.shade = enumValue(r.u8(), ShadeMode(2), "shade mode");
                s.depthTest = r.u8();
                s.depthWrite = r.u8();
                s.depthFunc = enumValue(r.u8(), CompareFunc(8), "depth func");
                s.alphaTest = r.u8();
                s.alphaFunc = enumValue(r.u8(), CompareFunc(8), "alpha func");
                s.alphaRef = r.u8();
                s.blend = r.u8();
                s.srcBlend = enumValue(r.u8(), BlendFactor(13), "source blend factor");
                s.dstBlend = enumValue(r.u8(), BlendFactor(13), "destination blend factor");
                s.blendOp = enumValue(r.u8(), BlendOp(5), "blend op");
                s.colorWriteMask = r.u8();
                s.scissorTest = r.u8();
                s.specularEnable = r.u8();
                s.perspectiveColor = r.u8();
                break;
            }
            case TraceOp::Transforms:
                r.raw(&c.world, 64); r.raw(&c.view, 64); r.raw(&c.projection, 64);
                break;
            case TraceOp::Viewport:
                c.viewport.x = r.i32(); c.viewport.y = r.i32();
                c.viewport.width = r.i32(); c.viewport.height = r.i32();
                c.viewport.minZ = r.f32(); c.viewport.maxZ = r.f32();
                break;
            case TraceOp::Scissor: readRect(r, c.rect); break;
            case TraceOp::Stage: {
                c.unit = checkedIndex(r.u8(), tex::kMaxStages, "stage");
                tex::StageState& s = c.stage;
                s.colorOp = enumValue(r.u8(), tex::TextureOp::Count, "colour op");
                s.colorArg1 = r.u8(); s.colorArg2 = r.u8(); s.colorArg0 = r.u8();
                s.alphaOp = enumValue(r.u8(), tex::TextureOp::Count, "alpha op");
                s.alphaArg1 = r.u8(); s.alphaArg2 = r.u8(); s.alphaArg0 = r.u8();
                s.texCoordIndex = r.u8();
                s.colorScaleShift = r.u8(); s.alphaScaleShift = r.u8();
                break;
            }
            case TraceOp::Sampler: {
                c.unit = checkedIndex(r.u8(), tex::kMaxStages, "stage");
                tex::SamplerState& s = c.sampler;
                for (auto& a : s.address) a = enumValue(r.u8(), tex::AddressMode(5), "address mode");
                s.magFilter = enumValue(r.u8(), tex::FilterMode(2), "mag filter");
                s.minFilter = enumValue(r.u8(), tex::FilterMode(2), "min filter");
                s.mipFilter = enumValue(r.u8(), tex::MipMode(3), "mip filter");
                s.lodBias = r.f32(); s.minLod = r.f32(); s.maxLod = r.f32();
                s.baseLevel = r.i32(); s.maxLevel = r.i32();
                s.borderColor = r.rgba();
                break;
            }
            case TraceOp::TextureFactor: c.color = r.rgba(); break;
            case TraceOp::TexGen: {
                c.unit = checkedIndex(r.u8(), tex::kMaxTexCoordSets, "coordinate set");
                c.texGen.mode = enumValue(r.u8(), tex::TexGenMode(9), "texgen mode");
                r.raw(&c.texGen.planes, sizeof c.texGen.planes);
                c.texGen.matrixEnabled = r.u8() != 0;
                r.raw(&c.texGen.matrix, sizeof c.texGen.matrix);
                c.texGen.projected = r.u8() != 0;
                break;
            }
            case TraceOp::ColorTable: {
                c.unit = checkedIndex(r.u8(), tex::kMaxStages, "stage");
                if (r.u8()) {
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
                c.pixelTexture.enabled = r.u8() != 0;
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
                break;
            }
            case TraceOp::DrawPixels: {
                readRect(r, c.rect);
                const uint32_t n = r.u32();
                r.need(uint64_t(n) * 4);
                c.pixels.resize(n);
                r.raw(c.pixels.data(), size_t(n) * 4);
                break;
            }
            case TraceOp::CopyPixels:
                readRect(r, c.rect);
                c.dstX = r.i32();
                c.dstY = r.i32();
                break;
            case TraceOp::ReadPixels:
                readRect(r, c.rect);
                c.textureId = r.u64();
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
