// Internal to rasterizer/: the device's state, shared by device.cpp (draws, frames) and
// pixel_transfer.cpp (clears, pixel transfers, read-back).
#pragma once

#include <algorithm>
#include <memory>
#include <string>

#include <tbb/task_arena.h>

#include "core/error.h"
#include "pipeline.h"
#include "raster_tiles.h"
#include "rasterizer/device.h"

namespace rg::raster {

struct Device::Impl {
    const Profile& profile;
    DeviceOptions options;
    Framebuffer fb;
    PipelineState state;
    glm::mat4 world{1.0f}, view{1.0f}, projection{1.0f};
    Viewport viewport;
    Rect scissor;
    tex::TextureUnits textureUnits;
    Counters counters;
    std::vector<PassRecord> passes;
    bool passOpen = false;
    std::function<void(const PassRecord&, const Framebuffer&)> observer;
    Device::FragmentObserver fragmentObserver;
    std::shared_ptr<TraceRecorder> recorder;  // capture: fed at every command when set
    std::unique_ptr<tbb::task_arena> arena;
    // Per-draw scratch kept between draws so that large frames do not page-fault fresh
    // memory on every call; contents never carry over.
    std::vector<detail::ProcessedVertex> scratchVertices;
    std::vector<detail::FastVertex> scratchFastVertices;  // draws without texture coordinates
    std::vector<detail::TriangleChunk> scratchChunks;
    std::vector<uint32_t> scratchRowSpans;  // drawInBands: rowSpanOf each vertex
    std::vector<Vertex> scratchInput;       // toVertex of a VertexXyzDiffuse draw's vertices

    // A draw recorded between beginBatch and endBatch: its context as draw() made it, with
    // the texture units pointing at the batch's copy, and where its copied vertices and
    // indices lie in the batch's arrays.
    struct BatchedDraw {
        Primitive primitive = Primitive::TriangleList;
        detail::DrawContext dc;
        std::unique_ptr<tex::TextureUnits> units;  // dc.tu
        glm::mat4 worldViewProj{1.0f}, worldView{1.0f};
        glm::mat3 normalMatrix{1.0f};
        size_t fullBegin = 0, fullCount = 0;  // in Batch::full
        size_t xyzBegin = 0, xyzCount = 0;    // in Batch::xyz (compact draws only)
        size_t indexBegin = 0, indexCount = 0;
        uint32_t triangles = 0;
        // endBatch's multi-thread run: the draw's vertex records (from scratchVertices or
        // scratchFastVertices) and its chunks (from scratchChunks).
        size_t recordBegin = 0, firstChunk = 0;
        uint32_t chunkCount = 0;
        bool compact = false;
    };
    struct Batch {
        std::vector<BatchedDraw> draws;
        std::vector<Vertex> full;
        std::vector<VertexXyzDiffuse> xyz;
        std::vector<uint32_t> indices;
        void clear() {
            draws.clear();
            full.clear();
            xyz.clear();
            indices.clear();
        }
    };
    bool batching = false;
    Batch batch;

    Impl(const Profile& p, int w, int h, DepthFormat d, DeviceOptions o)
        : profile(p), options(o), fb(checkedFramebuffer(p, w, h, d)) {
        viewport = Viewport{0, 0, w, h, 0.0f, 1.0f};
        scissor = Rect{0, 0, w, h};
        makeArena();
    }

    static Framebuffer checkedFramebuffer(const Profile& p, int w, int h, DepthFormat d) {
        if (w <= 0 || h <= 0 || w > p.maxViewport || h > p.maxViewport)
            throw InvalidState("render target " + std::to_string(w) + "x" + std::to_string(h) +
                               " is empty or exceeds the maximum viewport " +
                               std::to_string(p.maxViewport) + " of profile '" +
                               std::string(p.name) + "'");
        switch (d) {
            case DepthFormat::None: break;
            case DepthFormat::D16: p.require(Feature::Depth16, "D16 depth buffer"); break;
            case DepthFormat::D24: p.require(Feature::Depth24, "D24 depth buffer"); break;
            default: throw InvalidState("depth format " + std::to_string(int(d)) + " out of range");
        }
        return Framebuffer(w, h, d);
    }

    void makeArena() {
        int n = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
        arena = std::make_unique<tbb::task_arena>(std::max(1, n));
    }

    void endPass() {
        if (!passOpen) return;
        passOpen = false;
        if (observer) observer(passes.back(), fb);
    }

    // An error for what a batch cannot defer (Device::beginBatch).
    void notInBatch(const char* what) const {
        if (batching)
            throw InvalidState(std::string(what) + " inside a draw batch (endBatch first)");
    }

    void validateState() const;
    // Checks and counts a draw, then runs it (execute) or, inside a batch, records it.
    void draw(Primitive primitive, VertexSpace space, detail::VertexSource source,
              std::span<const uint32_t> indices);
    // Runs a checked draw on the reference path, one thread or the tile/band paths.
    // `chunkMaxIndex`: the highest index of each run of 3·kChunk indices (chunkMaxima).
    void execute(const detail::DrawContext& dc, Primitive primitive, detail::VertexSource source,
                 std::span<const uint32_t> indices, std::span<const uint32_t> chunkMaxIndex,
                 const glm::mat4& worldViewProj, const glm::mat4& worldView,
                 const glm::mat3& normalMatrix);
    void endBatch();
    // endBatch's run of the recorded draws on the fast path with several threads.
    void runBatchInTiles();
    void addCounters(const detail::GeometryCounters& gc, const detail::RasterCounters& rc);
    // draw()'s multi-thread path for meshes of FastVertex records (device.cpp).
    void drawInBands(const detail::DrawContext& dc, Primitive primitive,
                     const detail::VertexSource& vertices, std::span<const uint32_t> indices,
                     detail::FastVertex* fastVertices, const glm::mat4& worldViewProj,
                     const glm::mat4& worldView, const glm::mat3& normalMatrix,
                     uint32_t triangles, uint32_t chunk, detail::GeometryCounters& gc,
                     detail::RasterCounters& rc);
};

}  // namespace rg::raster
