// libFuzzer target: the trace reader (rasterizer/trace_reader.cpp) on arbitrary bytes.
// Malformed input must end in rg::raster::TraceError, never a crash, a hang or an
// allocation the input does not pay for. Traces that parse are replayed when small, so
// the player's handling of hostile-but-well-formed records is covered too.
#include <cstddef>
#include <cstdint>

#include "core/error.h"
#include "rasterizer/trace.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const rg::raster::Trace t = rg::raster::readTrace({data, size});
        if (size_t(t.width) * size_t(t.height) <= 64 * 64 && t.commands.size() <= 64)
            (void)rg::raster::replayTrace(t, {rg::Path::Reference, 1, -1});
    } catch (const rg::Error&) {
    }
    return 0;
}
