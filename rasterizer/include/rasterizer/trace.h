// Capture and replay of the emulated device (docs/trace-format.md).
//
// A trace is everything a Device was asked to do, in order: the profile and framebuffer,
// every state that a command reads (pipeline state, transforms, viewport, scissor, texture
// stages, samplers, TFACTOR, texgen, colour tables, pixel texture), the contents of every
// texture a command reads (all levels and faces, stored once per content hash), and the
// commands themselves (clears, draws, pixel transfers, read-backs, frames and passes).
//
//   capture:  Device ──(setRecorder)──▶ TraceRecorder ──▶ bytes / .trace file
//   replay:   .trace ──▶ readTrace() ──▶ Trace ──▶ replayTrace() ──▶ Framebuffer
//
// The recorder is fed by the Device at each command and diffs the device's current state
// against what it last wrote, so applications configure the device (and its texture
// units) as usual and nothing in texunit/ knows about tracing. Texture contents are
// hashed at the commands that read them, which also catches re-uploads in place.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/color.h"
#include "core/error.h"
#include "core/path.h"
#include "rasterizer/framebuffer.h"
#include "rasterizer/state.h"
#include "rasterizer/vertex.h"
#include "texunit/texture_units.h"

namespace rg::raster {

class Device;

constexpr uint32_t kTraceVersion = 1;
// The eight bytes every trace starts with.
constexpr char kTraceMagic[8] = {'R', 'G', 'T', 'R', 'A', 'C', 'E', '\0'};

// Record kinds (docs/trace-format.md, "Records"). The numbers are the file format.
enum class TraceOp : uint8_t {
    Device = 0x01,        // profile, framebuffer size, depth format (first record)
    Framebuffer = 0x02,   // initial colour (and depth) contents when not all zero
    State = 0x10,         // PipelineState
    Transforms = 0x11,    // world, view, projection
    Viewport = 0x12,
    Scissor = 0x13,
    Stage = 0x20,         // StageState of one stage
    Sampler = 0x21,       // SamplerState of one stage
    TextureFactor = 0x22,
    TexGen = 0x23,        // TexGenState of one coordinate set
    ColorTable = 0x24,    // colour table of one stage (or none)
    PixelTexture = 0x25,
    Texture = 0x26,       // texture contents, identified by their content hash
    BindTexture = 0x27,   // texture of one stage (by content hash, 0: none)
    BeginFrame = 0x30,
    BeginPass = 0x31,
    EndFrame = 0x32,
    Clear = 0x40,
    Draw = 0x41,
    DrawPixels = 0x42,
    CopyPixels = 0x43,
    ReadPixels = 0x44,
    End = 0xff,           // last record: a trace without it is truncated
};

// A trace that cannot be read: truncated, wrong magic or version, a record whose length
// does not match its contents, a value out of range.
class TraceError : public Error {
  public:
    using Error::Error;
};

// 64-bit FNV-1a: the content hash of textures and read-backs (not a security hash).
uint64_t traceHash64(const void* data, size_t size, uint64_t seed = 0xcbf29ce484222325ull);
// SHA-256 (FIPS 180-4) as 64 lowercase hex digits: the hash `retroglass replay` prints
// for the raw framebuffer bytes and the golden manifest stores.
std::string sha256Hex(const void* data, size_t size);
// The replay hash of a framebuffer: SHA-256 of its colour bytes (RGBA8, rows top to bottom).
std::string framebufferHash(const Framebuffer& fb);

// ---- capture ---------------------------------------------------------------------------
// Collects a trace in memory; Device::setRecorder() attaches it (writing the Device
// record and the framebuffer contents at that moment), the device then feeds it at every
// command. finish() writes the End record; save() finishes and writes the file.
class TraceRecorder {
  public:
    TraceRecorder();
    ~TraceRecorder();
    TraceRecorder(const TraceRecorder&) = delete;
    TraceRecorder& operator=(const TraceRecorder&) = delete;

    const std::vector<uint8_t>& bytes() const;
    void finish();
    void save(const std::filesystem::path& file);
    bool finished() const;

    // ---- called by the Device --------------------------------------------------------
    void attach(const Device& device);
    void beginFrame();
    void beginPass(const std::string& label);
    void endFrame();
    void clear(const Device& device, bool color, Rgba8 colorValue, bool depth, float depthValue);
    void draw(const Device& device, Primitive primitive, VertexSpace space,
              std::span<const Vertex> vertices, std::span<const uint32_t> indices);
    void drawPixels(const Device& device, int x, int y, int width, int height,
                    std::span<const Rgba8> pixels);
    void copyPixels(const Device& device, int srcX, int srcY, int width, int height, int dstX,
                    int dstY);
    void readPixels(int x, int y, int width, int height, std::span<const Rgba8> result);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// ---- read ------------------------------------------------------------------------------
struct TraceTexture {
    uint64_t id = 0;
    tex::TextureDesc desc;
    // Packed texels in the format's layout (format.h), level 0 first, within a level
    // face 0 first; each face's level is `levelBytes` long.
    std::vector<std::vector<uint8_t>> levelFaces;  // [level * faces + face]
};

// One record after Device/Framebuffer/Texture. Only the fields of its op are meaningful.
struct TraceCommand {
    TraceOp op{};
    int unit = 0;  // stage or coordinate set
    PipelineState state;
    glm::mat4 world{1.0f}, view{1.0f}, projection{1.0f};
    Viewport viewport;
    Rect rect;  // Scissor; DrawPixels/ReadPixels rectangle; CopyPixels source
    int dstX = 0, dstY = 0;
    tex::StageState stage;
    tex::SamplerState sampler;
    Rgba8 color;  // TextureFactor, Clear colour
    tex::TexGenState texGen;
    std::shared_ptr<const tex::ColorTable> colorTable;  // nullptr: none
    tex::PixelTextureState pixelTexture;
    uint64_t textureId = 0;  // BindTexture (0: unbind); ReadPixels: content hash
    std::string label;
    bool clearColor = false, clearDepth = false;
    float depthValue = 1.0f;
    Primitive primitive = Primitive::TriangleList;
    VertexSpace space = VertexSpace::Untransformed;
    std::vector<Vertex> vertices;
    std::vector<uint32_t> indices;
    std::vector<Rgba8> pixels;
};

struct Trace {
    uint32_t version = kTraceVersion;
    std::string profile;
    int width = 0, height = 0;
    DepthFormat depth = DepthFormat::None;
    std::vector<Rgba8> initialColor;     // empty: all zero
    std::vector<uint32_t> initialDepth;  // empty: all zero
    std::map<uint64_t, TraceTexture> textures;
    std::vector<TraceCommand> commands;
    int passCount() const;
};

// Parses and checks the framing and value ranges of every record; does not draw.
// Throws TraceError.
Trace readTrace(std::span<const uint8_t> bytes);
Trace readTraceFile(const std::filesystem::path& file);

// ---- replay ----------------------------------------------------------------------------
struct ReplayOptions {
    Path path = Path::Fast;
    int threads = 0;
    int stopAfterPass = -1;  // >= 0: stop when pass K (counted from 0 over the trace) ends
};

struct ReplayResult {
    Framebuffer framebuffer;
    int passes = 0;             // passes begun
    int readBacks = 0;          // ReadPixels commands replayed
    int readBackMismatches = 0; // of which returned other bytes than at capture
};

// Plays the trace on a fresh Device of the trace's profile. Throws TraceError for
// --pass past the last pass, and whatever the device throws for state it refuses.
ReplayResult replayTrace(const Trace& trace, const ReplayOptions& options = {});

}  // namespace rg::raster
