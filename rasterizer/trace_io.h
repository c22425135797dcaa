// Internal to rasterizer/: little-endian byte writing and bounds-checked reading for the
// trace format (docs/trace-format.md, "Encoding").
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "rasterizer/trace.h"

namespace rg::raster::detail {

static_assert(std::endian::native == std::endian::little,
              "the trace encoder copies little-endian values as they are in memory");

struct ByteWriter {
    std::vector<uint8_t>& out;
    void u8(uint8_t v) { out.push_back(v); }
    void u32(uint32_t v) { raw(&v, 4); }
    void i32(int32_t v) { raw(&v, 4); }
    void u64(uint64_t v) { raw(&v, 8); }
    void f32(float v) { raw(&v, 4); }  // IEEE-754 binary32 bits, NaN payloads kept
    void rgba(Rgba8 c) { raw(&c, 4); }
    void raw(const void* p, size_t n) {
        const auto* b = static_cast<const uint8_t*>(p);
        out.insert(out.end(), b, b + n);
    }
};

// Reads one record's payload; every read checks the remaining length.
struct ByteReader {
    std::span<const uint8_t> in;
    size_t pos = 0;
    const char* what = "trace";
    size_t remaining() const { return in.size() - pos; }
    void need(size_t n) const {
        if (n > remaining())
            throw TraceError(std::string(what) + ": record ends " + std::to_string(n - remaining()) +
                             " bytes early");
    }
    void raw(void* p, size_t n) {
        need(n);
        if (n) std::memcpy(p, in.data() + pos, n);
        pos += n;
    }
    uint8_t u8() { need(1); return in[pos++]; }
    uint32_t u32() { uint32_t v; raw(&v, 4); return v; }
    int32_t i32() { int32_t v; raw(&v, 4); return v; }
    uint64_t u64() { uint64_t v; raw(&v, 8); return v; }
    float f32() { float v; raw(&v, 4); return v; }
    Rgba8 rgba() { Rgba8 c; raw(&c, 4); return c; }
    void done() const {
        if (remaining() != 0)
            throw TraceError(std::string(what) + ": " + std::to_string(remaining()) +
                             " unread bytes at the end of the record");
    }
};

// Bytes of one level of one face in the packed layout of `format`.
uint64_t traceLevelBytes(const tex::TextureDesc& desc, int level);
int traceFaces(const tex::TextureDesc& desc);
// The dimensions a texture target uses: 1D 1, 2D and cube maps 2, 3D 3, 4D 4.
int traceDims(const tex::TextureDesc& desc);
// One level of one face packed in the format's layout, checked to expand back to the
// texture's texels (rasterizer/trace_recorder.cpp).
std::vector<uint8_t> tracePackLevel(const tex::Texture& t, int level, int face);
// replayTrace() of a programmable (version 2) trace (rasterizer/trace_player_program.cpp).
ReplayResult replayProgrammableTrace(const Trace& trace, const ReplayOptions& options,
                                     const std::shared_ptr<TraceRecorder>& recorder);
// The content hash of a texture (descriptor, every texel of every level and face); never 0.
uint64_t traceContentHash(const tex::Texture& t);

}  // namespace rg::raster::detail
