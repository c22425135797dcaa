#include "rasterizer/counters.h"

namespace rg::raster {

std::string Counters::toString() const {
    std::string s;
    auto line = [&](const char* name, uint64_t v) {
        s += name;
        s.append(24 - std::string(name).size(), ' ');
        s += std::to_string(v) + "\n";
    };
    line("passes", passes);
    line("draw_calls", drawCalls);
    line("triangles_submitted", trianglesSubmitted);
    line("triangles_culled", trianglesCulled);
    line("triangles_clipped", trianglesClipped);
    line("triangles_drawn", trianglesDrawn);
    line("triangles_invalid", trianglesInvalid);
    line("fragments_generated", fragmentsGenerated);
    line("fragments_written", fragmentsWritten);
    line("blend_ops", blendOps);
    line("bytes_read_back", bytesReadBack);
    line("texel_fetches", texture.texelFetches);
    line("texture_upload_bytes", texture.uploadBytes);
    return s;
}

}  // namespace rg::raster
