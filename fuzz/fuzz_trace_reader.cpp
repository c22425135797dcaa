// libFuzzer target: the trace reader (rasterizer/trace_reader.cpp) on arbitrary bytes.
// Malformed input must end in rg::raster::TraceError, never a crash, a hang or an
// allocation the input does not pay for. Traces that parse are replayed when small, so
// the player's handling of hostile-but-well-formed records is covered too. The bench
// programs are registered (bench/bench_programs.h), so that programmable (version 2)
// traces reach the draw records and the player; the seed corpus has one
// (programmable-small-search.trace).
#include <cstddef>
#include <cstdint>

#include "bench_programs.h"
#include "core/error.h"
#include "rasterizer/trace.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const bool registered = (rg::bench::registerPrograms(), true);
    (void)registered;
    try {
        const rg::raster::Trace t = rg::raster::readTrace({data, size});
        // A render target's extent is not paid for by the input (a record of 23 bytes may
        // declare 32768²): replay only what stays small.
        // Nor is a draw's fill: 4,000 points of 8192 pixels each cover a 64×64 target 4,000
        // times, seconds of the reference path's search.
        uint64_t targetBytes = 0, programVertices = 0;
        for (const auto& [id, rt] : t.renderTargets) targetBytes += rg::raster::renderTargetValueBytes(rt.desc);
        for (const auto& c : t.commands) programVertices += c.programDraw.vertexCount + c.indices.size();
        if (size_t(t.width) * size_t(t.height) <= 64 * 64 && t.commands.size() <= 64 && targetBytes <= (1u << 20) &&
            (!t.programmable || programVertices <= 256))
            (void)rg::raster::replayTrace(t, {rg::Path::Reference, 1, -1});
    } catch (const rg::Error&) {
    }
    return 0;
}
