// The tir programs registered by name, so that traces of a tir frame name them
// (docs/trace-format.md, version 2) and `retroglass replay` plays them.
#include "rasterizer/program_registry.h"
#include "tir_programs.h"

namespace rg::tir {

void registerTirPrograms() {
    using raster::registerProgram;
    registerProgram<EyeVP, NormalDepthFP, TirVertex>("tir/normal_depth");
    registerProgram<EyeVP, NearbyFP, TirVertex>("tir/nearby");
    registerProgram<ScreenVP, EnvFP, TirVertex>("tir/environment");
    registerProgram<ScreenVP, CopyFP, TirVertex>("tir/copy");
    registerProgram<EyeVP, TirFP, TirVertex>("tir/final_pass");
    registerProgram<EyeVP, Wyman05FP, TirVertex>("tir/wyman05");
}

}  // namespace rg::tir
