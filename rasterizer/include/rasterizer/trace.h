// Capture and replay of the emulated devices (docs/trace-format.md).
//
// A trace is everything a device was asked to do, in order. For the fixed-function Device
// (version 1): the profile and framebuffer, every state that a command reads (pipeline
// state, transforms, viewport, scissor, texture stages, samplers, TFACTOR, texgen, colour
// tables, pixel texture), the contents of every texture a command reads (all levels and
// faces, stored once per content hash), and the commands themselves (clears, draws, pixel
// transfers, read-backs, frames and passes). For the ProgrammableDevice (version 2): the
// profile, the render targets (size, format, contents at first use), the bound targets,
// program state, viewport, scissor, the texture and sampler of every unit a draw reads,
// clears, and draws naming their program by its registered name
// (rasterizer/include/rasterizer/program_registry.h) with the program objects' and
// vertices' bytes; at the end a hash of every render target's final contents.
//
//   capture:  Device / ProgrammableDevice ──(setRecorder)──▶ TraceRecorder ──▶ .trace file
//   replay:   .trace ──▶ readTrace() ──▶ Trace ──▶ replayTrace() ──▶ image + hashes
//
// The recorder is fed by the device at each command and diffs the device's current state
// against what it last wrote, so applications configure the device (and its texture
// units) as usual and nothing in texunit/ knows about tracing. Texture contents are
// hashed at the commands that read them, which also catches re-uploads in place.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <typeindex>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/color.h"
#include "core/error.h"
#include "core/path.h"
#include "rasterizer/framebuffer.h"
#include "rasterizer/program.h"
#include "rasterizer/state.h"
#include "rasterizer/vertex.h"
#include "texunit/texture_units.h"

namespace rg::raster {

class Device;
class ProgrammableDevice;
struct RegisteredProgram;

// Version 1: the fixed-function Device's records. Version 2 adds the programmable
// device's. A recorder writes the lowest version that holds its records (a Device's
// trace is version 1, readable by version-1 readers); the reader reads both.
constexpr uint32_t kTraceVersionFixedFunction = 1;
constexpr uint32_t kTraceVersionProgrammable = 2;
constexpr uint32_t kTraceVersion = 2;  // the newest version readTrace() reads
// The eight bytes every trace starts with.
constexpr char kTraceMagic[8] = {'R', 'G', 'T', 'R', 'A', 'C', 'E', '\0'};

// Record kinds (docs/trace-format.md, "Records"). The numbers are the file format.
enum class TraceOp : uint8_t {
    Device = 0x01,        // profile, framebuffer size, depth format (first record)
    Framebuffer = 0x02,   // initial colour (and depth) contents when not all zero
    ProgrammableDevice = 0x03,  // v2: profile (first record of a programmable trace)
    State = 0x10,         // PipelineState
    Transforms = 0x11,    // world, view, projection
    Viewport = 0x12,      // both devices
    Scissor = 0x13,
    ProgramState = 0x14,    // v2: ProgramState
    RenderTargets = 0x15,   // v2: the bound colour targets and depth target
    ProgramScissor = 0x16,  // v2: the scissor rectangle, or off
    Stage = 0x20,         // StageState of one stage
    Sampler = 0x21,       // SamplerState of one stage
    TextureFactor = 0x22,
    TexGen = 0x23,        // TexGenState of one coordinate set
    ColorTable = 0x24,    // colour table of one stage (or none)
    PixelTexture = 0x25,
    Texture = 0x26,       // texture contents, identified by their content hash
    BindTexture = 0x27,   // texture of one stage (by content hash, 0: none)
    RenderTarget = 0x28,    // v2: a render-target texture (identity), contents at first use
    ProgramTexture = 0x29,  // v2: texture (or render target) and sampler of one unit
    BeginFrame = 0x30,      // both devices
    BeginPass = 0x31,
    EndFrame = 0x32,
    Clear = 0x40,
    Draw = 0x41,
    DrawPixels = 0x42,
    CopyPixels = 0x43,
    ReadPixels = 0x44,
    ClearTarget = 0x45,   // v2: clearColor of one target
    ClearDepth = 0x46,    // v2: clearDepth
    ProgramDraw = 0x47,   // v2: a draw: program name, program bytes, vertices, indices
    TargetHash = 0x50,    // v2: after the commands, a render target's final contents hash
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

// The bytes a render target's stored values take in a trace, all levels and faces (level
// 0 first, within a level face 0 first, texels x fastest): RGBA8 4 bytes R, G, B, A per
// texel; R16F, R32F, Depth24, Depth32F one f32; RGBA16F, RGBA32F four f32 (the values as
// the target holds them, so no format conversion stands between capture and replay).
std::vector<uint8_t> renderTargetValues(const tex::Texture& target);
uint64_t renderTargetValueBytes(const tex::TextureDesc& desc);

// ---- capture ---------------------------------------------------------------------------
// Collects a trace in memory; Device::setRecorder() or ProgrammableDevice::setRecorder()
// attaches it (writing the device record, and for a Device the framebuffer contents at
// that moment), the device then feeds it at every command. finish() writes the End record
// (after a programmable device's final target hashes); save() finishes and writes the
// file. One recorder records one device.
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

    // ---- called by the ProgrammableDevice --------------------------------------------
    void attach(const ProgrammableDevice& device);
    // Writes the final hash of every render target the trace used that still exists; the
    // recorder takes no more commands.
    void detach(const ProgrammableDevice& device);
    void clearColor(const ProgrammableDevice& device, int target, const glm::vec4& value);
    void clearDepth(const ProgrammableDevice& device, float value);
    // `program`: typeid(detail::ProgramTriple<VP, FP, V>); `units`: FP::kUnits.
    void programDraw(const ProgrammableDevice& device, std::type_index program,
                     std::span<const uint8_t> vertexProgram, std::span<const uint8_t> fragmentProgram,
                     uint32_t units, ProgramPrimitive primitive, std::span<const uint8_t> vertices,
                     uint32_t stride, std::span<const uint32_t> indices);

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

// A render target of a programmable trace, created by the player at its first use.
struct TraceRenderTarget {
    uint64_t id = 0;
    tex::TextureDesc desc;
    std::vector<uint8_t> contents;  // renderTargetValues() at first use; empty: all zero
};

// One attachment of a RenderTargets record: a level and face of a render target.
struct TraceTargetBinding {
    uint64_t id = 0;  // 0: none
    int level = 0, face = 0;
    friend bool operator==(const TraceTargetBinding&, const TraceTargetBinding&) = default;
};

struct TraceProgramDraw {
    const RegisteredProgram* program = nullptr;  // found by name in the registry
    ProgramPrimitive primitive = ProgramPrimitive::TriangleList;
    std::vector<uint8_t> vertexProgram, fragmentProgram;  // the objects' bytes
    std::vector<uint8_t> vertices;  // vertexCount · program->vertexBytes bytes
    uint32_t vertexCount = 0;
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
    // ---- version 2, the programmable device ----
    ProgramState programState;
    std::vector<TraceTargetBinding> colorTargets;  // RenderTargets
    TraceTargetBinding depthTarget;                 // RenderTargets (id 0: none)
    bool scissorOn = false;                         // ProgramScissor (rect: the rectangle)
    glm::vec4 clearValue{0.0f};                     // ClearTarget (unit: the target)
    TraceProgramDraw programDraw;                   // ProgramDraw (indices: its indices)
    // ProgramTexture: unit, textureId (a Texture or RenderTarget id, 0: none), sampler.
    // ClearDepth: depthValue.
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
    // ---- version 2, the programmable device ----
    bool programmable = false;  // the first record is ProgrammableDevice
    std::map<uint64_t, TraceRenderTarget> renderTargets;
    std::map<uint64_t, uint64_t> targetHashes;  // id → FNV-1a 64 of its final renderTargetValues()
    // The trace's image: colour target 0 of the last RenderTargets record that binds one
    // (id 0: none). For a programmable trace, width and height are its size.
    TraceTargetBinding image;
    int passCount() const;
};

// Parses and checks the framing, value ranges and references of every record; does not
// draw. A programmable trace's programs must be registered (program_registry.h) before it
// is read: each draw's program is found by name and its recorded sizes checked against
// the registered types. Throws TraceError.
Trace readTrace(std::span<const uint8_t> bytes);
Trace readTraceFile(const std::filesystem::path& file);

// ---- replay ----------------------------------------------------------------------------
struct ReplayOptions {
    Path path = Path::Fast;
    int threads = 0;
    int stopAfterPass = -1;  // >= 0: stop when pass K (counted from 0 over the trace) ends
    // > 0: replay with this many subpixel bits instead of the profile's (a fixed-function
    // trace only). Not an emulation of any machine: `retroglass conform` replays with a
    // peer's precision to show which differences the profile's snapping explains.
    int subpixelBits = 0;
    // Called for every rasterized 2×2 quad of a fixed-function trace
    // (Device::setFragmentObserver): which pixels a documented choice decides.
    std::function<void(const tex::FragmentQuad&, uint8_t passed)> fragmentObserver = nullptr;
    // false: ReplayResult::hash stays empty. `retroglass bench` times the commands against
    // llvmpipe, whose side computes no hash (the SHA-256 of a 640×480 frame was 3 % of a
    // replay of hybrid's passes).
    bool hash = true;
};

struct ReplayResult {
    // The framebuffer; for a programmable trace its image (Trace::image) as RGBA8 (float
    // targets through tex::floatToRgba8), empty when there is none.
    Framebuffer framebuffer;
    // What `retroglass replay` prints: SHA-256 of the framebuffer's RGBA8 bytes, and for a
    // programmable trace of the image's stored values (renderTargetValues() of its bound
    // level and face: the same bytes for an RGBA8 image).
    std::string hash;
    int passes = 0;             // passes begun
    int readBacks = 0;          // ReadPixels commands replayed
    int readBackMismatches = 0; // of which returned other bytes than at capture
    int targetChecks = 0;       // render targets with a TargetHash record
    int targetMismatches = 0;   // of which ended with other contents than at capture
};

// Plays the trace on a fresh device of the trace's profile (Device or
// ProgrammableDevice). Throws TraceError for --pass past the last pass, and whatever the
// device throws for state it refuses. `recorder`, when given, is attached to the
// replaying device from the start: a trace of the replay, the same bytes as the trace
// replayed (tests/trace checks it).
ReplayResult replayTrace(const Trace& trace, const ReplayOptions& options = {},
                         std::shared_ptr<TraceRecorder> recorder = nullptr);

}  // namespace rg::raster
