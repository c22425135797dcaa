// The impostors programs registered by name, so that traces of an impostors frame name them
// (docs/trace-format.md, version 2) and `retroglass replay` plays them.
#include "impostor_programs.h"
#include "rasterizer/program_registry.h"

namespace rg::impostors {

void registerImpostorPrograms() {
    using raster::registerProgram;
    registerProgram<WorldVP, DiffuseFP, ImpostorVertex>("impostors/diffuse");
    registerProgram<ScreenVP, SkyFP, ImpostorVertex>("impostors/sky");
    registerProgram<WorldVP, NormalDistanceFP, ImpostorVertex>("impostors/refractor_map");
    registerProgram<WorldVP, DepthOnlyFP, ImpostorVertex>("impostors/shadow_map");
    registerProgram<TextureSpaceVP, LightMapFP, ImpostorVertex>("impostors/light_map");
    registerProgram<WorldVP, GlassFP<false, false>, ImpostorVertex>("impostors/glass");
    registerProgram<WorldVP, GlassFP<true, false>, ImpostorVertex>("impostors/glass_mover_search");
    registerProgram<WorldVP, GlassFP<false, true>, ImpostorVertex>("impostors/glass_diagnostics");
    registerProgram<WorldVP, GlassFP<true, true>, ImpostorVertex>("impostors/glass_mover_search_diagnostics");
    registerProgram<WorldVP, GridFP, ImpostorVertex>("impostors/mode_a");
}

template <class VP, class FP>
void drawTriangles(raster::ProgrammableDevice& device, const VP& vp, const FP& fp,
                   std::span<const ImpostorVertex> vertices, std::span<const uint32_t> indices) {
    device.draw(vp, fp, raster::ProgramPrimitive::TriangleList, vertices, indices);
}

#define RG_IMPOSTORS_DRAW(VP, ...)                                                                      \
    template void drawTriangles<VP, __VA_ARGS__>(raster::ProgrammableDevice&, const VP&, const __VA_ARGS__&, \
                                                 std::span<const ImpostorVertex>, std::span<const uint32_t>);
RG_IMPOSTORS_DRAW(WorldVP, DiffuseFP)
RG_IMPOSTORS_DRAW(ScreenVP, SkyFP)
RG_IMPOSTORS_DRAW(WorldVP, NormalDistanceFP)
RG_IMPOSTORS_DRAW(WorldVP, DepthOnlyFP)
RG_IMPOSTORS_DRAW(TextureSpaceVP, LightMapFP)
RG_IMPOSTORS_DRAW(WorldVP, GlassFP<false, false>)
RG_IMPOSTORS_DRAW(WorldVP, GlassFP<true, false>)
RG_IMPOSTORS_DRAW(WorldVP, GlassFP<false, true>)
RG_IMPOSTORS_DRAW(WorldVP, GlassFP<true, true>)
RG_IMPOSTORS_DRAW(WorldVP, GridFP)
#undef RG_IMPOSTORS_DRAW

}  // namespace rg::impostors
