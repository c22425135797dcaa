// The fast path's screen tiles (internal to rasterizer/; see raster_tiles.cpp).
#pragma once

#include <span>
#include <vector>

#include "pipeline.h"

namespace rg::raster::detail {

// 64×64 pixel tiles: even-aligned so that no 2×2 quad straddles two tiles, large enough
// that a 640×480 frame has 80 tiles to spread over the threads.
constexpr int kTileShift = 6;
constexpr int kTileSize = 1 << kTileShift;

// A consecutive run of the draw's triangles, set up by one task and binned into tiles.
struct TriangleChunk {
    std::vector<SetupTriangle> tris;
    std::vector<Plane> texPlanes;    // texture-coordinate planes of `tris`
    std::vector<uint32_t> binStart;  // per tile: first entry in binItems (size tiles + 1)
    std::vector<uint32_t> binItems;  // triangle numbers within `tris`, in order
    GeometryCounters geometry;
};

void binChunk(TriangleChunk& chunk, int tilesX, int tilesY);
// Rasterizes every chunk's triangles that touch tile `tile`, in chunk and triangle order,
// adding its counts to `rc`.
void rasterizeTile(const DrawContext& dc, std::span<const TriangleChunk> chunks, int tile,
                   int tilesX, RasterCounters& rc);

// Single-thread variant: the chunk's triangles in order, each over its whole box.
void rasterizeChunk(const DrawContext& dc, const TriangleChunk& chunk, RasterCounters& rc);

}  // namespace rg::raster::detail
