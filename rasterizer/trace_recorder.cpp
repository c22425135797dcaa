// Capture: the Device feeds the recorder at every command; the recorder writes the state
// the command reads when it differs from what it last wrote, then the command
// (docs/trace-format.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <fstream>

#include "core/error.h"
#include "rasterizer/device.h"
#include "rasterizer/trace.h"
#include "trace_io.h"
#include "trace_recorder_impl.h"

namespace rg::raster {

using detail::ByteWriter;

namespace detail {

int traceFaces(const tex::TextureDesc& desc) {
    return desc.target == tex::TextureTarget::CubeMap ? 6 : 1;
}

int traceDims(const tex::TextureDesc& desc) {
    switch (desc.target) {
        case tex::TextureTarget::Texture1D: return 1;
        case tex::TextureTarget::Texture2D: return 2;
        case tex::TextureTarget::Texture3D: return 3;
        case tex::TextureTarget::CubeMap: return 2;
        case tex::TextureTarget::Texture4D: return 4;
    }
    return 2;
}

uint64_t traceLevelBytes(const tex::TextureDesc& desc, int level) {
    const int dims = traceDims(desc);
    const std::array<int, 4> base{desc.width, desc.height, desc.depth, desc.size4};
    uint64_t n = uint64_t(tex::formatInfo(desc.format).bytesPerTexel);
    for (int d = 0; d < dims; ++d) n *= uint64_t(std::max(1, base[size_t(d)] >> level));
    return n;
}

}  // namespace detail

namespace {

uint16_t floatToHalfBits(float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    const uint32_t sign = (bits >> 16) & 0x8000u;
    const int32_t exp = int32_t((bits >> 23) & 0xff);
    const uint32_t man = bits & 0x7fffffu;
    if (exp == 255) return uint16_t(sign | 0x7c00u | (man >> 13) | (man ? 0x200u : 0u));
    const int32_t e = exp - 127 + 15;
    if (exp == 0) return uint16_t(sign);  // float subnormals are below every half
    if (e >= 31) return uint16_t(sign | 0x7c00u);
    if (e <= 0) {
        if (e < -10) return uint16_t(sign);
        return uint16_t(sign | ((man | 0x800000u) >> (14 - e)));
    }
    return uint16_t(sign | uint32_t(e) << 10 | (man >> 13));
}

void put16(uint8_t* p, uint32_t v) { p[0] = uint8_t(v); p[1] = uint8_t(v >> 8); }
void put32(uint8_t* p, uint32_t v) { for (int i = 0; i < 4; ++i) p[i] = uint8_t(v >> (8 * i)); }
void putF(uint8_t* p, float f) { std::memcpy(p, &f, 4); }

// The packed bytes whose expansion is the stored texel: the inverse of expandTexel8 (bit
// replication keeps the top bits, so 565/4444 invert exactly) and of expandTexelFloat.
void packTexel8(tex::TexelFormat f, Rgba8 c, uint8_t* p) {
    using tex::TexelFormat;
    switch (f) {
        case TexelFormat::L8: case TexelFormat::I8: p[0] = c.r; break;
        case TexelFormat::A8: p[0] = c.a; break;
        case TexelFormat::L8A8: p[0] = c.r; p[1] = c.a; break;
        case TexelFormat::RGB565:
            put16(p, uint32_t(c.r >> 3) << 11 | uint32_t(c.g >> 2) << 5 | uint32_t(c.b >> 3));
            break;
        case TexelFormat::RGBA4444:
            put16(p, uint32_t(c.r >> 4) << 12 | uint32_t(c.g >> 4) << 8 | uint32_t(c.b >> 4) << 4 |
                         uint32_t(c.a >> 4));
            break;
        case TexelFormat::RGB8: p[0] = c.r; p[1] = c.g; p[2] = c.b; break;
        case TexelFormat::RGBA8: p[0] = c.r; p[1] = c.g; p[2] = c.b; p[3] = c.a; break;
        default: break;
    }
}

void packTexelFloat(tex::TexelFormat f, const glm::vec4& v, uint8_t* p) {
    using tex::TexelFormat;
    switch (f) {
        case TexelFormat::R16F: put16(p, floatToHalfBits(v.r)); break;
        case TexelFormat::RGBA16F:
            for (int i = 0; i < 4; ++i) put16(p + 2 * i, floatToHalfBits(v[i]));
            break;
        case TexelFormat::R32F: putF(p, v.r); break;
        case TexelFormat::RGBA32F: for (int i = 0; i < 4; ++i) putF(p + 4 * i, v[i]); break;
        case TexelFormat::Depth16: put16(p, uint32_t(std::lround(double(v.r) * 65535.0))); break;
        case TexelFormat::Depth24: put32(p, uint32_t(std::lround(double(v.r) * 16777215.0))); break;
        case TexelFormat::Depth32F: putF(p, v.r); break;
        default: break;
    }
}

}  // namespace

// Packs one level of one face; checks that it expands back to the stored texels, so a
// replay uploads exactly what the capture sampled.
std::vector<uint8_t> detail::tracePackLevel(const tex::Texture& t, int level, int face) {
    const tex::TextureDesc& d = t.desc();
    const int bpt = t.format().bytesPerTexel;
    const auto& s = t.levelSize(level);
    std::vector<uint8_t> out(detail::traceLevelBytes(d, level));
    size_t i = 0;
    for (int w = 0; w < s[3]; ++w)
        for (int z = 0; z < s[2]; ++z)
            for (int y = 0; y < s[1]; ++y)
                for (int x = 0; x < s[0]; ++x, ++i) {
                    uint8_t* p = out.data() + i * size_t(bpt);
                    if (t.isFloat()) {
                        const glm::vec4 v = t.texelFloat(level, face, x, y, z, w);
                        packTexelFloat(d.format, v, p);
                        const glm::vec4 back = tex::expandTexelFloat(d.format, p);
                        if (std::memcmp(&back, &v, sizeof v) != 0)
                            throw Error("trace capture: a " +
                                        std::string(t.format().name) +
                                        " texel does not round-trip through its packed form");
                    } else if (t.is16()) {
                        // I16 keeps its 16-bit value beside the 8-bit expansion.
                        const uint16_t v = t.texel16(level, face, x, y, z, w);
                        p[0] = uint8_t(v & 0xff);
                        p[1] = uint8_t(v >> 8);
                    } else {
                        const Rgba8 c = t.texel8(level, face, x, y, z, w);
                        packTexel8(d.format, c, p);
                        if (!(tex::expandTexel8(d.format, p) == c))
                            throw Error("trace capture: a " + std::string(t.format().name) +
                                        " texel does not round-trip through its packed form");
                    }
                }
    return out;
}

uint64_t detail::traceContentHash(const tex::Texture& t) {
    const tex::TextureDesc& d = t.desc();
    uint64_t h = traceHash64(&d.target, 1);
    h = traceHash64(&d.format, 1, h);
    const int32_t ext[5] = {d.width, d.height, d.depth, d.size4, d.levels};
    h = traceHash64(ext, sizeof ext, h);
    for (int l = 0; l < t.levels(); ++l) {
        const auto& s = t.levelSize(l);
        const size_t count = size_t(s[0]) * s[1] * s[2] * s[3];
        for (int f = 0; f < t.faces(); ++f) {
            if (t.is16()) {
                for (int w = 0; w < s[3]; ++w)
                    for (int z = 0; z < s[2]; ++z)
                        for (int y = 0; y < s[1]; ++y)
                            for (int x = 0; x < s[0]; ++x) {
                                const uint16_t v = t.texel16(l, f, x, y, z, w);
                                h = traceHash64(&v, sizeof v, h);
                            }
            } else if (!t.isFloat()) {
                h = traceHash64(t.data8(l, f), count * sizeof(Rgba8), h);
            } else {
                for (int w = 0; w < s[3]; ++w)
                    for (int z = 0; z < s[2]; ++z)
                        for (int y = 0; y < s[1]; ++y)
                            for (int x = 0; x < s[0]; ++x) {
                                const glm::vec4 v = t.texelFloat(l, f, x, y, z, w);
                                h = traceHash64(&v, sizeof v, h);
                            }
            }
        }
    }
    return h == 0 ? 1 : h;  // 0 means "no texture" in BindTexture
}

namespace {

bool sameBytes(const void* a, const void* b, size_t n) { return std::memcmp(a, b, n) == 0; }

bool sameTexGen(const tex::TexGenState& a, const tex::TexGenState& b) {
    return a.mode == b.mode && sameBytes(&a.planes, &b.planes, sizeof a.planes) &&
           a.matrixEnabled == b.matrixEnabled && sameBytes(&a.matrix, &b.matrix, sizeof a.matrix) &&
           a.projected == b.projected;
}

bool sameTable(const tex::ColorTable* a, const tex::ColorTable* b) {
    if (!a || !b) return a == b;
    return a->format == b->format && a->entries == b->entries;
}

}  // namespace

void TraceRecorder::Impl::writeTexture(const tex::Texture& t, uint64_t id) {
    auto it = std::lower_bound(written.begin(), written.end(), id);
    if (it != written.end() && *it == id) return;
    written.insert(it, id);
    size_t at = begin(TraceOp::Texture);
    ByteWriter w{bytes};
    const tex::TextureDesc& d = t.desc();
    w.u64(id);
    w.u8(uint8_t(d.target));
    w.u8(uint8_t(d.format));
    w.i32(d.width); w.i32(d.height); w.i32(d.depth); w.i32(d.size4); w.i32(d.levels);
    for (int l = 0; l < d.levels; ++l)
        for (int f = 0; f < t.faces(); ++f) {
            std::vector<uint8_t> packed = detail::tracePackLevel(t, l, f);
            w.raw(packed.data(), packed.size());
        }
    end(at);
}

void TraceRecorder::Impl::sync(const Device& dev, uint32_t readStages) {
    ByteWriter w{bytes};
    const bool all = !known;
    known = true;
    if (all || !(dev.state() == state)) {
        state = dev.state();
        size_t at = begin(TraceOp::State);
        const PipelineState& s = state;
        for (uint8_t v : {uint8_t(s.cull), uint8_t(s.shade), s.depthTest, s.depthWrite,
                          uint8_t(s.depthFunc), s.alphaTest, uint8_t(s.alphaFunc), s.alphaRef,
                          s.blend, uint8_t(s.srcBlend), uint8_t(s.dstBlend), uint8_t(s.blendOp),
                          s.colorWriteMask, s.scissorTest, s.specularEnable, s.perspectiveColor})
            w.u8(v);
        end(at);
    }
    const std::array<glm::mat4, 3> t{dev.world(), dev.view(), dev.projection()};
    if (all || !sameBytes(&t, &transforms, sizeof t)) {
        transforms = t;
        size_t at = begin(TraceOp::Transforms);
        w.raw(&t, sizeof t);  // 3 × 16 floats, column-major
        end(at);
    }
    const Viewport& v = dev.viewport();
    if (all || !sameBytes(&v, &viewport, sizeof v)) {
        viewport = v;
        size_t at = begin(TraceOp::Viewport);
        w.i32(v.x); w.i32(v.y); w.i32(v.width); w.i32(v.height); w.f32(v.minZ); w.f32(v.maxZ);
        end(at);
    }
    const Rect& r = dev.scissor();
    if (all || !(r == scissor)) {
        scissor = r;
        size_t at = begin(TraceOp::Scissor);
        w.i32(r.x); w.i32(r.y); w.i32(r.width); w.i32(r.height);
        end(at);
    }
    const tex::TextureUnits& tu = dev.textureUnits();
    for (int i = 0; i < tex::kMaxStages; ++i) {
        const tex::StageState& st = tu.stage(i);
        if (all || !(st == stages[size_t(i)])) {
            stages[size_t(i)] = st;
            size_t at = begin(TraceOp::Stage);
            w.u8(uint8_t(i));
            for (uint8_t b : {uint8_t(st.colorOp), st.colorArg1, st.colorArg2, st.colorArg0,
                              uint8_t(st.alphaOp), st.alphaArg1, st.alphaArg2, st.alphaArg0,
                              st.texCoordIndex, st.colorScaleShift, st.alphaScaleShift})
                w.u8(b);
            end(at);
        }
        const tex::SamplerState& sa = tu.sampler(i);
        if (all || !sameBytes(&sa, &samplers[size_t(i)], sizeof sa)) {
            samplers[size_t(i)] = sa;
            size_t at = begin(TraceOp::Sampler);
            w.u8(uint8_t(i));
            for (auto a : sa.address) w.u8(uint8_t(a));
            w.u8(uint8_t(sa.magFilter)); w.u8(uint8_t(sa.minFilter)); w.u8(uint8_t(sa.mipFilter));
            w.f32(sa.lodBias); w.f32(sa.minLod); w.f32(sa.maxLod);
            w.i32(sa.baseLevel); w.i32(sa.maxLevel);
            w.rgba(sa.borderColor);
            end(at);
        }
        const tex::ColorTable* table = tu.colorTable(i).get();
        if (all || !sameTable(table, tables[size_t(i)].get())) {
            tables[size_t(i)] = table ? std::make_shared<tex::ColorTable>(*table) : nullptr;
            size_t at = begin(TraceOp::ColorTable);
            w.u8(uint8_t(i));
            w.u8(table ? 1 : 0);
            if (table) {
                w.u8(uint8_t(table->format));
                w.u32(uint32_t(table->entries.size()));
                for (Rgba8 e : table->entries) w.rgba(e);
            }
            end(at);
        }
        if (readStages >> i & 1u) {
            const tex::Texture* tx = tu.texture(i).get();
            const uint64_t id = tx ? detail::traceContentHash(*tx) : 0;
            if (tx) writeTexture(*tx, id);
            if (all || id != bound[size_t(i)]) {
                bound[size_t(i)] = id;
                size_t at = begin(TraceOp::BindTexture);
                w.u8(uint8_t(i));
                w.u64(id);
                end(at);
            }
        }
    }
    if (all || !(tu.textureFactor() == tfactor)) {
        tfactor = tu.textureFactor();
        size_t at = begin(TraceOp::TextureFactor);
        w.rgba(tfactor);
        end(at);
    }
    for (int i = 0; i < tex::kMaxTexCoordSets; ++i) {
        const tex::TexGenState& g = tu.texGen(i);
        if (all || !sameTexGen(g, texGens[size_t(i)])) {
            texGens[size_t(i)] = g;
            size_t at = begin(TraceOp::TexGen);
            w.u8(uint8_t(i));
            w.u8(uint8_t(g.mode));
            w.raw(&g.planes, sizeof g.planes);
            w.u8(g.matrixEnabled ? 1 : 0);
            w.raw(&g.matrix, sizeof g.matrix);
            w.u8(g.projected ? 1 : 0);
            end(at);
        }
    }
    const tex::PixelTextureState& pt = tu.pixelTexture();
    if (all || !(pt == pixelTexture)) {
        pixelTexture = pt;
        size_t at = begin(TraceOp::PixelTexture);
        w.u8(pt.enabled ? 1 : 0); w.u8(uint8_t(pt.mode)); w.u8(pt.stage);
        end(at);
    }
}


TraceRecorder::TraceRecorder() : impl_(std::make_unique<Impl>()) {}
TraceRecorder::~TraceRecorder() = default;

const std::vector<uint8_t>& TraceRecorder::bytes() const { return impl_->bytes; }
bool TraceRecorder::finished() const { return impl_->finished; }

void TraceRecorder::finish() {
    if (impl_->finished) return;
    if (impl_->programmable && !impl_->program.detached) impl_->writeTargetHashes();
    size_t at = impl_->begin(TraceOp::End);
    impl_->end(at);
    impl_->finished = true;
}

void TraceRecorder::save(const std::filesystem::path& file) {
    finish();
    std::ofstream f(file, std::ios::binary);
    f.write(reinterpret_cast<const char*>(impl_->bytes.data()), std::streamsize(impl_->bytes.size()));
    if (!f) throw Error("cannot write trace '" + file.string() + "'");
}

void TraceRecorder::attach(const Device& dev) {
    Impl& m = *impl_;
    if (m.attached) throw Error("trace recorder: already attached to a device");
    m.attached = true;
    ByteWriter w{m.bytes};
    w.raw(kTraceMagic, 8);
    w.u32(kTraceVersionFixedFunction);
    size_t at = m.begin(TraceOp::Device);
    const std::string_view name = dev.profile().name;
    w.u8(uint8_t(name.size()));
    w.raw(name.data(), name.size());
    const Framebuffer& fb = dev.framebuffer();
    w.i32(fb.width()); w.i32(fb.height()); w.u8(uint8_t(fb.depthFormat()));
    m.end(at);
    // The contents at attach time, unless all zero (a fresh device).
    const bool colorZero = std::all_of(fb.color().begin(), fb.color().end(),
                                       [](Rgba8 c) { return c == Rgba8{}; });
    const bool depthZero = std::all_of(fb.depth().begin(), fb.depth().end(),
                                       [](uint32_t z) { return z == 0; });
    if (!colorZero || !depthZero) {
        at = m.begin(TraceOp::Framebuffer);
        w.raw(fb.color().data(), fb.color().size_bytes());
        for (uint32_t z : fb.depth()) w.u32(z);
        m.end(at);
    }
}

void TraceRecorder::beginFrame() { impl_->end(impl_->begin(TraceOp::BeginFrame)); }
void TraceRecorder::endFrame() { impl_->end(impl_->begin(TraceOp::EndFrame)); }
void TraceRecorder::beginPass(const std::string& label) {
    size_t at = impl_->begin(TraceOp::BeginPass);
    ByteWriter w{impl_->bytes};
    w.u32(uint32_t(label.size()));
    w.raw(label.data(), label.size());
    impl_->end(at);
}

void TraceRecorder::clear(const Device& dev, bool color, Rgba8 colorValue, bool depth,
                          float depthValue) {
    impl_->sync(dev, 0);
    size_t at = impl_->begin(TraceOp::Clear);
    ByteWriter w{impl_->bytes};
    w.u8(uint8_t((color ? 1 : 0) | (depth ? 2 : 0)));
    w.rgba(colorValue);
    w.f32(depthValue);
    impl_->end(at);
}

void TraceRecorder::draw(const Device& dev, Primitive primitive, VertexSpace space,
                         std::span<const Vertex> vertices, std::span<const uint32_t> indices) {
    impl_->sync(dev, Impl::drawStages(dev.textureUnits()));
    // Coordinate sets past the last one holding a non-zero value are not stored.
    int sets = 0;
    for (const Vertex& v : vertices)
        for (int s = tex::kMaxTexCoordSets; s > sets; --s)
            if (v.tex[size_t(s - 1)] != glm::vec4(0.0f) ||
                std::signbit(v.tex[size_t(s - 1)].x) || std::signbit(v.tex[size_t(s - 1)].y) ||
                std::signbit(v.tex[size_t(s - 1)].z) || std::signbit(v.tex[size_t(s - 1)].w)) {
                sets = s;
                break;
            }
    size_t at = impl_->begin(TraceOp::Draw);
    ByteWriter w{impl_->bytes};
    w.u8(uint8_t(primitive));
    w.u8(uint8_t(space));
    w.u8(uint8_t(sets));
    w.u32(uint32_t(vertices.size()));
    w.u32(uint32_t(indices.size()));
    for (const Vertex& v : vertices) {
        w.raw(&v.position, 16);
        w.raw(&v.normal, 12);
        w.rgba(v.diffuse);
        w.rgba(v.specular);
        for (int s = 0; s < sets; ++s) w.raw(&v.tex[size_t(s)], 16);
    }
    for (uint32_t i : indices) w.u32(i);
    impl_->end(at);
}

void TraceRecorder::drawPixels(const Device& dev, int x, int y, int width, int height,
                               std::span<const Rgba8> pixels) {
    impl_->sync(dev, Impl::transferStages(dev.textureUnits()));
    size_t at = impl_->begin(TraceOp::DrawPixels);
    ByteWriter w{impl_->bytes};
    w.i32(x); w.i32(y); w.i32(width); w.i32(height);
    w.u32(uint32_t(pixels.size()));
    w.raw(pixels.data(), pixels.size_bytes());
    impl_->end(at);
}

void TraceRecorder::copyPixels(const Device& dev, int srcX, int srcY, int width, int height,
                               int dstX, int dstY) {
    impl_->sync(dev, Impl::transferStages(dev.textureUnits()));
    size_t at = impl_->begin(TraceOp::CopyPixels);
    ByteWriter w{impl_->bytes};
    for (int v : {srcX, srcY, width, height, dstX, dstY}) w.i32(v);
    impl_->end(at);
}

void TraceRecorder::readPixels(int x, int y, int width, int height, std::span<const Rgba8> result) {
    size_t at = impl_->begin(TraceOp::ReadPixels);
    ByteWriter w{impl_->bytes};
    w.i32(x); w.i32(y); w.i32(width); w.i32(height);
    w.u64(traceHash64(result.data(), result.size_bytes()));
    impl_->end(at);
}

uint64_t traceHash64(const void* data, size_t size, uint64_t h) {
    const auto* p = static_cast<const uint8_t*>(data);
    for (size_t i = 0; i < size; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

}  // namespace rg::raster
