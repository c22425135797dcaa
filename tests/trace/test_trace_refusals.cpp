// What docs/trace-format.md leaves undefined, or the device refuses, the reader refuses
// (issue 23, item 1): one small version-1 trace written byte by byte from the document's
// tables, then each refusal as that trace with one field made bad. Every bad trace is also a
// fuzz seed (fuzz/corpus/trace_reader/refused-*.trace), so the fuzzer starts at each refusal;
// RETROGLASS_WRITE_TRACE_SEEDS=1 rewrites them after a change of this file.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "rasterizer/device.h"
#include "rasterizer/trace.h"

namespace rg::raster {
namespace {

// ---- a trace from the document's tables ----------------------------------------------
struct Bytes {
    std::vector<uint8_t> b;
    Bytes& u8(uint8_t v) { b.push_back(v); return *this; }
    Bytes& raw(const void* p, size_t n) {
        const auto* c = static_cast<const uint8_t*>(p);
        b.insert(b.end(), c, c + n);
        return *this;
    }
    Bytes& u32(uint32_t v) { return raw(&v, 4); }
    Bytes& i32(int32_t v) { return raw(&v, 4); }
    Bytes& u64(uint64_t v) { return raw(&v, 8); }
    Bytes& f32(float v) { return raw(&v, 4); }
    Bytes& rgba(uint8_t r, uint8_t g, uint8_t bl, uint8_t a) { return u8(r).u8(g).u8(bl).u8(a); }
};

// The fields of the base trace that the cases change, with their good values.
struct Fields {
    uint32_t version = 1;
    std::string profile = "geforce256";
    uint8_t depthFormat = 1;  // D16
    bool framebuffer = true;
    bool framebufferLate = false;  // after the State record instead of second
    uint32_t initialDepth = 0xffff;
    std::array<uint8_t, 16> state{0, 1, 1, 1, 3, 0, 7, 0, 0, 1, 0, 0, 15, 0, 0, 1};
    int32_t viewport[4] = {0, 0, 8, 8};
    float minZ = 0, maxZ = 1;
    int32_t scissorWidth = 8;
    std::array<uint8_t, 11> stage{3, 2, 0, 1, 3, 2, 0, 1, 0, 0, 0};  // MODULATE(TEXTURE, DIFFUSE) both
    uint8_t texGenMatrixEnabled = 0, texGenProjected = 0;
    uint8_t colorTablePresent = 0;
    uint8_t pixelTextureEnabled = 0;
    uint8_t textureTarget = 1;  // 2D
    int32_t textureExtent[4] = {2, 2, 1, 1};
    int32_t textureLevels = 2;
    uint8_t clearFlags = 3;
    float clearDepth = 1.0f;
    uint32_t index2 = 2;  // the draw's third index
    uint32_t drawPixelsCount = 4;
    int32_t copySource[2] = {6, 6};
    int32_t readRect[4] = {0, 0, 8, 8};
    bool secondDevice = false;
};

std::vector<uint8_t> traceBytes(const Fields& f) {
    Bytes out;
    out.raw("RGTRACE\0", 8).u32(f.version);
    auto record = [&](uint8_t kind, const Bytes& p) { out.u8(kind).u32(uint32_t(p.b.size())).raw(p.b.data(), p.b.size()); };
    Bytes device;
    device.u8(uint8_t(f.profile.size())).raw(f.profile.data(), f.profile.size()).i32(8).i32(8).u8(f.depthFormat);
    record(0x01, device);
    Bytes fb;
    for (int i = 0; i < 64; ++i) fb.rgba(uint8_t(4 * i), 10, 20, 255);
    for (int i = 0; i < 64; ++i) fb.u32(f.initialDepth);
    if (f.framebuffer && !f.framebufferLate) record(0x02, fb);
    if (f.secondDevice) record(0x01, device);
    Bytes state;
    state.raw(f.state.data(), 16);
    record(0x10, state);
    if (f.framebufferLate) record(0x02, fb);
    Bytes transforms;
    const glm::mat4 id(1.0f);
    for (int m = 0; m < 3; ++m) transforms.raw(&id, 64);
    record(0x11, transforms);
    Bytes viewport;
    for (int32_t v : f.viewport) viewport.i32(v);
    viewport.f32(f.minZ).f32(f.maxZ);
    record(0x12, viewport);
    Bytes scissor;
    scissor.i32(0).i32(0).i32(f.scissorWidth).i32(8);
    record(0x13, scissor);
    Bytes stage;
    stage.u8(0).raw(f.stage.data(), 11);
    record(0x20, stage);
    Bytes sampler;
    sampler.u8(0).u8(0).u8(0).u8(0).u8(0).u8(1).u8(1).u8(2).f32(0).f32(-1000).f32(1000).i32(0).i32(1000).rgba(0, 0, 0, 0);
    record(0x21, sampler);
    Bytes factor;
    factor.rgba(255, 255, 255, 255);
    record(0x22, factor);
    Bytes texGen;
    const glm::vec4 planes[4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
    texGen.u8(0).u8(0).raw(planes, 64).u8(f.texGenMatrixEnabled).raw(&id, 64).u8(f.texGenProjected);
    record(0x23, texGen);
    Bytes table;
    table.u8(0).u8(f.colorTablePresent);
    if (f.colorTablePresent) table.u8(4).u32(2).rgba(0, 0, 0, 255).rgba(255, 255, 255, 255);
    record(0x24, table);
    Bytes pixelTexture;
    pixelTexture.u8(f.pixelTextureEnabled).u8(0).u8(0);
    record(0x25, pixelTexture);
    Bytes texture;
    texture.u64(77).u8(f.textureTarget).u8(7);  // RGBA8
    for (int32_t e : f.textureExtent) texture.i32(e);
    texture.i32(f.textureLevels);
    const int faces = f.textureTarget == 3 ? 6 : 1;
    for (int l = 0; l < f.textureLevels; ++l)
        for (int face = 0; face < faces; ++face) {
            int64_t n = 1;
            const int dims[] = {1, 2, 3, 2, 4};
            for (int d = 0; d < dims[f.textureTarget]; ++d) n *= std::max(1, f.textureExtent[d] >> l);
            for (int64_t i = 0; i < n; ++i) texture.rgba(uint8_t(50 * i), 100, 150, 255);
        }
    record(0x26, texture);
    Bytes bind;
    bind.u8(0).u64(77);
    record(0x27, bind);
    Bytes clear;
    clear.u8(f.clearFlags).rgba(9, 9, 9, 255).f32(f.clearDepth);
    record(0x40, clear);
    Bytes draw;
    draw.u8(0).u8(1).u8(1).u32(3).u32(3);  // a list, pre-transformed, one set, 3 vertices, 3 indices
    const float pos[3][2] = {{0.5f, 0.5f}, {7.5f, 1.5f}, {2.5f, 7.5f}};
    for (int v = 0; v < 3; ++v) {
        const glm::vec4 p(pos[v][0], pos[v][1], 0.5f, 1.0f), t(0.25f * float(v), 0.5f, 0, 1);
        const glm::vec3 n(0, 0, 1);
        draw.raw(&p, 16).raw(&n, 12).rgba(200, 100, uint8_t(50 * v), 255).rgba(0, 0, 0, 0).raw(&t, 16);
    }
    draw.u32(0).u32(1).u32(f.index2);
    record(0x41, draw);
    Bytes drawPixels;
    drawPixels.i32(1).i32(5).i32(2).i32(2).u32(f.drawPixelsCount);
    for (uint32_t i = 0; i < f.drawPixelsCount; ++i) drawPixels.rgba(255, uint8_t(60 * i), 0, 255);
    record(0x42, drawPixels);
    Bytes copy;
    copy.i32(f.copySource[0]).i32(f.copySource[1]).i32(2).i32(2).i32(0).i32(0);
    record(0x43, copy);
    Bytes read;
    for (int32_t v : f.readRect) read.i32(v);
    read.u64(0);
    record(0x44, read);
    record(0xff, Bytes{});
    return out.b;
}

struct Refusal {
    const char* name;                   // the seed's file name: refused-<name>.trace
    std::function<void(Fields&)> bad;  // the one field made bad
    const char* says;                   // what the error names
};

const std::vector<Refusal>& refusals() {
    static const std::vector<Refusal> list = {
        {"boolean-depthtest-2", [](Fields& f) { f.state[2] = 2; }, "depthTest 2 is not a boolean"},
        {"boolean-perspectivecolor-255", [](Fields& f) { f.state[15] = 255; }, "perspectiveColor 255 is not a boolean"},
        {"write-mask-beyond-rgba", [](Fields& f) { f.state[12] = 16; }, "colour write mask 16"},
        {"boolean-texgen-projected-2", [](Fields& f) { f.texGenProjected = 2; }, "projected 2 is not a boolean"},
        {"boolean-texgen-matrix-3", [](Fields& f) { f.texGenMatrixEnabled = 3; }, "matrixEnabled 3 is not a boolean"},
        {"boolean-colour-table-present-2", [](Fields& f) { f.colorTablePresent = 2; }, "colour table present 2"},
        {"boolean-pixel-texture-2", [](Fields& f) { f.pixelTextureEnabled = 2; }, "pixel texture enabled 2"},
        {"second-device", [](Fields& f) { f.secondDevice = true; }, "a second Device record"},
        {"framebuffer-not-second", [](Fields& f) { f.framebufferLate = true; }, "may only be the second record"},
        {"framebuffer-depth-past-d16", [](Fields& f) { f.initialDepth = 0x10000; }, "depth value 65536 above"},
        {"unknown-profile", [](Fields& f) { f.profile = "voodoo2"; }, "unknown profile 'voodoo2'"},
        {"viewport-outside", [](Fields& f) { f.viewport[0] = 1; }, "viewport (1, 0) 8x8 is not inside"},
        {"viewport-empty", [](Fields& f) { f.viewport[3] = 0; }, "viewport 8x0 is empty"},
        {"viewport-depth-range", [](Fields& f) { f.maxZ = 1.5f; }, "depth range outside [0, 1]"},
        {"scissor-negative", [](Fields& f) { f.scissorWidth = -1; }, "scissor size is negative"},
        {"stage-argument", [](Fields& f) { f.stage[1] = 0x45; }, "stage argument 69 is not a D3DTA_ value"},
        {"stage-colour-only-alpha-op", [](Fields& f) { f.stage[4] = 17; },
         "D3DTOP_MODULATEALPHA_ADDCOLOR has no meaning as an alpha op"},
        {"stage-texcoord-index", [](Fields& f) { f.stage[8] = 8; }, "texture coordinate index 8 is out of range"},
        {"stage-scale-shift", [](Fields& f) { f.stage[9] = 3; }, "colour scale shift 3 is out of range"},
        {"texture-unused-dimension", [](Fields& f) { f.textureExtent[2] = 2; }, "which its target does not use"},
        {"texture-past-full-chain", [](Fields& f) { f.textureLevels = 3; }, "more than the full chain's 2"},
        {"texture-cube-not-square", [](Fields& f) {
             f.textureTarget = 3;
             f.textureExtent[1] = 1;
             f.textureLevels = 1;
         }, "cube map faces are square"},
        {"clear-depth-outside", [](Fields& f) { f.clearDepth = -0.5f; }, "depth clear value outside [0, 1]"},
        {"draw-index-past-vertices", [](Fields& f) { f.index2 = 3; }, "index 3 past the 3 vertices"},
        {"drawpixels-count", [](Fields& f) { f.drawPixelsCount = 3; }, "3 pixels for a 2x2 rectangle"},
        {"copypixels-source-outside", [](Fields& f) { f.copySource[0] = 7; }, "copyPixels source (7, 6) 2x2 is not inside"},
        {"readpixels-outside", [](Fields& f) { f.readRect[3] = 9; }, "readPixels rectangle (0, 0) 8x9 is not inside"},
    };
    return list;
}

std::filesystem::path seedPath(const Refusal& r) {
    return std::filesystem::path(RETROGLASS_SOURCE_DIR) / "fuzz/corpus/trace_reader" /
           (std::string("refused-") + r.name + ".trace");
}

// The base trace is good: it reads and plays, so every refusal below is its one field.
TEST(TraceReaderRefusals, TheBaseTraceReadsAndPlays) {
    const Trace t = readTrace(traceBytes(Fields{}));
    EXPECT_EQ(t.initialDepth.size(), 64u);
    const ReplayResult r = replayTrace(t, {Path::Reference, 1, -1});
    EXPECT_EQ(r.readBacks, 1);
    EXPECT_NO_THROW(readTrace(traceBytes([] {
        Fields f;
        f.colorTablePresent = 1;
        f.stage[9] = 2;  // the largest scale
        f.textureTarget = 3;  // a square cube map
        return f;
    }())));
}

TEST(TraceReaderRefusals, EachUndefinedFieldIsRefusedAndNamed) {
    for (const Refusal& r : refusals()) {
        Fields f;
        r.bad(f);
        try {
            (void)readTrace(traceBytes(f));
            ADD_FAILURE() << r.name << ": read without an error";
        } catch (const TraceError& e) {
            EXPECT_NE(std::string(e.what()).find(r.says), std::string::npos)
                << r.name << ": \"" << e.what() << "\" does not say \"" << r.says << "\"";
        }
    }
}

// The fuzz seeds are these refusals, so that mutations start from each path.
TEST(TraceReaderRefusals, FuzzSeedsAreTheRefusals) {
    const bool write = std::getenv("RETROGLASS_WRITE_TRACE_SEEDS") != nullptr;
    for (const Refusal& r : refusals()) {
        Fields f;
        r.bad(f);
        const std::vector<uint8_t> bytes = traceBytes(f);
        if (write) {
            std::ofstream(seedPath(r), std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                                               std::streamsize(bytes.size()));
            continue;
        }
        std::ifstream in(seedPath(r), std::ios::binary);
        ASSERT_TRUE(in) << seedPath(r) << " is missing: run with RETROGLASS_WRITE_TRACE_SEEDS=1";
        const std::vector<uint8_t> seed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        EXPECT_EQ(seed, bytes) << seedPath(r) << " is not the current refusal: run with RETROGLASS_WRITE_TRACE_SEEDS=1";
    }
}

// A version-2 ProgramState: booleans and BOTH* as a destination factor.
TEST(TraceReaderRefusals, ProgramStateBooleansAndBothFactorsAsDestination) {
    auto programTrace = [](uint8_t depthTest, uint8_t enable, uint8_t dst) {
        Bytes out;
        out.raw("RGTRACE\0", 8).u32(2);
        auto record = [&](uint8_t kind, const Bytes& p) {
            out.u8(kind).u32(uint32_t(p.b.size())).raw(p.b.data(), p.b.size());
        };
        Bytes device;
        device.u8(11).raw("geforce8800", 11);
        record(0x03, device);
        Bytes state;
        state.u8(0).u8(depthTest).u8(1).u8(1).f32(1.0f);
        for (int k = 0; k < 4; ++k) state.u8(k == 0 ? enable : 0).u8(4).u8(k == 0 ? dst : 5).u8(0).u8(15);
        record(0x14, state);
        record(0xff, Bytes{});
        return out.b;
    };
    EXPECT_NO_THROW(readTrace(programTrace(1, 1, 5)));
    EXPECT_THROW(readTrace(programTrace(2, 1, 5)), TraceError);
    EXPECT_THROW(readTrace(programTrace(1, 7, 5)), TraceError);
    EXPECT_THROW(readTrace(programTrace(1, 1, 11)), TraceError);  // BOTHSRCALPHA
    EXPECT_THROW(readTrace(programTrace(1, 1, 12)), TraceError);  // BOTHINVSRCALPHA
}

// The device takes no other boolean either, so no trace it records has one.
TEST(TraceReaderRefusals, TheDeviceRefusesBooleansOtherThan0And1) {
    Device dev(profile(ProfileId::GeForce256), 8, 8, DepthFormat::None, {Path::Reference, 1});
    PipelineState s;
    s.blend = 2;
    EXPECT_THROW(dev.setState(s), InvalidState);
    s.blend = 1;
    EXPECT_NO_THROW(dev.setState(s));
}

// Without a Framebuffer record the capture started all zero, depth included: the recorder
// leaves the record out only then, and the replay must not start at the device's far value.
TEST(TraceReaderRefusals, ATraceWithoutFramebufferRecordStartsWithDepthZero) {
    Device dev(profile(ProfileId::GeForce256), 8, 8, DepthFormat::D16, {Path::Reference, 1});
    std::fill(dev.framebuffer().depth().begin(), dev.framebuffer().depth().end(), 0u);
    auto rec = std::make_shared<TraceRecorder>();
    dev.setRecorder(rec);
    PipelineState s;
    s.cull = CullMode::None;
    s.depthFunc = CompareFunc::Less;  // nothing is nearer than 0: the draw changes nothing
    dev.setState(s);
    std::vector<Vertex> tri(3);
    tri[0].position = {0, 0, 0.5f, 1};
    tri[1].position = {8, 0, 0.5f, 1};
    tri[2].position = {0, 8, 0.5f, 1};
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
    dev.setRecorder(nullptr);
    rec->finish();
    const Trace t = readTrace(rec->bytes());
    ASSERT_TRUE(t.initialColor.empty() && t.initialDepth.empty());  // no Framebuffer record
    EXPECT_EQ(framebufferHash(replayTrace(t, {Path::Reference, 1, -1}).framebuffer), framebufferHash(dev.framebuffer()));
}

}  // namespace
}  // namespace rg::raster
