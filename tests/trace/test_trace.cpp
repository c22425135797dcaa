// The trace format (docs/trace-format.md): capture fidelity (a replay reproduces the
// capturing device's framebuffer), the reader's refusals, texture de-duplication, --pass,
// and the SHA-256 the replay prints.
#include <gtest/gtest.h>

#include <cstring>

#include "golden_cases.h"
#include "rasterizer/device.h"
#include "rasterizer/trace.h"

namespace rg::raster {
namespace {

TEST(TraceSha256, KnownVectors) {
    // FIPS 180-4 examples ("abc", the empty string, the 448-bit message).
    EXPECT_EQ(sha256Hex("abc", 3), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
    EXPECT_EQ(sha256Hex("", 0), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
    const char* m = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
    EXPECT_EQ(sha256Hex(m, std::strlen(m)), "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

// Every golden case: the replay on each path and thread count equals what the capturing
// device drew, byte for byte.
TEST(TraceCapture, ReplayReproducesTheCapturingDeviceForEveryGoldenCase) {
    for (const auto& c : golden::goldenCases()) {
        Framebuffer live;
        const std::vector<uint8_t> bytes = golden::buildGoldenTrace(c.name, &live);
        const Trace t = readTrace(bytes);
        for (auto [path, threads] : {std::pair{Path::Reference, 1}, std::pair{Path::Fast, 4}}) {
            const ReplayResult r = replayTrace(t, {path, threads, -1});
            ASSERT_EQ(framebufferHash(r.framebuffer), framebufferHash(live))
                << c.name << " on " << pathName(path) << " with " << threads << " threads";
            EXPECT_EQ(r.readBackMismatches, 0) << c.name;
        }
    }
}

TEST(TraceReader, RefusesEveryTruncation) {
    const std::vector<uint8_t> bytes = golden::buildGoldenTrace("texture-units-3d");
    for (size_t n = 0; n < bytes.size(); ++n)
        EXPECT_THROW(readTrace(std::span(bytes.data(), n)), TraceError) << "prefix of " << n << " bytes";
    EXPECT_NO_THROW(readTrace(bytes));
}

TEST(TraceReader, RefusesBadMagicVersionAndTrailingBytes) {
    std::vector<uint8_t> bytes = golden::buildGoldenTrace("alpha-test");
    auto bad = bytes;
    bad[0] = 'X';
    EXPECT_THROW(readTrace(bad), TraceError);
    bad = bytes;
    bad[8] = 3;  // version 3: not one this reader knows
    EXPECT_THROW(readTrace(bad), TraceError);
    bad[8] = 0;
    EXPECT_THROW(readTrace(bad), TraceError);
    bad = bytes;
    bad.push_back(0);
    EXPECT_THROW(readTrace(bad), TraceError);
}

// Single-byte corruptions either still parse or raise TraceError: never anything else.
TEST(TraceReader, SingleByteCorruptionsParseOrRaiseTraceError) {
    const std::vector<uint8_t> bytes = golden::buildGoldenTrace("pixel-texture");
    for (size_t i = 0; i < bytes.size(); i += 7)
        for (uint8_t x : {uint8_t(0x01), uint8_t(0x80), uint8_t(0xff)}) {
            auto bad = bytes;
            bad[i] ^= x;
            try {
                (void)readTrace(bad);
            } catch (const TraceError&) {
            }
        }
}

// A draw of D3DFVF_XYZ | D3DFVF_DIFFUSE vertices goes into a trace as the Vertex draw it
// stands for, and replays to the same bytes.
TEST(TraceRecorder, XyzDiffuseDrawsAreRecordedAsTheirVertices) {
    const Profile& p = profile(ProfileId::GeForce256);
    Device dev(p, 16, 16, DepthFormat::None, {Path::Fast, 1});
    auto rec = std::make_shared<TraceRecorder>();
    dev.setRecorder(rec);
    PipelineState s;
    s.cull = CullMode::None;
    dev.setState(s);
    dev.setTransforms(glm::mat4(1.0f), glm::mat4(1.0f),
                      glm::mat4(glm::vec4(0.125f, 0, 0, 0), glm::vec4(0, -0.125f, 0, 0),
                                glm::vec4(0, 0, 1, 0), glm::vec4(-1, 1, 0, 1)));
    const std::vector<VertexXyzDiffuse> tri = {{{1, 1, 0.5f}, {255, 0, 0, 255}},
                                               {{15, 2, 0.5f}, {0, 255, 0, 255}},
                                               {{3, 14, 0.5f}, {0, 0, 255, 255}}};
    dev.draw(Primitive::TriangleList, tri);
    dev.setRecorder(nullptr);
    rec->finish();
    const Trace trace = readTrace(rec->bytes());
    const std::string hash = framebufferHash(dev.framebuffer());
    EXPECT_EQ(framebufferHash(replayTrace(trace).framebuffer), hash);
    // Not the untouched target: the triangle drew.
    Device blank(p, 16, 16, DepthFormat::None, {Path::Fast, 1});
    EXPECT_NE(framebufferHash(blank.framebuffer()), hash);
}

TEST(TraceRecorder, SixteenBitIndicesThroughA65536EntryTableReplayExactly) {
    // Heidrich et al. 1999 §5 on sgi-octane-mxe: an I16 index texture drawn through a
    // 65,536-entry colour table, and a pixel transfer through the same unit. The trace
    // keeps the 16-bit values (not their 8-bit expansion) and the whole table, so the
    // replay picks the same entries.
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    Device dev(p, 16, 16, DepthFormat::None, {Path::Fast, 1});
    auto rec = std::make_shared<TraceRecorder>();
    dev.setRecorder(rec);
    tex::TextureMemory mem(p);
    auto t = mem.create({tex::TextureTarget::Texture2D, tex::TexelFormat::I16, 4, 4, 1, 1, 1});
    std::vector<uint8_t> bytes;
    for (int i = 0; i < 16; ++i) {
        const uint16_t v = uint16_t(4099 * i + 257);  // neighbours differ in the low byte too
        bytes.push_back(uint8_t(v & 0xff));
        bytes.push_back(uint8_t(v >> 8));
    }
    mem.upload(*t, 0, 0, bytes);
    auto table = std::make_shared<tex::ColorTable>();
    table->format = tex::BaseFormat::Rgba;
    for (uint32_t i = 0; i < 65536; ++i)
        table->entries.push_back({uint8_t(i), uint8_t(i >> 8), uint8_t(i * 13), 255});
    tex::TextureUnits& tu = dev.textureUnits();
    tu.setTexture(0, t);
    tex::SamplerState ss;
    ss.magFilter = ss.minFilter = tex::FilterMode::Nearest;
    tu.setSampler(0, ss);
    tu.setColorTable(0, table);
    tu.setStage(0, tex::texEnvStage(tex::TexEnvMode::Replace, tex::BaseFormat::Rgba));
    PipelineState s;
    s.cull = CullMode::None;
    s.depthTest = 0;
    dev.setState(s);
    std::vector<Vertex> quad(6);
    const glm::vec2 corners[6] = {{0, 0}, {16, 0}, {16, 16}, {0, 0}, {16, 16}, {0, 16}};
    for (int i = 0; i < 6; ++i) {
        quad[size_t(i)].position = glm::vec4(corners[i], 0.5f, 1.0f);
        quad[size_t(i)].tex[0] = glm::vec4(corners[i] / 16.0f, 0.0f, 1.0f);
    }
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, quad);
    tu.setPixelTexture({true, tex::PixelTexGenMode::Rgb, 0});
    std::vector<Rgba8> px(8 * 8);
    for (size_t i = 0; i < px.size(); ++i) px[i] = {uint8_t(i * 4), uint8_t(255 - i * 4), 0, 200};
    dev.drawPixels(8, 8, 8, 8, px);
    dev.setRecorder(nullptr);
    rec->finish();
    const std::string hash = framebufferHash(dev.framebuffer());
    EXPECT_EQ(dev.framebuffer().pixel(0, 0), table->entries[257]);  // texel (0, 0) = 257
    for (Path path : {Path::Reference, Path::Fast})
        EXPECT_EQ(framebufferHash(replayTrace(readTrace(rec->bytes()), {path, 2, -1}).framebuffer), hash);
}

TEST(TraceRecorder, TexturesAreStoredOncePerContent) {
    const Profile& p = profile(ProfileId::GeForce256);
    Device dev(p, 8, 8, DepthFormat::None, {Path::Reference, 1});
    tex::TextureMemory mem(p);
    auto t = mem.create({tex::TextureTarget::Texture2D, tex::TexelFormat::RGBA8, 2, 2, 1, 1, 1});
    std::vector<Rgba8> texels(4, Rgba8{1, 2, 3, 4});
    mem.upload(*t, 0, 0, texels);
    auto rec = std::make_shared<TraceRecorder>();
    dev.setRecorder(rec);
    PipelineState s;
    s.cull = CullMode::None;
    dev.setState(s);
    tex::StageState st;
    st.colorOp = tex::TextureOp::SelectArg1;
    dev.textureUnits().setStage(0, st);
    dev.textureUnits().setTexture(0, t);
    std::vector<Vertex> tri(3);
    tri[0].position = {0, 0, 0.5f, 1};
    tri[1].position = {8, 0, 0.5f, 1};
    tri[2].position = {0, 8, 0.5f, 1};
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);  // same contents
    texels[0] = {9, 9, 9, 9};
    mem.upload(*t, 0, 0, texels);  // in place: new contents, new record
    dev.draw(Primitive::TriangleList, VertexSpace::Pretransformed, tri);
    dev.setRecorder(nullptr);
    rec->finish();
    const Trace trace = readTrace(rec->bytes());
    EXPECT_EQ(trace.textures.size(), 2u);
    EXPECT_EQ(framebufferHash(replayTrace(trace).framebuffer), framebufferHash(dev.framebuffer()));
}

// --pass K: each pass changes the image, the last one ends with the frame, K past the
// last pass is refused.
TEST(TraceReplay, PassKStopsAtTheEndOfPassK) {
    Framebuffer live;
    const Trace t = readTrace(golden::buildGoldenTrace("passes-readback", &live));
    ASSERT_EQ(t.passCount(), 3);
    const std::string full = framebufferHash(replayTrace(t, {Path::Fast, 2, -1}).framebuffer);
    EXPECT_EQ(full, framebufferHash(live));
    std::string previous;
    for (int k = 0; k < 3; ++k) {
        const std::string h = framebufferHash(replayTrace(t, {Path::Reference, 1, k}).framebuffer);
        EXPECT_NE(h, previous) << "pass " << k << " changed nothing";
        previous = h;
    }
    EXPECT_EQ(previous, full);  // the last pass ends with the frame
    EXPECT_THROW(replayTrace(t, {Path::Reference, 1, 3}), TraceError);
}

// ReplayOptions::hash = false (the bench's replays): the same framebuffer, no hash; the
// default hash is the SHA-256 of the framebuffer's bytes, as `retroglass replay` prints.
TEST(TraceReplay, WithoutTheHashTheFramebufferIsTheSame) {
    Framebuffer live;
    const Trace t = readTrace(golden::buildGoldenTrace("passes-readback", &live));
    ReplayOptions noHash;
    noHash.hash = false;
    const ReplayResult quiet = replayTrace(t, noHash);
    const ReplayResult hashed = replayTrace(t);
    EXPECT_TRUE(quiet.hash.empty());
    EXPECT_EQ(hashed.hash, sha256Hex(live.color().data(), live.color().size() * sizeof(Rgba8)));
    EXPECT_EQ(framebufferHash(quiet.framebuffer), hashed.hash);
}

}  // namespace
}  // namespace rg::raster
