// The device: state, frames and passes, and the draw call that runs the stages of
// pipeline.h on the reference path or the fast path.
#include "rasterizer/device.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "device_impl.h"
#include "pipeline.h"
#include "raster_tiles.h"
#include "rasterizer/trace.h"

#include "core/tsan_annotations.h"

namespace rg::raster {

using namespace detail;

// ---- state validation ----------------------------------------------------------------
namespace {

template <class E>
void checkEnum(E value, E last, const char* name) {
    if (static_cast<uint32_t>(value) > static_cast<uint32_t>(last))
        throw InvalidState(std::string(name) + " = " + std::to_string(static_cast<int>(value)) +
                           " is out of range");
}

// Triangles per chunk on the fast path: one task's setup, one run of a tile's bins.
constexpr uint32_t kChunk = 1024;

// The highest index of each run of 3·kChunk indices (a list's chunk of triangles), for the
// vertex interleave of execute(), and of all of them in `maxIndex`. One maximum over the
// indices first: that loop vectorizes, one that may throw at each index does not (3% of
// a 40,000-triangle mesh's draw, measured); only a draw with a bad index searches for the
// first one, which the message names.
std::vector<uint32_t> chunkMaxima(std::span<const uint32_t> indices, uint32_t& maxIndex) {
    std::vector<uint32_t> chunkMax;
    chunkMax.reserve((indices.size() + 3 * kChunk - 1) / (3 * kChunk));
    maxIndex = 0;
    for (size_t b = 0; b < indices.size(); b += 3 * kChunk) {
        const size_t e = std::min(indices.size(), b + 3 * kChunk);
        uint32_t m = 0;
        for (size_t k = b; k < e; ++k) m = std::max(m, indices[k]);
        chunkMax.push_back(m);
        maxIndex = std::max(maxIndex, m);
    }
    return chunkMax;
}

// The highest vertex number triangles [begin, end) of a draw use (begin < end).
uint32_t lastVertexUsed(Primitive primitive, uint32_t begin, uint32_t end,
                        std::span<const uint32_t> indices) {
    // Positions in the vertex (or index) stream: lists 3i..3i+2, strips i..i+2, fans
    // i+1..i+2 and 0.
    const uint32_t first = primitive == Primitive::TriangleList ? 3 * begin : begin;
    const uint32_t last = primitive == Primitive::TriangleList ? 3 * end - 1 : end + 1;
    if (indices.empty()) return last;
    uint32_t hi = primitive == Primitive::TriangleFan ? indices[0] : 0;
    for (uint32_t k = first; k <= last; ++k) hi = std::max(hi, indices[k]);
    return hi;
}

}  // namespace

void Device::Impl::validateState() const {
    const PipelineState& s = state;
    checkEnum(s.cull, CullMode::CCW, "cull mode");
    checkEnum(s.shade, ShadeMode::Gouraud, "shade mode");
    checkEnum(s.depthFunc, CompareFunc::Always, "depth function");
    checkEnum(s.alphaFunc, CompareFunc::Always, "alpha function");
    checkEnum(s.srcBlend, BlendFactor::BothInvSrcAlpha, "source blend factor");
    checkEnum(s.dstBlend, BlendFactor::BothInvSrcAlpha, "destination blend factor");
    checkEnum(s.blendOp, BlendOp::Max, "blend operation");
    if (s.colorWriteMask > kWriteRGBA)
        throw InvalidState("colour write mask " + std::to_string(s.colorWriteMask) +
                           " has bits beyond RGBA");
    if (s.blend) {
        // D3D7: BOTHSRCALPHA and BOTHINVSRCALPHA are source blend modes only.
        if (s.dstBlend == BlendFactor::BothSrcAlpha || s.dstBlend == BlendFactor::BothInvSrcAlpha)
            throw InvalidState("destination blend factor BOTHSRCALPHA/BOTHINVSRCALPHA is only "
                               "valid as a source blend factor");
        if (s.blendOp == BlendOp::Subtract || s.blendOp == BlendOp::RevSubtract)
            profile.require(Feature::BlendSubtract, "blend operation subtract/revsubtract");
        if (s.blendOp == BlendOp::Min || s.blendOp == BlendOp::Max)
            profile.require(Feature::BlendMinMax, "blend operation min/max");
    }
}

// ---- a mesh in bands of rows ---------------------------------------------------------
// The multi-thread path for meshes of compact vertices (compactVertices): the clip rect
// cut into one horizontal band per thread, with as many of the mesh's vertices in each
// (rows in steps of kBandStrip, even so that no 2×2 quad straddles two bands), and each
// band's triangles set up and rasterized by one task as the one-thread path does a whole
// draw (RowBand, pipeline.h). A pixel's triangles all come from its one band, in
// submission order, whatever the split: the split moves work between threads and never a
// byte. Against the tile path this saves its eleven fork/joins per 40,000 triangles and
// the 256-byte set-up triangles that cross cores from the thread that set them up to the
// one that owns their tile. Measured on the 2-core VM, bench/bench_pipeline.cpp's
// 40,000-triangle mesh of 164-byte Vertex records (clear and draw, tenth percentile of
// 1,000 frames): 1.0–1.08 ms on two threads in bands, 1.29–1.34 ms on the tile path,
// 1.65–1.76 ms on one thread.
// Balancing by vertices suits meshes, whose cost follows their triangles; a draw of
// large triangles with few vertices shares out less evenly (at worst one thread's time),
// which is why only draws of at least kBandMinTriangles come here.
namespace {
constexpr int kBandStrip = 8;
}  // namespace

void Device::Impl::drawInBands(const DrawContext& dc, Primitive primitive,
                               const VertexSource& vertices,
                               std::span<const uint32_t> indices, FastVertex* fastVertices,
                               const glm::mat4& worldViewProj, const glm::mat4& worldView,
                               const glm::mat3& normalMatrix, uint32_t triangles,
                               uint32_t chunk, GeometryCounters& gc, RasterCounters& rc) {
    const int s = dc.subpixelBits;
    const int strips = (fb.height() + kBandStrip - 1) / kBandStrip;
    // Unclipped vertices in the clip rows, per strip of rows.
    std::vector<uint32_t> perStrip(size_t(strips), 0);
    const int bands = arena->max_concurrency();
    std::vector<GeometryCounters> bandGeometry(static_cast<size_t>(bands));
    std::vector<RasterCounters> bandRaster(static_cast<size_t>(bands));
    if (scratchChunks.size() < size_t(bands)) scratchChunks.resize(size_t(bands));
    std::vector<int> bandY(size_t(bands) + 1);  // band b: rows [bandY[b], bandY[b + 1])
    if (scratchRowSpans.size() < vertices.size()) scratchRowSpans.resize(vertices.size());
    uint32_t* const rowSpans = scratchRowSpans.data();

    [[maybe_unused]] int forkJoin = 0;  // the address TSan's fork/join edges name
    RG_TSAN_RELEASE(&forkJoin);
    arena->execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, vertices.size(), 2048),
            [&](const tbb::blocked_range<size_t>& r) {
                RG_TSAN_ACQUIRE(&forkJoin);
                processVerticesCompact(dc, worldViewProj, worldView, normalMatrix, vertices,
                                       r.begin(), r.end(), fastVertices);
                // The block's vertices by strip, read back from L1, published with one
                // atomic add per strip that has any.
                std::vector<uint32_t> local(size_t(strips), 0);
                for (size_t i = r.begin(); i < r.end(); ++i) {
                    const FastVertex& v = fastVertices[i];
                    rowSpans[i] = rowSpanOf(v, s);
                    const int row = v.sy >> s;  // (sy: 0 unless unclipped)
                    if (v.unclipped && row >= dc.clipY0 && row < dc.clipY1)
                        ++local[size_t(row / kBandStrip)];
                }
                for (int k = 0; k < strips; ++k)
                    if (local[size_t(k)])
                        std::atomic_ref<uint32_t>(perStrip[size_t(k)])
                            .fetch_add(local[size_t(k)], std::memory_order_relaxed);
                RG_TSAN_RELEASE(&forkJoin);
            });
        RG_TSAN_ACQUIRE(&forkJoin);
        RG_TSAN_RELEASE(&forkJoin);

        // Band b ends at the first strip boundary with (b + 1)/bands of the vertices above
        // it (equal heights when no vertex is unclipped), inside the clip rows.
        uint64_t total = 0;
        for (int k = 0; k < strips; ++k) total += perStrip[size_t(k)];
        bandY[0] = dc.clipY0;
        bandY[size_t(bands)] = dc.clipY1;
        uint64_t above = 0;
        int strip = 0;
        for (int b = 1; b < bands; ++b) {
            int y;
            if (total == 0) {
                y = (dc.clipY0 + int(int64_t(dc.clipY1 - dc.clipY0) * b / bands)) & ~1;
            } else {
                const uint64_t want = total * uint64_t(b) / uint64_t(bands);
                while (strip < strips && above < want) above += perStrip[size_t(strip++)];
                y = strip * kBandStrip;
            }
            bandY[size_t(b)] = std::clamp(y, bandY[size_t(b) - 1], dc.clipY1);
        }

        tbb::parallel_for(
            tbb::blocked_range<int>(0, bands, 1),
            [&](const tbb::blocked_range<int>& r) {
                RG_TSAN_ACQUIRE(&forkJoin);
                for (int b = r.begin(); b < r.end(); ++b) {
                    if (bandY[size_t(b)] == bandY[size_t(b) + 1]) continue;
                    DrawContext bandDc = dc;
                    bandDc.clipY0 = bandY[size_t(b)];
                    bandDc.clipY1 = bandY[size_t(b) + 1];
                    const RowBand band{&dc, rowSpans};
                    TriangleChunk& ch = scratchChunks[size_t(b)];
                    // Counted locally, published once: the bands' counters share a line.
                    GeometryCounters g;
                    RasterCounters rcBand;
                    // A band keeps about 1/bands of the triangles it reads.
                    const uint32_t step = chunk * uint32_t(bands);
                    for (uint32_t t = 0; t < triangles; t += step) {
                        ch.tris.clear();
                        ch.texPlanes.clear();
                        setupTrianglesCompact(bandDc, primitive, t,
                                              std::min(triangles, t + step), indices,
                                              vertices, fastVertices, worldViewProj,
                                              worldView, normalMatrix, ch.tris, ch.texPlanes,
                                              g, false, &band);
                        rasterizeChunk(bandDc, ch, rcBand);
                    }
                    bandGeometry[size_t(b)] = g;
                    bandRaster[size_t(b)] = rcBand;
                }
                RG_TSAN_RELEASE(&forkJoin);
            },
            tbb::simple_partitioner());
    });
    RG_TSAN_ACQUIRE(&forkJoin);
    for (int b = 0; b < bands; ++b) {
        gc.add(bandGeometry[size_t(b)]);
        rc.add(bandRaster[size_t(b)]);
    }
}

// ---- draw ----------------------------------------------------------------------------
void Device::Impl::draw(Primitive primitive, VertexSpace space, VertexSource source,
                        std::span<const uint32_t> indices) {
    checkEnum(primitive, Primitive::TriangleFan, "primitive type");
    checkEnum(space, VertexSpace::Pretransformed, "vertex space");
    validateState();
    textureUnits.validate(profile);
    uint32_t maxIndex = 0;
    const std::vector<uint32_t> chunkMaxIndex = chunkMaxima(indices, maxIndex);
    if (!indices.empty() && maxIndex >= source.size())
        for (uint32_t i : indices)
            if (i >= source.size())
                throw InvalidState("index " + std::to_string(i) + " is past the " +
                                   std::to_string(source.size()) + " vertices of the draw");
    ++counters.drawCalls;
    if (passOpen) ++passes.back().drawCalls;

    DrawContext dc = makeDrawContext(state, fb, textureUnits, options.path, space, viewport,
                                     scissor, profile.subpixelBits);
    if (fragmentObserver) dc.fragmentObserver = &fragmentObserver;
    const glm::mat4 worldView = view * world;
    const glm::mat4 worldViewProj = projection * worldView;
    const glm::mat3 normalMatrix = glm::transpose(glm::inverse(glm::mat3(worldView)));
    if (!batching) {
        execute(dc, primitive, source, indices, chunkMaxIndex, worldViewProj, worldView,
                normalMatrix);
        return;
    }

    // Recorded: the context with its own copy of the texture units (the caller may rebind
    // before endBatch), the vertices and indices copied into the batch's arrays.
    BatchedDraw d;
    d.primitive = primitive;
    d.units = std::make_unique<tex::TextureUnits>(textureUnits);
    d.dc = dc;
    d.dc.tu = d.units.get();
    d.worldViewProj = worldViewProj;
    d.worldView = worldView;
    d.normalMatrix = normalMatrix;
    d.compact = options.path == Path::Fast && !dc.fragmentObserver && compactVertices(dc);
    if (!source.full.empty()) {
        d.fullBegin = batch.full.size();
        d.fullCount = source.full.size();
        batch.full.insert(batch.full.end(), source.full.begin(), source.full.end());
    } else if (d.compact) {
        d.xyzBegin = batch.xyz.size();
        d.xyzCount = source.xyzDiffuse.size();
        batch.xyz.insert(batch.xyz.end(), source.xyzDiffuse.begin(), source.xyzDiffuse.end());
    } else {  // execute() would make Vertex records of them: made here once
        d.fullBegin = batch.full.size();
        d.fullCount = source.xyzDiffuse.size();
        for (const VertexXyzDiffuse& v : source.xyzDiffuse) batch.full.push_back(toVertex(v));
    }
    d.indexBegin = batch.indices.size();
    d.indexCount = indices.size();
    batch.indices.insert(batch.indices.end(), indices.begin(), indices.end());
    d.triangles =
        triangleCount(primitive, uint32_t(indices.empty() ? source.size() : indices.size()));
    batch.draws.push_back(std::move(d));
}

void Device::Impl::execute(const DrawContext& dc, Primitive primitive, VertexSource source,
                           std::span<const uint32_t> indices,
                           std::span<const uint32_t> chunkMaxIndex,
                           const glm::mat4& worldViewProj, const glm::mat4& worldView,
                           const glm::mat3& normalMatrix) {
    // Meshes of at least this many triangles go through drawInBands on several threads;
    // smaller draws of large triangles (fills) share their pixels out better in tiles.
    constexpr uint32_t kBandMinTriangles = 4 * kChunk;
    const uint32_t vertexCount = uint32_t(indices.empty() ? source.size() : indices.size());
    const uint32_t triangles = triangleCount(primitive, vertexCount);
    auto vertexOf = [&](uint32_t k) { return indices.empty() ? k : indices[k]; };

    // Vertex stage: every submitted vertex once, independent of the others.
    std::vector<ProcessedVertex>& processed = scratchVertices;
    // The observer hook lives in the reference raster loop, which gets the reference setup.
    const bool fastPath = options.path == Path::Fast && !dc.fragmentObserver;
    // Draws without texture coordinates keep 32-byte FastVertex records instead
    // (pipeline.h): the setup of small triangles waited on vertex bytes. Kept between
    // draws, like scratchVertices, so that a large mesh does not page-fault fresh memory
    // on every draw.
    const bool compact = fastPath && compactVertices(dc);
    // D3DFVF_XYZ | D3DFVF_DIFFUSE vertices: the compact records are made from them as they
    // are; every other path reads Vertex records, toVertex of each.
    if (!compact && source.full.empty() && !source.xyzDiffuse.empty()) {
        scratchInput.resize(source.xyzDiffuse.size());
        std::transform(source.xyzDiffuse.begin(), source.xyzDiffuse.end(), scratchInput.begin(),
                       [](const VertexXyzDiffuse& v) { return toVertex(v); });
        source = VertexSource{scratchInput, {}};
    }
    const std::span<const Vertex> vertices = source.full;  // (every path but the compact one)
    if (compact && scratchFastVertices.size() < source.size())
        scratchFastVertices.resize(source.size());
    FastVertex* const fastVertices = scratchFastVertices.data();
    if (!compact && processed.size() < source.size()) processed.resize(source.size());
    auto processRange = [&](size_t b, size_t e) {
        if (compact) {
            processVerticesCompact(dc, worldViewProj, worldView, normalMatrix, source, b, e,
                                   fastVertices);
            return;
        }
        if (fastPath) {
            processVerticesFast(dc, worldViewProj, worldView, normalMatrix, vertices, b, e,
                                processed.data());
            return;
        }
        for (size_t i = b; i < e; ++i)
            processed[i] = processVertex(dc, worldViewProj, worldView, normalMatrix, vertices[i]);
    };
    auto processedAt = [&](uint32_t i) -> const ProcessedVertex& { return processed[i]; };
    // Set by the one-thread path while a chunk's records were transformed just before it.
    bool recordsInCache = false;
    auto setupRange = [&](uint32_t b, uint32_t e, std::vector<SetupTriangle>& out,
                          std::vector<Plane>& texPool, GeometryCounters& gc, auto&& fetch) {
        if (compact) {
            setupTrianglesCompact(dc, primitive, b, e, indices, source, fastVertices,
                                  worldViewProj, worldView, normalMatrix, out, texPool, gc,
                                  !recordsInCache);
            return;
        }
        if (fastPath) {
            setupTrianglesFast(dc, primitive, b, e, indices, vertices, processed.data(), out,
                               texPool, gc);
            return;
        }
        out.reserve(out.size() + (e - b));
        for (uint32_t i = b; i < e; ++i) {
            auto tv = triangleVertices(primitive, i);
            uint32_t a = vertexOf(tv[0]), bb = vertexOf(tv[1]), c = vertexOf(tv[2]);
            // The provoking vertex's bytes matter only for flat shading.
            const Rgba8 flatD = dc.gouraud ? Rgba8{} : vertices[a].diffuse;
            const Rgba8 flatS = dc.gouraud ? Rgba8{} : vertices[a].specular;
            const ProcessedVertex& pa = fetch(a);
            const ProcessedVertex& pb = fetch(bb);
            const ProcessedVertex& pc = fetch(c);
            clipAndSetup(dc, pa, pb, pc, flatD, flatS, out, texPool, gc);
        }
    };

    GeometryCounters gc;
    RasterCounters rc;
    if (!fastPath) {
        processRange(0, source.size());
        std::vector<SetupTriangle> tris;
        std::vector<Plane> texPool;
        setupRange(0, triangles, tris, texPool, gc, processedAt);
        rasterizeReference(dc, tris, texPool, rc);
    } else {
        // Fast path: vertices and triangle chunks in parallel (each writes only its own
        // output), then tiles in parallel; a tile walks the chunks and their triangles in
        // submission order, so each pixel sees its triangles in the reference's order.
        const int tilesX = (fb.width() + kTileSize - 1) / kTileSize;
        const int tilesY = (fb.height() + kTileSize - 1) / kTileSize;
        const uint32_t chunkCount = (triangles + kChunk - 1) / kChunk;
        // Chunks per batch (see below): 8 measured best on 2 threads (4 the same, all of a
        // draw's 40 chunks 1.3 times the CPU time); at least two per thread.
        const uint32_t kBatch = std::max<uint32_t>(8, 2 * uint32_t(arena->max_concurrency()));
        const uint32_t batch = std::min(chunkCount, kBatch);
        if (scratchChunks.size() < batch) scratchChunks.resize(batch);
        std::span<TriangleChunk> chunks(scratchChunks.data(), batch);
        std::vector<RasterCounters> tileCounters(size_t(tilesX) * tilesY);
        const bool multi = arena->max_concurrency() > 1;
        if (arena->max_concurrency() == 1) {
            // One thread: set up and rasterize chunk by chunk, no binning (raster_tiles.h),
            // each chunk's vertices transformed just before it (up to the highest vertex it
            // uses), so that setup reads them from cache rather than from a whole draw's
            // vertex array written long before. Meshes whose indices
            // grow along the list (most) interleave; others transform everything at the
            // first chunk, as before.
            size_t transformed = 0;
            if (scratchChunks.empty()) scratchChunks.resize(1);
            TriangleChunk& ch = scratchChunks[0];
            for (uint32_t b = 0; b < triangles; b += kChunk) {
                const uint32_t e = std::min(triangles, b + kChunk);
                // A list's chunk uses indices [3b, 3e): its block's maximum (the last
                // block also covers the indices past the last whole triangle, all valid:
                // a few more vertices transformed early, the same bytes).
                const uint32_t last = primitive == Primitive::TriangleList && !indices.empty()
                                          ? chunkMaxIndex[b / kChunk]
                                          : lastVertexUsed(primitive, b, e, indices);
                const size_t needed = size_t(last) + 1;
                // Records just transformed for this chunk are in cache, unless the chunk's
                // indices jump far ahead (a whole draw's records at once): no prefetch
                // for the first (measured: 6% of the one-thread frame of a
                // 40,000-triangle mesh).
                recordsInCache = needed > transformed && needed - transformed <= 4 * kChunk;
                if (needed > transformed) {
                    processRange(transformed, needed);
                    transformed = needed;
                }
                ch.tris.clear();
                ch.texPlanes.clear();
                setupRange(b, e, ch.tris, ch.texPlanes, gc, processedAt);
                rasterizeChunk(dc, ch, rc);
            }
        } else if (compact && triangles >= kBandMinTriangles && dc.clipX0 < dc.clipX1 &&
                   dc.clipY0 < dc.clipY1 && triangles <= uint32_t(INT32_MAX)) {
            // (The band selection keeps a flag in bit 31 of a triangle number.)
            drawInBands(dc, primitive, source, indices, fastVertices, worldViewProj,
                        worldView, normalMatrix, triangles, kChunk, gc, rc);
        } else {
        [[maybe_unused]] int forkJoin = 0;  // the address TSan's fork/join edges name
        RG_TSAN_RELEASE(&forkJoin);
        arena->execute([&] {
            // Each batch's vertices first (up to the highest one its chunks use, those not
            // transformed for an earlier batch), in blocks, then its triangle chunks: a
            // barrier is cheaper than an atomic claim per vertex, and the blocks share out
            // evenly. Per batch rather than the whole draw's at once, as the one-thread
            // path interleaves per chunk: the records setup reads are then still in cache
            // (measured on hybrid's textured layer passes, 31,000 vertices of 200-byte
            // records: setup took 3.4 times the CPU time of the one-thread path when all
            // vertices came first). Meshes whose indices jump about transform everything
            // at the first batch, as before.
            size_t transformed = 0;
            auto transformUpTo = [&](size_t needed) {
                if (needed <= transformed) return;
                tbb::parallel_for(tbb::blocked_range<size_t>(transformed, needed, 2048),
                                  [&](const tbb::blocked_range<size_t>& r) {
                                      RG_TSAN_ACQUIRE(&forkJoin);
                                      processRange(r.begin(), r.end());
                                      RG_TSAN_RELEASE(&forkJoin);
                                  });
                RG_TSAN_ACQUIRE(&forkJoin);
                RG_TSAN_RELEASE(&forkJoin);
                transformed = needed;
            };
            // Then batches of chunks: set up and bin a batch in parallel, then
            // rasterize its tiles in parallel. The batches reuse the same chunk buffers, so
            // the SetupTriangles (256 bytes each) stay in cache between setup and
            // rasterization instead of a whole draw's going out to memory and back
            // (measured: with all chunks set up first, setup and rasterization cost 1.6
            // and 1.9 times the CPU time of the one-thread path on a 40,000-triangle mesh).
            // Tiles walk a batch's chunks in order and the batches run in order, so each
            // pixel still sees its triangles in submission order.
            for (uint32_t c0 = 0; c0 < chunkCount; c0 += batch) {
                const uint32_t n = std::min(batch, chunkCount - c0);
                {
                    const uint32_t b = c0 * kChunk, e = std::min(triangles, (c0 + n) * kChunk);
                    uint32_t last = 0;
                    if (primitive == Primitive::TriangleList && !indices.empty()) {
                        for (uint32_t c = c0; c < c0 + n; ++c)
                            last = std::max(last, chunkMaxIndex[c]);
                    } else {
                        last = lastVertexUsed(primitive, b, e, indices);
                    }
                    // (The last block's maximum also covers indices past the last whole
                    // triangle: all valid, a few vertices transformed early.)
                    transformUpTo(std::min(source.size(), size_t(last) + 1));
                }
                tbb::parallel_for(uint32_t(0), n, [&](uint32_t i) {
                    RG_TSAN_ACQUIRE(&forkJoin);
                    TriangleChunk& ch = chunks[i];
                    ch.tris.clear();
                    ch.texPlanes.clear();
                    GeometryCounters local;  // published once: chunks share cache lines
                    const uint32_t c = c0 + i;
                    setupRange(c * kChunk, std::min(triangles, (c + 1) * kChunk), ch.tris,
                               ch.texPlanes, local, processedAt);
                    ch.geometry = local;
                    binChunk(ch, tilesX, tilesY);
                    RG_TSAN_RELEASE(&forkJoin);
                });
                RG_TSAN_ACQUIRE(&forkJoin);
                RG_TSAN_RELEASE(&forkJoin);
                tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
                    RG_TSAN_ACQUIRE(&forkJoin);
                    rasterizeTile(dc, std::span<const TriangleChunk>(chunks.data(), n), tile,
                                  tilesX, tileCounters[size_t(tile)]);
                    RG_TSAN_RELEASE(&forkJoin);
                });
                RG_TSAN_ACQUIRE(&forkJoin);
                RG_TSAN_RELEASE(&forkJoin);
                for (uint32_t i = 0; i < n; ++i) gc.add(chunks[i].geometry);
            }
        });
        RG_TSAN_ACQUIRE(&forkJoin);
        }
        if (multi)
            for (const RasterCounters& t : tileCounters) rc.add(t);  // zero if in bands
    }
    addCounters(gc, rc);
}

void Device::Impl::addCounters(const GeometryCounters& gc, const RasterCounters& rc) {
    counters.trianglesSubmitted += gc.submitted;
    counters.trianglesCulled += gc.culled;
    counters.trianglesClipped += gc.clipped;
    counters.trianglesDrawn += gc.drawn;
    counters.trianglesInvalid += gc.invalid;
    counters.fragmentsGenerated += rc.generated;
    counters.fragmentsWritten += rc.written;
    counters.blendOps += rc.blendOps;
    counters.texture = textureUnits.counters();  // texel fetches and uploads this frame
}

// ---- batches ---------------------------------------------------------------------------
void Device::Impl::endBatch() {
    if (!batching) throw InvalidState("endBatch without beginBatch");
    batching = false;
    // The batch's arrays are emptied whatever happens (they keep their capacity).
    struct Emptied {
        Batch& b;
        ~Emptied() { b.clear(); }
    } emptied{batch};
    if (options.path == Path::Fast && !fragmentObserver && arena->max_concurrency() > 1 &&
        batch.draws.size() > 1) {
        runBatchInTiles();
        return;
    }
    // One thread, the reference path, an observer or a single draw: each draw as issued.
    for (const BatchedDraw& d : batch.draws) {
        const VertexSource source{std::span<const Vertex>(batch.full).subspan(d.fullBegin, d.fullCount),
                                  std::span<const VertexXyzDiffuse>(batch.xyz).subspan(d.xyzBegin, d.xyzCount)};
        const std::span<const uint32_t> indices =
            std::span<const uint32_t>(batch.indices).subspan(d.indexBegin, d.indexCount);
        uint32_t maxIndex = 0;
        const std::vector<uint32_t> chunkMaxIndex = chunkMaxima(indices, maxIndex);
        execute(d.dc, d.primitive, source, indices, chunkMaxIndex, d.worldViewProj, d.worldView,
                d.normalMatrix);
    }
}

// The batch's draws as the tile path runs one draw's batch of chunks (execute), with
// every draw in each of the three phases: all vertices, in blocks over the threads; all
// chunks set up and binned, over the threads; then each tile, over the threads, walks the
// draws in the order issued and each draw's chunks in order, with the draw's own context.
// A pixel sees its triangles in submission order: the bytes of drawing one by one.
void Device::Impl::runBatchInTiles() {
    std::vector<BatchedDraw>& draws = batch.draws;
    struct Item {
        uint32_t draw, begin;  // a block of vertices from `begin`, or chunk number `begin`
    };
    constexpr uint32_t kVertexBlock = 2048;
    std::vector<Item> vertexItems, chunkItems;
    size_t fullRecords = 0, fastRecords = 0, chunkTotal = 0;
    for (uint32_t k = 0; k < uint32_t(draws.size()); ++k) {
        BatchedDraw& d = draws[k];
        const size_t n = d.fullCount + d.xyzCount;  // (one of them is 0)
        size_t& records = d.compact ? fastRecords : fullRecords;
        d.recordBegin = records;
        records += n;
        for (size_t b = 0; b < n; b += kVertexBlock) vertexItems.push_back({k, uint32_t(b)});
        d.firstChunk = chunkTotal;
        d.chunkCount = (d.triangles + kChunk - 1) / kChunk;
        for (uint32_t c = 0; c < d.chunkCount; ++c) chunkItems.push_back({k, c});
        chunkTotal += d.chunkCount;
    }
    if (scratchVertices.size() < fullRecords) scratchVertices.resize(fullRecords);
    if (scratchFastVertices.size() < fastRecords) scratchFastVertices.resize(fastRecords);
    if (scratchChunks.size() < chunkTotal) scratchChunks.resize(chunkTotal);
    auto sourceOf = [&](const BatchedDraw& d) {
        return VertexSource{std::span<const Vertex>(batch.full).subspan(d.fullBegin, d.fullCount),
                            std::span<const VertexXyzDiffuse>(batch.xyz).subspan(d.xyzBegin, d.xyzCount)};
    };
    auto indicesOf = [&](const BatchedDraw& d) {
        return std::span<const uint32_t>(batch.indices).subspan(d.indexBegin, d.indexCount);
    };
    const int tilesX = (fb.width() + kTileSize - 1) / kTileSize;
    const int tilesY = (fb.height() + kTileSize - 1) / kTileSize;
    std::vector<RasterCounters> tileCounters(size_t(tilesX) * tilesY);

    [[maybe_unused]] int forkJoin = 0;  // the address TSan's fork/join edges name
    RG_TSAN_RELEASE(&forkJoin);
    arena->execute([&] {
        tbb::parallel_for(size_t(0), vertexItems.size(), [&](size_t i) {
            RG_TSAN_ACQUIRE(&forkJoin);
            const Item it = vertexItems[i];
            const BatchedDraw& d = draws[it.draw];
            const VertexSource source = sourceOf(d);
            const size_t e = std::min(source.size(), size_t(it.begin) + kVertexBlock);
            if (d.compact)
                processVerticesCompact(d.dc, d.worldViewProj, d.worldView, d.normalMatrix,
                                       source, it.begin, e,
                                       scratchFastVertices.data() + d.recordBegin);
            else
                processVerticesFast(d.dc, d.worldViewProj, d.worldView, d.normalMatrix,
                                    source.full, it.begin, e,
                                    scratchVertices.data() + d.recordBegin);
            RG_TSAN_RELEASE(&forkJoin);
        });
        RG_TSAN_ACQUIRE(&forkJoin);
        RG_TSAN_RELEASE(&forkJoin);
        tbb::parallel_for(size_t(0), chunkItems.size(), [&](size_t i) {
            RG_TSAN_ACQUIRE(&forkJoin);
            const Item it = chunkItems[i];
            const BatchedDraw& d = draws[it.draw];
            TriangleChunk& ch = scratchChunks[d.firstChunk + it.begin];
            ch.tris.clear();
            ch.texPlanes.clear();
            GeometryCounters local;  // published once: chunks share cache lines
            const uint32_t b = it.begin * kChunk, e = std::min(d.triangles, b + kChunk);
            if (d.compact)
                setupTrianglesCompact(d.dc, d.primitive, b, e, indicesOf(d), sourceOf(d),
                                      scratchFastVertices.data() + d.recordBegin,
                                      d.worldViewProj, d.worldView, d.normalMatrix, ch.tris,
                                      ch.texPlanes, local);
            else
                setupTrianglesFast(d.dc, d.primitive, b, e, indicesOf(d), sourceOf(d).full,
                                   scratchVertices.data() + d.recordBegin, ch.tris,
                                   ch.texPlanes, local);
            ch.geometry = local;
            binChunk(ch, tilesX, tilesY);
            RG_TSAN_RELEASE(&forkJoin);
        });
        RG_TSAN_ACQUIRE(&forkJoin);
        RG_TSAN_RELEASE(&forkJoin);
        tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
            RG_TSAN_ACQUIRE(&forkJoin);
            for (const BatchedDraw& d : draws) {
                const std::span<const TriangleChunk> chunks(scratchChunks.data() + d.firstChunk,
                                                            d.chunkCount);
                // Most of a batch's small draws miss most tiles: skip them before
                // rasterizeTile sets up its walk.
                if (std::none_of(chunks.begin(), chunks.end(), [&](const TriangleChunk& c) {
                        return c.binStart[size_t(tile)] != c.binStart[size_t(tile) + 1];
                    }))
                    continue;
                rasterizeTile(d.dc, chunks, tile, tilesX, tileCounters[size_t(tile)]);
            }
            RG_TSAN_RELEASE(&forkJoin);
        });
    });
    RG_TSAN_ACQUIRE(&forkJoin);
    GeometryCounters gc;
    RasterCounters rc;
    for (size_t c = 0; c < chunkTotal; ++c) gc.add(scratchChunks[c].geometry);
    for (const RasterCounters& t : tileCounters) rc.add(t);
    addCounters(gc, rc);
}

// ---- Device ----------------------------------------------------------------------------
Device::Device(const Profile& profile, int width, int height, DepthFormat depth,
               DeviceOptions options)
    : impl_(std::make_unique<Impl>(profile, width, height, depth, options)) {}
Device::~Device() = default;

const Profile& Device::profile() const { return impl_->profile; }
const DeviceOptions& Device::options() const { return impl_->options; }
void Device::setPath(Path path) {
    impl_->notInBatch("setPath");
    impl_->options.path = path;
}
void Device::setThreads(int threads) {
    impl_->notInBatch("setThreads");
    if (threads < 0) throw InvalidState("thread count " + std::to_string(threads) + " is negative");
    impl_->options.threads = threads;
    impl_->makeArena();
}

void Device::setState(const PipelineState& state) {
    // A boolean state is 0 or 1: the trace format has no other value (docs/trace-format.md,
    // "State"), so the device takes none (the rest is validated at draw time).
    const std::pair<uint8_t, const char*> flags[] = {
        {state.depthTest, "depthTest"}, {state.depthWrite, "depthWrite"}, {state.alphaTest, "alphaTest"},
        {state.blend, "blend"}, {state.scissorTest, "scissorTest"}, {state.specularEnable, "specularEnable"},
        {state.perspectiveColor, "perspectiveColor"}};
    for (const auto& [v, name] : flags)
        if (v > 1) throw InvalidState(std::string(name) + " = " + std::to_string(v) + " is not 0 or 1");
    impl_->state = state;
}
const PipelineState& Device::state() const { return impl_->state; }
void Device::setTransforms(const glm::mat4& world, const glm::mat4& view,
                           const glm::mat4& projection) {
    impl_->world = world;
    impl_->view = view;
    impl_->projection = projection;
}
const glm::mat4& Device::world() const { return impl_->world; }
const glm::mat4& Device::view() const { return impl_->view; }
const glm::mat4& Device::projection() const { return impl_->projection; }

void Device::setViewport(const Viewport& v) {
    const Framebuffer& fb = impl_->fb;
    if (v.width <= 0 || v.height <= 0)
        throw InvalidState("viewport size " + std::to_string(v.width) + "x" +
                           std::to_string(v.height) + " is empty");
    if (v.x < 0 || v.y < 0 || int64_t(v.x) + v.width > fb.width() ||
        int64_t(v.y) + v.height > fb.height())
        throw InvalidState("viewport (" + std::to_string(v.x) + ", " + std::to_string(v.y) + ") " +
                           std::to_string(v.width) + "x" + std::to_string(v.height) +
                           " lies outside the " + std::to_string(fb.width()) + "x" +
                           std::to_string(fb.height()) + " render target");
    if (!(v.minZ >= 0.0f && v.minZ <= 1.0f && v.maxZ >= 0.0f && v.maxZ <= 1.0f))
        throw InvalidState("viewport depth range [" + std::to_string(v.minZ) + ", " +
                           std::to_string(v.maxZ) + "] is not inside [0, 1]");
    impl_->viewport = v;
}

void Device::setScissor(const Rect& r) {
    if (r.width < 0 || r.height < 0)
        throw InvalidState("scissor size " + std::to_string(r.width) + "x" +
                           std::to_string(r.height) + " is negative");
    impl_->scissor = r;
}

const Viewport& Device::viewport() const { return impl_->viewport; }
const Rect& Device::scissor() const { return impl_->scissor; }

tex::TextureUnits& Device::textureUnits() { return impl_->textureUnits; }
const tex::TextureUnits& Device::textureUnits() const { return impl_->textureUnits; }

void Device::beginFrame() {
    impl_->notInBatch("beginFrame");
    if (impl_->recorder) impl_->recorder->beginFrame();
    impl_->endPass();
    impl_->counters = Counters{};
    impl_->textureUnits.resetCounters();
    impl_->passes.clear();
}

void Device::beginPass(std::string label) {
    impl_->notInBatch("beginPass");
    if (impl_->recorder) impl_->recorder->beginPass(label);
    impl_->endPass();
    impl_->passes.push_back(PassRecord{std::move(label), 0});
    impl_->passOpen = true;
    ++impl_->counters.passes;
}

const std::vector<PassRecord>& Device::passes() const { return impl_->passes; }
void Device::setFragmentObserver(FragmentObserver observer) {
    impl_->notInBatch("setFragmentObserver");
    impl_->fragmentObserver = std::move(observer);
}

void Device::setPassObserver(std::function<void(const PassRecord&, const Framebuffer&)> observer) {
    impl_->notInBatch("setPassObserver");
    impl_->observer = std::move(observer);
}
void Device::endFrame() {
    impl_->notInBatch("endFrame");
    if (impl_->recorder) impl_->recorder->endFrame();
    impl_->endPass();
}

void Device::setRecorder(std::shared_ptr<TraceRecorder> recorder) {
    impl_->notInBatch("setRecorder");
    if (recorder) recorder->attach(*this);
    impl_->recorder = std::move(recorder);
}

void Device::draw(Primitive primitive, VertexSpace space, std::span<const Vertex> vertices,
                  std::span<const uint32_t> indices) {
    if (impl_->recorder) impl_->recorder->draw(*this, primitive, space, vertices, indices);
    impl_->draw(primitive, space, VertexSource{vertices, {}}, indices);
}

void Device::draw(Primitive primitive, std::span<const VertexXyzDiffuse> vertices,
                  std::span<const uint32_t> indices) {
    if (impl_->recorder) {  // a trace holds Vertex records: the draw this one stands for
        std::vector<Vertex> full(vertices.size());
        std::transform(vertices.begin(), vertices.end(), full.begin(),
                       [](const VertexXyzDiffuse& v) { return toVertex(v); });
        impl_->recorder->draw(*this, primitive, VertexSpace::Untransformed, full, indices);
    }
    impl_->draw(primitive, VertexSpace::Untransformed, VertexSource{{}, vertices}, indices);
}

void Device::beginBatch() {
    impl_->notInBatch("beginBatch");
    impl_->batching = true;
}
void Device::endBatch() { impl_->endBatch(); }
bool Device::batching() const { return impl_->batching; }

Framebuffer& Device::framebuffer() { return impl_->fb; }
const Framebuffer& Device::framebuffer() const { return impl_->fb; }
const Counters& Device::counters() const { return impl_->counters; }

}  // namespace rg::raster
