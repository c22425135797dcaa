// The impostor_secant and impostor_height workloads (bench/impostor_peers_workload.h): our
// side is the glass pass of the impostor renderer's frame, and llvmpipe's GLSL twins of
// GlassFP and GlassHeightFP render close to it.
//   ImpostorPeersRetroglass  the benchmark's frames against the renderer's own frame and
//                            against the reference path
//   ImpostorPeersMesa        llvmpipe's frames against ours, within a stated closeness; the
//                            same check refuses shaders with a planted bug
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "closeness.h"
#include "bench/impostor_peers_mesa.h"
#include "bench/impostor_peers_retroglass.h"
#include "bench/impostor_peers_workload.h"

namespace rg::bench::impostor_peers {
namespace {

using peer_test::Closeness;
using peer_test::compareCovered;
using peer_test::describe;

const char* const kRepro = "reproduce: build/bin/test_peer --gtest_filter='ImpostorPeers*'";

std::vector<uint8_t> oursImage(Exit e) {
    ImpostorPeerScene ours(inputs(e), 2);
    ours.frame();
    return ours.image();
}

// ---- ours is the renderer's glass pass -----------------------------------------------------

// The renderer draws the board and the sky, then the glass pieces in the order captured.
// Wherever the benchmark's frame has glass (alpha 255) at the depth the renderer's frame
// ends with, the renderer's glass fragment won there too, so its frame has the same bytes:
// the inputs were carried over whole (maps, impostors, meshes, vertex program, constants)
// and the units bound as drawGlass binds them. Where the depths differ the board won. The
// one exception is a depth tie: a piece's foot stands on the board's top face, and where
// both land on the same 24-bit depth the board, drawn first, keeps the pixel under LESS
// while our frame, without the board, shows the glass. Measured: 11 such pixels of 34,579
// in both workloads, where the renderer's colours are dark or light board squares' (21 12 8,
// 113 106 88, ...); at most 0.1 % is allowed.
void expectRendererGlassPass(Exit e) {
    const Inputs& in = inputs(e);
    ImpostorPeerScene scene(in, 2);
    scene.frame();
    const std::vector<uint8_t> ours = scene.image();
    const float* depth = scene.depth->dataR(0, 0);
    int covered = 0, compared = 0, differing = 0;
    for (size_t i = 0; i < ours.size(); i += 4) {
        if (ours[i + 3] != 255) continue;
        ++covered;
        if (depth[i / 4] != in.rendererDepth[i / 4]) continue;
        ++compared;
        const uint8_t* r = &in.rendererFrame[i];
        if (ours[i] != r[0] || ours[i + 1] != r[1] || ours[i + 2] != r[2]) {
            if (differing++ < 3)
                std::printf("%s pixel (%zu, %zu), a depth tie: bench %d %d %d, renderer %d %d %d\n", workloadName(e),
                            (i / 4) % kWidth, (i / 4) / kWidth, ours[i], ours[i + 1], ours[i + 2], r[0], r[1], r[2]);
        }
    }
    std::printf("%s: %zu pieces drawn, %d glass pixels, %d compared with the renderer's frame, %lld fragments "
                "per frame\n",
                workloadName(e), in.draws.size(), covered, compared, static_cast<long long>(in.fragmentsPerFrame));
    EXPECT_LE(differing, compared / 1000) << kRepro;
    // The 33 pieces of the §8 scene, all in view, cover about a tenth of the 600² frame;
    // nearly all of it in front of the board; every covered pixel ran the program at least
    // once.
    EXPECT_GE(in.draws.size(), 30u);
    EXPECT_GT(covered, 30000);
    EXPECT_GT(compared, 0.99 * covered);
    EXPECT_GE(in.fragmentsPerFrame, covered);
}

TEST(ImpostorPeersRetroglass, SecantFrameIsTheGlassPassOfTheRenderer) { expectRendererGlassPass(Exit::Secant); }
TEST(ImpostorPeersRetroglass, HeightFrameIsTheGlassPassOfTheRenderer) { expectRendererGlassPass(Exit::Height); }

// The frame the benchmark times is the reference path's, byte for byte, one thread and two.
void expectReferenceBytes(Exit e) {
    ImpostorPeerScene reference(inputs(e), 1, Path::Reference);
    reference.frame();
    const std::vector<uint8_t> want = reference.image();
    for (int threads : {1, 2}) {
        ImpostorPeerScene fast(inputs(e), threads);
        fast.frame();
        EXPECT_EQ(fast.image(), want) << workloadName(e) << ", " << threads << " threads; " << kRepro;
    }
}

TEST(ImpostorPeersRetroglass, SecantSameBytesOnTheReferencePath) { expectReferenceBytes(Exit::Secant); }
TEST(ImpostorPeersRetroglass, HeightSameBytesOnTheReferencePath) { expectReferenceBytes(Exit::Height); }

// ---- llvmpipe against ours ---------------------------------------------------------------

constexpr int kSteps = 3;

// The closeness the GLSL twins are held to. The searches are chains of decisions on floats
// (which cube face and texel, undershoot or overshoot, inside or outside the height map,
// refract or reflect), and llvmpipe computes the same expressions with its own rounding in
// places (1/√x, its cube-face selection), so the twins cannot be exact; but they are
// further apart than tir's (99.85 % within 3 steps) and the cause is not yet known:
//   - both sides are stable: moving the eye by 2 ulps changes 0.16 % (secant) and 0.05 %
//     (height) of our pixels and 0.24 % and 0.05 % of llvmpipe's by more than 3 steps, so
//     the gap is systematic, not rounding noise;
//   - it grows with the secant iterations (at 0 iterations 99.58 % of the pixels are
//     within 3 steps, 94.57 % at 8), and in the height workload it sits in the pixels whose
//     exit reflects totally (27 % of them differ, 2.4 % of the others), where the exit
//     point and direction agree (99.35 %) but the environment search from there does not;
//   - half-texel shifts of the height map, texelFetch, `precise` (no fused multiply-adds)
//     and correctly rounded division in the searches do not move it.
// Measured on llvmpipe (LLVM 15.0.6, 256 bits), 1 thread, the same 34,580 glass pixels
// covered on both sides:
//   impostor_secant   94.57 % within 3 steps, mean 2.46 steps (the subtlest planted bug, one
//                     secant step dropped: 84.52 %, mean 7.36)
//   impostor_height   86.39 %, mean 8.93 (one bisection step dropped: 77.58 %, 17.2)
// The bounds below sit between the two:
//   coverage   the same glass pixels but for silhouette edge ties: at most 0.5 % of ours
//              covered on one side only;
//   per pixel  at least `within` of the pixels both cover have every channel within 3 steps;
//   overall    the mean difference is under `mean` steps.
struct Bounds {
    double within, mean;
};
Bounds bounds(Exit e) { return e == Exit::Height ? Bounds{0.84, 11.0} : Bounds{0.92, 3.5}; }

bool closeEnough(const Closeness& c, Exit e) {
    const int onlyOne = c.oursCovered + c.mesaCovered - 2 * c.both;
    const Bounds b = bounds(e);
    return c.oursCovered > 30000 && onlyOne <= c.oursCovered / 200 && c.within >= b.within * c.both &&
           c.meanError < b.mean;
}

void expectClose(Exit e) {
    const MesaImage mesa = renderMesa(inputs(e), 1);
    ASSERT_NE(mesa.renderer.find("llvmpipe"), std::string::npos) << mesa.renderer;
    const Closeness c = compareCovered(oursImage(e), mesa.rgba, kSteps);
    std::printf("%s on %s: %s\n", workloadName(e), mesa.renderer.c_str(), describe(c, "glass pixels").c_str());
    EXPECT_TRUE(closeEnough(c, e)) << workloadName(e) << ": " << describe(c, "glass pixels") << "; " << kRepro;
}

TEST(ImpostorPeersMesa, SecantCloseToOurs) { expectClose(Exit::Secant); }
TEST(ImpostorPeersMesa, HeightCloseToOurs) { expectClose(Exit::Height); }

// The same check against shaders with a bug planted: each mistake a twin could make must
// fail it, or the closeness above proves nothing.
struct Bug {
    const char* what;
    const char* from;
    const char* to;
};

void expectBugsRefused(Exit e, std::initializer_list<Bug> bugs) {
    const std::vector<uint8_t> ours = oursImage(e);
    for (const Bug& bug : bugs) {
        std::string fs = fragmentShader(e);
        const size_t at = fs.find(bug.from);
        ASSERT_NE(at, std::string::npos) << bug.what << ": the shader no longer has `" << bug.from << "`";
        fs.replace(at, std::strlen(bug.from), bug.to);
        const Closeness c = compareCovered(ours, renderMesa(inputs(e), 1, fs).rgba, kSteps);
        std::printf("planted in %s: %s: %s\n", workloadName(e), bug.what, describe(c, "glass pixels").c_str());
        EXPECT_FALSE(closeEnough(c, e)) << workloadName(e) << ": " << bug.what << " passes the check: " << describe(c, "glass pixels")
                                     << "; " << kRepro;
    }
}

TEST(ImpostorPeersMesa, SecantPlantedBugsFailTheCheck) {
    expectBugsRefused(Exit::Secant,
                      {
                          {"one secant step dropped", "for (int i = 0; i < iterations; ++i)",
                           "for (int i = 1; i < iterations; ++i)"},
                          {"the refractor search not seeded", "Search s = secantSearch(refractorMap, xl, Tl, true);",
                           "Search s = secantSearch(refractorMap, xl, Tl, false);"},
                          {"no second search under total internal reflection", "if (tirOut) {", "if (false) {"},
                          {"the secant step's ratio turned round", "((1.0 - aU) / den)", "((1.0 - aO) / den)"},
                          {"the Fresnel weight swapped", "er.colour * g.fresnel + (et.colour * g.transmit) * (1.0 - g.fresnel)",
                           "er.colour * (1.0 - g.fresnel) + (et.colour * g.transmit) * g.fresnel"},
                          {"refraction with η instead of 1/η", "refractOrReflect(V, N, invEta, tirIn)",
                           "refractOrReflect(V, N, eta, tirIn)"},
                      });
}

TEST(ImpostorPeersMesa, HeightPlantedBugsFailTheCheck) {
    expectBugsRefused(Exit::Height,
                      {
                          {"no mirrored retry", "if (retry) second = bisect", "if (false) second = bisect"},
                          {"one bisection step dropped", "for (int i = 0; i < steps; ++i)",
                           "for (int i = 1; i < steps; ++i)"},
                          {"the normal not mirrored", "nh = tex.z * sigma", "nh = tex.z"},
                          {"v not flipped (row 0 at tLo)", "(tHi - t) * vScale", "(t - tLo) * vScale"},
                      });
}

}  // namespace
}  // namespace rg::bench::impostor_peers
