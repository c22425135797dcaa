// The kernels of the height-map glass programs (impostor_height_programs.h), and their names
// for traces (docs/trace-format.md, version 2).
#include "impostor_height_programs.h"

#include "rasterizer/program_registry.h"

namespace rg::impostors {

void registerImpostorHeightPrograms() {
    using raster::registerProgram;
    registerProgram<WorldVP, GlassHeightFP<false, false>, ImpostorVertex>("impostors/glass_height");
    registerProgram<WorldVP, GlassHeightFP<true, false>, ImpostorVertex>("impostors/glass_height_mover_search");
    registerProgram<WorldVP, GlassHeightFP<false, true>, ImpostorVertex>("impostors/glass_height_diagnostics");
    registerProgram<WorldVP, GlassHeightFP<true, true>, ImpostorVertex>("impostors/glass_height_mover_search_diagnostics");
}

template <bool kMover, bool kDiagnostics>
void drawHeightGlass(raster::ProgrammableDevice& device, const WorldVP& vp, const GlassHeightFP<kMover, kDiagnostics>& fp,
                     std::span<const ImpostorVertex> vertices, std::span<const uint32_t> indices) {
    device.draw(vp, fp, raster::ProgramPrimitive::TriangleList, vertices, indices);
}

template void drawHeightGlass<false, false>(raster::ProgrammableDevice&, const WorldVP&, const GlassHeightFP<false, false>&,
                                            std::span<const ImpostorVertex>, std::span<const uint32_t>);
template void drawHeightGlass<true, false>(raster::ProgrammableDevice&, const WorldVP&, const GlassHeightFP<true, false>&,
                                           std::span<const ImpostorVertex>, std::span<const uint32_t>);
template void drawHeightGlass<false, true>(raster::ProgrammableDevice&, const WorldVP&, const GlassHeightFP<false, true>&,
                                           std::span<const ImpostorVertex>, std::span<const uint32_t>);
template void drawHeightGlass<true, true>(raster::ProgrammableDevice&, const WorldVP&, const GlassHeightFP<true, true>&,
                                          std::span<const ImpostorVertex>, std::span<const uint32_t>);

}  // namespace rg::impostors
