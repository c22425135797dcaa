// Traces of the programmable profile (docs/trace-format.md, version 2): the program
// registry, capture fidelity of a frame that uses every version-2 record (render targets
// written and sampled in place, multiple targets, float and depth targets, clears,
// viewport, scissor, blending, uniforms, indexed and point draws, a target with contents
// before the capture, a texture re-uploaded in place), replay on both paths and several
// thread counts, a replay re-recording its trace byte for byte, and the reader's refusals
// of malformed input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "bench_programs.h"
#include "binary_search_retroglass.h"
#include "core/profile.h"
#include "golden_cases.h"
#include "program_frame.h"
#include "rasterizer/program_registry.h"
#include "rasterizer/programmable_device.h"
#include "rasterizer/trace.h"

namespace rg::raster {
namespace {

using namespace test;

// ---- record editing -----------------------------------------------------------------------

struct Record {
    uint8_t kind;
    std::vector<uint8_t> payload;
};

std::vector<Record> split(const std::vector<uint8_t>& bytes) {
    std::vector<Record> out;
    size_t p = 12;
    while (p < bytes.size()) {
        uint32_t len;
        std::memcpy(&len, bytes.data() + p + 1, 4);
        out.push_back({bytes[p], std::vector<uint8_t>(bytes.begin() + ptrdiff_t(p + 5), bytes.begin() + ptrdiff_t(p + 5 + len))});
        p += 5 + len;
    }
    return out;
}

std::vector<uint8_t> join(const std::vector<uint8_t>& original, const std::vector<Record>& records) {
    std::vector<uint8_t> out(original.begin(), original.begin() + 12);  // magic and version
    for (const Record& r : records) {
        out.push_back(r.kind);
        const uint32_t len = uint32_t(r.payload.size());
        out.insert(out.end(), reinterpret_cast<const uint8_t*>(&len), reinterpret_cast<const uint8_t*>(&len) + 4);
        out.insert(out.end(), r.payload.begin(), r.payload.end());
    }
    return out;
}

size_t first(const std::vector<Record>& rs, TraceOp op, size_t from = 0) {
    for (size_t i = from; i < rs.size(); ++i)
        if (rs[i].kind == uint8_t(op)) return i;
    ADD_FAILURE() << "no record of kind " << int(op);
    return 0;
}

size_t count(const std::vector<Record>& rs, TraceOp op) {
    return size_t(std::count_if(rs.begin(), rs.end(), [&](const Record& r) { return r.kind == uint8_t(op); }));
}

// A ProgramDraw payload with another program name.
std::vector<uint8_t> renamed(const std::vector<uint8_t>& draw, const std::string& name) {
    std::vector<uint8_t> out(1 + name.size());
    out[0] = uint8_t(name.size());
    std::memcpy(out.data() + 1, name.data(), name.size());
    out.insert(out.end(), draw.begin() + 1 + draw[0], draw.end());
    return out;
}

std::string readError(const std::vector<uint8_t>& bytes) {
    try {
        (void)readTrace(bytes);
    } catch (const TraceError& e) {
        return e.what();
    }
    return "(no error)";
}

// ---- the registry -----------------------------------------------------------------------------

TEST(ProgramRegistry, RegisteringAgainIsANoOpAndNamesOneProgramEach) {
    registerTestPrograms();
    const RegisteredProgram& p = registerProgram<TransformVP, TexturedMrtFP, TestVertex>("test/textured_mrt");
    EXPECT_EQ(&p, findProgram("test/textured_mrt"));
    EXPECT_EQ(&p, findProgram(std::type_index(typeid(detail::ProgramTriple<TransformVP, TexturedMrtFP, TestVertex>))));
    EXPECT_EQ(p.vertexProgramBytes, sizeof(TransformVP));
    EXPECT_EQ(p.fragmentProgramBytes, sizeof(TexturedMrtFP));
    EXPECT_EQ(p.vertexBytes, sizeof(TestVertex));
    EXPECT_EQ(p.units, 1u);
    EXPECT_EQ(p.targets, 3u);
    // An empty program type is recorded as no bytes.
    EXPECT_EQ(findProgram("bench/binary_search")->vertexProgramBytes, 0u);
    EXPECT_EQ(findProgram("bench/binary_search")->fragmentProgramBytes, 0u);
    // A name another triple has, and a triple under a second name, are refused.
    EXPECT_THROW((registerProgram<TransformVP, CompositeFP, TestVertex>("test/textured_mrt")), Error);
    EXPECT_THROW((registerProgram<TransformVP, TexturedMrtFP, TestVertex>("test/other_name")), Error);
    EXPECT_EQ(findProgram("test/other_name"), nullptr);
    for (const char* bad : {"", "Test/Upper", "has space", "quote\"", "\xc3\xa9"})
        EXPECT_THROW((registerProgram<ClipVP, CompositeFP, ClipVertex>(bad)), Error) << bad;
    EXPECT_THROW((registerProgram<ClipVP, CompositeFP, ClipVertex>(std::string(256, 'a'))), Error);
    const std::vector<std::string> names = registeredProgramNames();
    EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
    EXPECT_NE(std::find(names.begin(), names.end(), "test/composite"), names.end());
}

TEST(ProgramRegistry, RecordingAnUnregisteredProgramIsAnErrorNamingIt) {
    registerTestPrograms();
    tex::TextureMemory mem(g80());
    ProgrammableDevice dev(g80(), {Path::Fast, 1});
    tex::TextureDesc d;
    d.width = d.height = 8;
    ColorTarget c{mem.createRenderTarget(d)};
    dev.setRenderTargets({&c, 1});
    auto rec = std::make_shared<TraceRecorder>();
    dev.setRecorder(rec);
    const std::vector<TestVertex> tri = {vtx(-1, 1, 0.5f, 0, 0, {}), vtx(1, 1, 0.5f, 0, 0, {}), vtx(-1, -1, 0.5f, 0, 0, {})};
    try {
        dev.draw(TransformVP{}, UnregisteredFP{}, ProgramPrimitive::TriangleList, std::span<const TestVertex>(tri));
        ADD_FAILURE() << "recorded an unregistered program";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("UnregisteredFP"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("registerProgram"), std::string::npos) << e.what();
    }
    // Nothing of the refused draw is in the trace, and nothing was drawn.
    dev.setRecorder(nullptr);
    rec->finish();
    const Trace t = readTrace(rec->bytes());
    EXPECT_EQ(std::count_if(t.commands.begin(), t.commands.end(),
                            [](const TraceCommand& x) { return x.op == TraceOp::ProgramDraw; }),
              0);
    EXPECT_EQ(dev.counters().drawCalls, 0u);
}

// ---- capture and replay ------------------------------------------------------------------------

TEST(ProgramTraceCapture, EveryRecordKindOfTheFrameIsWritten) {
    const Frame f = recordFrame();
    EXPECT_EQ(f.trace[8], 2) << "a programmable trace is version 2";
    const std::vector<Record> rs = split(f.trace);
    EXPECT_EQ(rs.front().kind, uint8_t(TraceOp::ProgrammableDevice));
    EXPECT_EQ(rs.back().kind, uint8_t(TraceOp::End));
    EXPECT_EQ(count(rs, TraceOp::RenderTarget), 5u);
    EXPECT_EQ(count(rs, TraceOp::RenderTargets), 2u);
    EXPECT_EQ(count(rs, TraceOp::TargetHash), 5u);
    EXPECT_EQ(count(rs, TraceOp::Texture), 3u) << "t0, t0 after its re-upload, t1";
    EXPECT_EQ(count(rs, TraceOp::ProgramDraw), 5u);
    EXPECT_EQ(count(rs, TraceOp::ClearTarget), 3u);
    EXPECT_EQ(count(rs, TraceOp::ClearDepth), 1u);
    EXPECT_EQ(count(rs, TraceOp::BeginFrame), 1u);
    EXPECT_GE(count(rs, TraceOp::ProgramState), 4u);
    EXPECT_GE(count(rs, TraceOp::Viewport), 1u);
    EXPECT_GE(count(rs, TraceOp::ProgramScissor), 1u);
    EXPECT_GE(count(rs, TraceOp::ProgramTexture), 4u);
    const Trace t = readTrace(f.trace);
    // Only `before` had contents at its first use.
    int withContents = 0;
    for (const auto& [id, rt] : t.renderTargets) withContents += !rt.contents.empty();
    EXPECT_EQ(withContents, 1);
    EXPECT_EQ(t.width, 32);
    EXPECT_EQ(t.height, 32);
}

// The replay leaves every render target as the capturing device left it, on both paths
// and at 1, 2 and 3 threads; the capture's own path and thread count do not matter.
TEST(ProgramTraceReplay, EveryTargetEqualsTheCaptureOnBothPathsAndAnyThreadCount) {
    const Frame f = recordFrame(Path::Reference, 1);
    EXPECT_EQ(recordFrame(Path::Fast, 3).trace, f.trace) << "the capture depends on the capturing path";
    const Trace t = readTrace(f.trace);
    for (auto [path, threads] : {std::pair{Path::Reference, 1}, std::pair{Path::Fast, 1}, std::pair{Path::Fast, 2},
                                 std::pair{Path::Fast, 3}}) {
        const ReplayResult r = replayTrace(t, {path, threads, -1});
        EXPECT_EQ(r.targetChecks, 5) << pathName(path) << " " << threads;
        EXPECT_EQ(r.targetMismatches, 0) << pathName(path) << " " << threads;
        EXPECT_EQ(r.hash, f.imageHash) << pathName(path) << " " << threads;
        ASSERT_EQ(r.framebuffer.width(), 32);
        EXPECT_EQ(std::memcmp(r.framebuffer.color().data(), f.targets[3].data(), f.targets[3].size()), 0);
    }
    // Each target drew something (not the cleared or zero target): the frame tests what it says.
    for (size_t i = 0; i < f.targets.size(); ++i) {
        const std::vector<uint8_t>& v = f.targets[i];
        EXPECT_FALSE(std::all_of(v.begin(), v.end(), [&](uint8_t x) { return x == v[0]; })) << "target " << i;
    }
}

// A replay with a recorder attached records the trace it plays, byte for byte: the
// recorder and the player are each other's inverse. For the frame, and every golden trace
// (version 1 and 2).
TEST(ProgramTraceReplay, AReplayRecordsTheTraceItPlays) {
    auto check = [](const std::vector<uint8_t>& bytes, const std::string& name) {
        const Trace t = readTrace(bytes);
        auto again = std::make_shared<TraceRecorder>();
        (void)replayTrace(t, {Path::Fast, 2, -1}, again);
        again->finish();
        EXPECT_EQ(again->bytes() == bytes, true) << name << ": " << again->bytes().size() << " bytes re-recorded, "
                                                 << bytes.size() << " played";
    };
    check(recordFrame().trace, "the frame");
    golden::registerGoldenPrograms();
    for (const auto& c : golden::goldenCases()) check(golden::buildGoldenTrace(c.name), c.name);
}

// The golden binary-search trace replays to the workload's scalar reference image
// (bench/binary_search_workload.h), byte for byte: its hash is an analytic oracle's.
TEST(ProgramTraceReplay, BinarySearchGoldenIsTheWorkloadReferenceImage) {
    golden::registerGoldenPrograms();
    const Trace t = readTraceFile(RETROGLASS_SOURCE_DIR "/tests/golden/programmable-binary-search.trace");
    const ReplayResult r = replayTrace(t, {Path::Fast, 2, -1});
    const std::vector<uint8_t> want = bench::binary_search::referenceImage();
    ASSERT_EQ(r.framebuffer.color().size_bytes(), want.size());
    EXPECT_EQ(std::memcmp(r.framebuffer.color().data(), want.data(), want.size()), 0);
    EXPECT_EQ(r.hash, sha256Hex(want.data(), want.size()));
    EXPECT_EQ(r.targetChecks, 1);
    EXPECT_EQ(r.targetMismatches, 0);
}

// The target-hash check catches a target that ends otherwise than at capture.
TEST(ProgramTraceReplay, ATargetThatDiffersFromTheCaptureIsCounted) {
    const Frame f = recordFrame();
    std::vector<Record> rs = split(f.trace);
    rs[first(rs, TraceOp::TargetHash)].payload[8] ^= 1;
    const ReplayResult r = replayTrace(readTrace(join(f.trace, rs)), {Path::Fast, 2, -1});
    EXPECT_EQ(r.targetChecks, 5);
    EXPECT_EQ(r.targetMismatches, 1);
    EXPECT_THROW(replayTrace(readTrace(f.trace), {Path::Reference, 1, 0}), TraceError) << "--pass on a programmable trace";
}

// ---- the reader --------------------------------------------------------------------------------

// A small binary-search trace: the fuzz target's seed (fuzz/corpus/trace_reader/) and the
// corruption tests' input. Both programs, a scissored clear, an indexed draw.
std::vector<uint8_t> smallSearchTrace() {
    bench::registerPrograms();
    namespace bs = bench::binary_search;
    tex::TextureMemory mem(g80());
    ProgrammableDevice dev(g80(), {Path::Fast, 1});
    tex::TextureDesc dd;
    dd.format = tex::TexelFormat::R32F;
    dd.width = dd.height = 4;
    auto depth = mem.create(dd);
    std::vector<float> values = {0.3f, 0.4f, 0.5f, 0.6f, 0.7f, 0.35f, 0.45f, 0.55f,
                                 0.65f, 0.75f, 0.3f, 0.5f, 0.7f, 0.4f, 0.6f, 0.5f};
    std::vector<uint8_t> bytes(values.size() * 4);
    std::memcpy(bytes.data(), values.data(), bytes.size());
    mem.upload(*depth, 0, 0, bytes);
    tex::TextureDesc td;
    td.width = td.height = 8;
    ColorTarget c{mem.createRenderTarget(td)};
    dev.setRenderTargets({&c, 1});
    tex::SamplerState s;
    s.magFilter = s.minFilter = tex::FilterMode::Nearest;
    dev.setTexture(0, depth, s);
    auto rec = std::make_shared<TraceRecorder>();
    dev.setRecorder(rec);
    const Rect scissor{1, 1, 6, 5};
    dev.setScissor(&scissor);
    dev.clearColor(0, {0.2f, 0.4f, 0.6f, 1.0f});
    const std::vector<bs::QuadVertex> quad = {{{-1, 1, 0.5f, 1}}, {{1, 1, 0.5f, 1}}, {{-1, -1, 0.5f, 1}}, {{1, -1, 0.5f, 1}}};
    dev.draw(bs::QuadVP{}, bs::BinarySearchQuadFP{}, ProgramPrimitive::TriangleList, std::span<const bs::QuadVertex>(quad),
             std::vector<uint32_t>{0, 1, 2});
    dev.setScissor(nullptr);
    dev.draw(bs::QuadVP{}, bs::BinarySearchFP{}, ProgramPrimitive::TriangleStrip, std::span<const bs::QuadVertex>(quad));
    dev.setRecorder(nullptr);
    rec->finish();
    return rec->bytes();
}

// The seed is what the recorder writes today (regenerate: RETROGLASS_WRITE_FUZZ_SEED=1
// build/bin/test_trace --gtest_filter='ProgramTraceReader.FuzzSeedIsTheCurrentSmallSearchTrace').
TEST(ProgramTraceReader, FuzzSeedIsTheCurrentSmallSearchTrace) {
    const std::filesystem::path seed = RETROGLASS_SOURCE_DIR "/fuzz/corpus/trace_reader/programmable-small-search.trace";
    const std::vector<uint8_t> want = smallSearchTrace();
    if (std::getenv("RETROGLASS_WRITE_FUZZ_SEED")) {
        std::ofstream out(seed, std::ios::binary);
        out.write(reinterpret_cast<const char*>(want.data()), std::streamsize(want.size()));
    }
    std::ifstream in(seed, std::ios::binary);
    const std::vector<uint8_t> got((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(got == want, true) << seed << " is not the current small search trace";
    const Trace t = readTrace(want);
    EXPECT_EQ(replayTrace(t, {Path::Reference, 1, -1}).targetMismatches, 0);
}

TEST(ProgramTraceReader, RefusesEveryTruncation) {
    const std::vector<uint8_t> bytes = smallSearchTrace();
    for (size_t n = 0; n < bytes.size(); ++n)
        EXPECT_THROW(readTrace(std::span(bytes.data(), n)), TraceError) << "prefix of " << n << " bytes";
    EXPECT_NO_THROW(readTrace(bytes));
}

// Every single-byte corruption parses or raises TraceError; what parses replays or raises
// an rg::Error (the device's refusal): never a crash or another exception.
TEST(ProgramTraceReader, SingleByteCorruptionsParseOrRaiseTraceErrorAndReplayOrRaiseError) {
    const std::vector<uint8_t> bytes = smallSearchTrace();
    int parsed = 0, refused = 0;
    for (size_t i = 0; i < bytes.size(); ++i)
        for (uint8_t x : {uint8_t(0x01), uint8_t(0x80), uint8_t(0xff)}) {
            auto bad = bytes;
            bad[i] ^= x;
            Trace t;
            try {
                t = readTrace(bad);
            } catch (const TraceError&) {
                ++refused;
                continue;
            }
            ++parsed;
            uint64_t targetBytes = 0;
            for (const auto& [id, rt] : t.renderTargets) targetBytes += renderTargetValueBytes(rt.desc);
            if (targetBytes > (1u << 20)) continue;  // a corrupted extent: valid, but large
            try {
                (void)replayTrace(t, {Path::Reference, 1, -1});
            } catch (const Error&) {
            }
        }
    EXPECT_GT(parsed, 0);
    EXPECT_GT(refused, 0);
}

TEST(ProgramTraceReader, AnUnknownProgramIsAnErrorNamingIt) {
    const std::vector<uint8_t> bytes = smallSearchTrace();
    std::vector<Record> rs = split(bytes);
    const size_t d = first(rs, TraceOp::ProgramDraw);
    rs[d].payload = renamed(rs[d].payload, "nowhere/final_pass");
    const std::string e = readError(join(bytes, rs));
    EXPECT_NE(e.find("program 'nowhere/final_pass' is not registered"), std::string::npos) << e;
    EXPECT_NE(e.find("bench/binary_search"), std::string::npos) << "lists what is registered: " << e;
}

TEST(ProgramTraceReader, RecordedSizesMustBeTheRegisteredTypes) {
    registerTestPrograms();
    const Frame f = recordFrame();
    std::vector<Record> rs = split(f.trace);
    const size_t d = first(rs, TraceOp::ProgramDraw);
    // The frame's draw (48-byte vertex program, 16-byte fragment program, 48-byte vertices)
    // named as programs of other sizes.
    auto with = [&](const std::string& name) {
        std::vector<Record> x = rs;
        x[d].payload = renamed(x[d].payload, name);
        return readError(join(f.trace, x));
    };
    std::string e = with("bench/binary_search");
    EXPECT_NE(e.find("the vertex program of program 'bench/binary_search' is 48 bytes in the trace, but 0"),
              std::string::npos) << e;
    e = with("test/composite");  // same vertex program, same fragment-program size: accepted
    EXPECT_EQ(e, "(no error)");
    e = with("test/clip_only");
    EXPECT_NE(e.find("vertices of program 'test/clip_only' are 48 bytes each in the trace, but 16"), std::string::npos)
        << e;
}

TEST(ProgramTraceReader, RefusesRecordsOfTheOtherVersionOrDevice) {
    // A version-2 record in a version-1 trace.
    const std::vector<uint8_t> v1 = golden::buildGoldenTrace("alpha-test");
    std::vector<Record> rs = split(v1);
    const Frame f = recordFrame();
    const std::vector<Record> v2 = split(f.trace);
    rs.insert(rs.begin() + 1, v2[first(v2, TraceOp::ProgramState)]);
    EXPECT_NE(readError(join(v1, rs)).find("version 2 record in a version 1 trace"), std::string::npos);
    // A fixed-function record in a programmable trace.
    std::vector<Record> x = v2;
    x.insert(x.begin() + 1, split(v1)[first(split(v1), TraceOp::State)]);
    EXPECT_NE(readError(join(f.trace, x)).find("belongs to the other device"), std::string::npos);
    // A version-1 trace still reads and plays as before.
    EXPECT_NO_THROW(replayTrace(readTrace(v1)));
}

TEST(ProgramTraceReader, RefusesOutOfRangeValuesAndDanglingReferences) {
    const Frame f = recordFrame();
    const std::vector<Record> rs = split(f.trace);
    auto refused = [&](const std::function<void(std::vector<Record>&)>& edit, const std::string& expect) {
        std::vector<Record> x = rs;
        edit(x);
        const std::string e = readError(join(f.trace, x));
        EXPECT_NE(e.find(expect), std::string::npos) << "expected '" << expect << "', got: " << e;
    };
    const size_t rt = first(rs, TraceOp::RenderTarget), binding = first(rs, TraceOp::RenderTargets);
    const size_t state = first(rs, TraceOp::ProgramState), unit = first(rs, TraceOp::ProgramTexture);
    const size_t draw = first(rs, TraceOp::ProgramDraw), hash = first(rs, TraceOp::TargetHash);
    refused([&](auto& x) { x[rt].payload[9] = uint8_t(tex::TexelFormat::L8); }, "not a render-target format");
    refused([&](auto& x) { x[rt].payload[8] = uint8_t(tex::TextureTarget::Texture3D); }, "1D, 2D or a cube map");
    refused([&](auto& x) { x[rt].payload[13] = 0x80; }, "extent out of range");
    refused([&](auto& x) { x[rt].payload[18] = 7; }, "level count out of range");
    refused([&](auto& x) { x[rt].payload.back() = 2; }, "contents flag out of range");
    refused([&](auto& x) { x[rt].payload.back() = 1; }, "ends");  // contents promised, not there
    refused([&](auto& x) { x[binding].payload[0] = 5; }, "more than 4 colour targets");
    refused([&](auto& x) { x[binding].payload[1] ^= 0x40; }, "has not defined");
    refused([&](auto& x) { x[binding].payload[9] = 1; }, "level or face out of range");
    refused([&](auto& x) { std::swap(x[binding].payload[1], x[binding].payload[1 + 2 * 16]); },
            "a colour target has a depth format");  // colour target 0 and the depth target swapped
    refused([&](auto& x) { x[state].payload[0] = 3; }, "cull mode 3 is out of range");
    refused([&](auto& x) { x[state].payload[3] = 8; }, "depth func 8 is out of range");
    refused([&](auto& x) { std::memset(x[state].payload.data() + 4, 0, 4); }, "point size outside (0, 8192]");
    refused([&](auto& x) { x[state].payload[8 + 4] = 16; }, "colour write mask out of range");
    refused([&](auto& x) { x[state].payload[8 + 3] = 5; }, "blend op 5 is out of range");
    refused([&](auto& x) { x[unit].payload[0] = 16; }, "texture unit 16 is out of range");
    refused([&](auto& x) { x[unit].payload[1] ^= 0x40; }, "binds a texture the trace has not defined");
    refused([&](auto& x) { x[unit].payload[9] = 5; }, "address mode 5 is out of range");
    refused([&](auto& x) { x[draw].payload[1 + x[draw].payload[0]] = 4; }, "primitive 4 is out of range");
    refused([&](auto& x) { x.insert(x.begin() + ptrdiff_t(draw), x[hash]); }, "only TargetHash records may follow");
    refused([&](auto& x) { x.insert(x.begin() + ptrdiff_t(hash), x[hash]); }, "a second hash of one render target");
    refused([&](auto& x) { x[hash].payload[7] ^= 0x40; }, "render target the trace has not defined");
    refused([&](auto& x) { x.insert(x.begin() + 1, x[0]); }, "a second device record");
    refused([&](auto& x) { x[0].payload = {3, 'x', 'y', 'z'}; }, "unknown profile 'xyz'");
    refused([&](auto& x) { x[0].payload = {10, 'g', 'e', 'f', 'o', 'r', 'c', 'e', '2', '5', '6'}; },
            "has no programmable pipeline");
    refused([&](auto& x) { x[first(x, TraceOp::ClearTarget)].payload[0] = 4; }, "colour target 4 is out of range");
    // An index past the vertices.
    {
        const std::vector<uint8_t> small = smallSearchTrace();
        std::vector<Record> y = split(small);
        Record& d = y[first(y, TraceOp::ProgramDraw)];
        d.payload[d.payload.size() - 4] = 9;  // the last index of {0, 1, 2}; 4 vertices
        const std::string e = readError(join(small, y));
        EXPECT_NE(e.find("index 9 past the vertices"), std::string::npos) << e;
    }
}

}  // namespace
}  // namespace rg::raster
