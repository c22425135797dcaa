// The `impostor_secant` and `impostor_height` workloads (issue 19): the glass pass of
// Dancsik & Minarik's frame — every glass piece through its fragment program — run on our
// geforce8800 and, as GLSL, on Mesa llvmpipe, fragments/s compared in one `retroglass
// bench` run.
//
//   impostor_secant   GlassFP<false, false> (demos/impostors/impostor_programs.h): the
//                     refracted ray's exit by the secant search in the piece's refractor
//                     distance map (002 §3, Figure 3; a second search where the exit
//                     reflects totally), then the reflected and the exiting ray by the
//                     secant search in its environment distance impostor (§3, Figure 2),
//                     Fresnel and absorption between them
//   impostor_height   GlassHeightFP<false, false> (impostor_height_programs.h): the same,
//                     with the exit found by §6's binary search in the piece's refractor
//                     height map on a billboard (Figure 7's segment, the mirrored retry)
//
// Inputs     One frame of the §8 chess scene (makeChessScene(), its Figure 10 camera, the
//            mover at the start of its path) rendered once by ImpostorRenderer in Mode::Static
//            (nothing moves: no mover search) at kWidth × kHeight, DEPTH 2, 8 secant
//            iterations, ε 0.03, kEnvSize² environment impostors, 256² refractor distance
//            maps, 512² refractor height maps, 8 binary-search steps — once with the
//            distance-map exit (impostor_secant) and once with the height-map exit
//            (impostor_height: its impostors hold pieces drawn with that exit too, so each
//            workload has its own). From each:
//              draws          the glass pieces the frame's glass pass drew, in its order
//                             (nearest first, the ones in view): the piece's ObjectFrame,
//                             its environment impostor and its refractor map, a range of
//                             the mesh below
//              mesh           the drawn pieces' world-space triangles, concatenated
//              environment    one RGBA16F cube per draw (binary16 values held as floats):
//                             radiance, w = distance from the piece's centre
//              refractor      RGBA16F cubes, 256² (one per piece kind and the sphere):
//                             normal, w = distance from the mesh's centre
//              height         RGBA32F 512² (one per piece kind and the sphere): normal,
//                             w = height over the plane of symmetry; row 0 at tHi; and
//                             each one's HeightFrame
//              viewProj, eye  the camera's; every map is read NEAREST, CLAMP_TO_EDGE,
//                             level 0, cube faces on their own (not seamless)
// Per frame  clear the RGBA8 target to (0, 0, 0, 0) and the 24-bit depth buffer to 1; then
//            per draw bind unit 0 = the environment impostor and unit 1 = the refractor
//            distance map (secant) or unit 4 = the height map (height), set the piece's
//            constants and draw its triangles (counter-clockwise front faces, back faces
//            culled; depth test LESS with writes) with WorldVP — the frame's glass pass
//            without the board and sky drawn before it: only the glass programs are timed.
//            They write alpha 1, so alpha 255 marks the glass pixels and the clear's 0 the
//            rest.
// Items      the fragment-program invocations of that frame on ours (early depth test,
//            draws in order): Inputs::fragmentsPerFrame, the same count for both sides.
//
// Benchmarks (bench/harness.h naming): `impostor_secant/<impl>/threads:N` and
// `impostor_height/<impl>/threads:N`, N each of `--threads`, both sides with
// UseManualTime() (seconds per frame) and SetItemsProcessed(iterations · fragmentsPerFrame):
// bench/bench_impostor_peers.cpp. Ours: bench/impostor_peers_retroglass.h (the programs of
// demos/impostors on the geforce8800 programmable device); llvmpipe's GLSL twins:
// bench/impostor_peers_mesa.cpp. They cannot agree bit for bit (llvmpipe's own cube-face
// selection and texel snapping, 1/√x and a/b as its compiler rewrites them, fused
// multiply-adds), so tests/peer/test_impostor_peers_mesa.cpp holds them to a documented
// closeness.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "impostor_height_programs.h"
#include "impostor_programs.h"

namespace rg::bench::impostor_peers {

constexpr int kWidth = 600, kHeight = 600;  // §8's frame
constexpr int kEnvSize = 128;  // the environment impostors (§8: 256 or 512; 128 keeps the
                               // one-off capture, 2 × 33 impostors built DEPTH 2 times, short)
constexpr int kIterations = 8;  // secant steps after l ([D]'s 8)

enum class Exit { Secant, Height };  // which workload: the exit search of the refracted ray
const char* workloadName(Exit e);    // "impostor_secant", "impostor_height"

struct Cube {
    int size = 0;
    std::array<std::vector<glm::vec4>, 6> faces;  // +X, −X, +Y, −Y, +Z, −Z; row 0 = t ≈ 0
};

struct HeightMap {
    int size = 0;
    std::vector<glm::vec4> texels;  // size² texels, row 0 at the top (tHi)
    impostors::HeightFrame frame;
};

struct Draw {
    impostors::ObjectFrame frame;  // GlassConstants::self
    int env = 0;                   // Inputs::env index
    int refractor = 0;             // Inputs::refractors / heights index
    uint32_t firstVertex = 0, vertexCount = 0;  // the piece's range of Inputs::vertices
    uint32_t firstIndex = 0, indexCount = 0;    // its range of Inputs::indices (from its first vertex)
};

struct Inputs {
    Exit exit = Exit::Secant;
    std::vector<impostors::ImpostorVertex> vertices;  // world space, every draw's
    std::vector<uint32_t> indices;                    // each draw's from its first vertex
    std::vector<Draw> draws;                          // in the frame's order
    std::vector<Cube> env;                            // one per draw
    std::vector<Cube> refractors;                     // secant: the refractor distance maps
    std::vector<HeightMap> heights;                   // height: the refractor height maps
    glm::mat4 viewProj{1.0f};
    float eye[3] = {0, 0, 0};
    int iterations = kIterations;
    int64_t fragmentsPerFrame = 0;  // the items: program invocations of one frame on ours
    // The renderer's own frame (board, sky and glass; RGBA8, row 0 at the top) and its depth
    // buffer, for the test that the benchmark's frame is its glass pass.
    std::vector<uint8_t> rendererFrame;
    std::vector<float> rendererDepth;
};

// The chess frame's inputs for a workload, rendered on the first call (all cores, some
// seconds) and kept for the process. Call it before forking a peer child, which gets a copy.
const Inputs& inputs(Exit e);

}  // namespace rg::bench::impostor_peers
