// The `tir_final_pass` workload (issue 20): the last pass of Davis & Wyman 2007 — the
// refractor's front faces through the image-space search (demos/tir/tir_search.h, TirFP)
// — run on our geforce8800 and, as GLSL, on Mesa llvmpipe, fragments/s compared in one
// `retroglass bench` run.
//
// Inputs     One frame of the kitchen scene (makeTirScene("kitchen"), its camera) rendered
//            once by TirRenderer at 512×512 with the default TirSettings (3 bounces, back
//            faces only, 8/5 iterations, nearby search on, 128² environment). From it:
//              back, front, nearby maps  512² RGBA16F (binary16 values held as floats),
//                                        row 0 the top row; read NEAREST, CLAMP_TO_EDGE,
//                                        level 0
//              environment               RGBA16F cube map, 128² faces, bilinear, level 0,
//                                        each face clamped at its edges (not seamless)
//              refractor                 the bunny's world-space vertices and indices
//              EyeVP, SearchConstants    the frame's view, projection and search constants
// Per frame  clear the RGBA8 target to (0, 0, 0, 0) and the 24-bit depth buffer to 1;
//            draw the refractor's triangles (front faces: back faces culled; depth test
//            LESS with writes) with EyeVP and TirFP, units 0–3 = back, front, nearby,
//            environment — pass 4 of TirRenderer without its background (pass 3's copy):
//            only the search is timed. TirFP writes alpha 1, so alpha 255 marks the
//            refractive pixels and the clear's 0 the rest.
// Items      the fragment-program invocations of that draw on ours (early depth test,
//            primitive order): inputs().fragmentsPerFrame, the same count for both sides.
//
// Benchmarks (bench/harness.h naming): `tir_final_pass/<impl>/threads:N`, N ∈ {1,
// allThreads()}, both with UseManualTime() (wall-clock seconds per frame, which gives both
// the `/manual_time` suffix the harness pairs on) and SetItemsProcessed(iterations ·
// fragmentsPerFrame): bench/bench_tir_final_pass.cpp. Ours: bench/tir_final_pass_retroglass.h;
// llvmpipe's GLSL twin of TirFP and EyeVP: bench/tir_final_pass_mesa.cpp. The two cannot
// agree bit for bit (llvmpipe's own float ↔ binary16 and cube-map filtering, 1/√x and
// division rewritten by its compiler, its rasterizer's rules for y-up windows), so
// tests/peer/test_tir_final_pass_mesa.cpp holds them to a documented closeness.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "tir_programs.h"

namespace rg::bench::tir_final_pass {

constexpr int kWidth = 512, kHeight = 512;  // the frame and the maps (mapScale 1)

struct Inputs {
    std::vector<glm::vec4> back, front, nearby;  // kWidth·kHeight texels, row 0 at the top
    int envSize = 0;
    std::array<std::vector<glm::vec4>, 6> env;  // faces +X, −X, +Y, −Y, +Z, −Z; row 0 = t ≈ 0
    std::vector<tir::TirVertex> vertices;       // the refractor, world space
    std::vector<uint32_t> indices;
    tir::EyeVP vp;
    tir::SearchConstants k;
    int64_t fragmentsPerFrame = 0;  // the items: TirFP invocations of one frame on ours
};

// The kitchen frame's inputs, rendered on the first call (all cores, a second or two) and
// kept for the process. Call it before forking a peer child, which gets a copy.
const Inputs& inputs();

}  // namespace rg::bench::tir_final_pass
