// Internal to rasterizer/: the recorder's state, shared by the fixed-function half
// (rasterizer/trace_recorder.cpp) and the programmable half
// (rasterizer/trace_recorder_program.cpp). It holds what the trace has said so far,
// which is the replaying device's state at that point of the replay.
#pragma once

#include <array>
#include <cstring>
#include <memory>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/error.h"
#include "rasterizer/program.h"
#include "rasterizer/trace.h"
#include "texunit/texture_units.h"

namespace rg::raster {

struct TraceRecorder::Impl {
    std::vector<uint8_t> bytes;
    bool attached = false, finished = false;
    bool programmable = false;  // attached to a ProgrammableDevice (version 2)

    // ---- the fixed-function device: what the trace has said so far ----
    bool known = false;
    PipelineState state;
    std::array<glm::mat4, 3> transforms;
    Viewport viewport;
    Rect scissor;
    std::array<tex::StageState, tex::kMaxStages> stages;
    std::array<tex::SamplerState, tex::kMaxStages> samplers;
    std::array<uint64_t, tex::kMaxStages> bound{};
    std::array<std::shared_ptr<tex::ColorTable>, tex::kMaxStages> tables;
    std::array<tex::TexGenState, tex::kMaxTexCoordSets> texGens;
    Rgba8 tfactor;
    tex::PixelTextureState pixelTexture;
    std::vector<uint64_t> written;  // texture ids already in the trace (sorted)

    // ---- the programmable device ----
    struct RenderTargetSeen {
        // Identity, not contents: a target is written in place between commands, so the
        // trace names it by an id given at its first use. The weak pointer tells a target
        // destroyed since (whose address a new texture may take) from a live one.
        std::weak_ptr<const tex::Texture> texture;
        const tex::Texture* address = nullptr;
        uint64_t id = 0;
    };
    struct ProgramSaid {
        bool known = false;       // anything said yet (the first command says everything)
        bool stateKnown = false;  // ProgramState is said before the first draw
        ProgramState state;
        std::vector<TraceTargetBinding> colors;
        TraceTargetBinding depth;
        Viewport viewport;
        bool scissorOn = false;
        Rect scissor;
        std::array<bool, kMaxProgramUnits> unitKnown{};
        std::array<uint64_t, kMaxProgramUnits> unitTexture{};
        std::array<tex::SamplerState, kMaxProgramUnits> unitSampler{};
        std::vector<RenderTargetSeen> targets;  // in id order
        // Render-target ids have the top bit set and texture ids (content hashes) clear,
        // so the two kinds never collide.
        uint64_t nextTargetId = (uint64_t{1} << 63) | 1u;
        bool detached = false;
    } program;

    // Starts a record; returns the offset of its length field.
    size_t begin(TraceOp op) {
        if (!attached) throw Error("trace recorder: not attached to a device");
        if (finished) throw Error("trace recorder: the trace is already finished");
        bytes.push_back(uint8_t(op));
        size_t at = bytes.size();
        bytes.resize(at + 4);
        return at;
    }
    void end(size_t at) {
        const uint32_t len = uint32_t(bytes.size() - at - 4);
        std::memcpy(bytes.data() + at, &len, 4);
    }

    // A Texture record for `id` unless the trace has one.
    void writeTexture(const tex::Texture& t, uint64_t id);
    // Writes every piece of the Device's state a command reads that differs from the
    // trace's. `readStages`: bit i set when stage i's texture can be read by the command.
    void sync(const Device& dev, uint32_t readStages);

    // The programmable device's state a command reads: targets, viewport, scissor, and
    // for a draw (`draw`) the program state and the units in `units`.
    void syncProgram(const ProgrammableDevice& dev, bool draw, uint32_t units);
    // The id of a render target, writing its RenderTarget record at its first use.
    uint64_t targetId(const std::shared_ptr<const tex::Texture>& target);
    // The TargetHash records of every render target still alive.
    void writeTargetHashes();

    // The stages whose texture a draw can read: those before the first disabled colour
    // op (Direct3D 7's cascade rule, TextureUnits::activeStages()).
    static uint32_t drawStages(const tex::TextureUnits& tu) {
        uint32_t m = 0;
        for (int i = 0; i < tex::kMaxStages; ++i) {
            if (tu.stage(i).colorOp == tex::TextureOp::Disable) break;
            m |= 1u << i;
        }
        return m;
    }
    static uint32_t transferStages(const tex::TextureUnits& tu) {
        const auto& pt = tu.pixelTexture();
        return pt.enabled && pt.stage < tex::kMaxStages ? 1u << pt.stage : 0u;
    }
};

}  // namespace rg::raster
