// `retroglass conform`: how a golden trace's replay on ours may differ from a peer's (Mesa
// llvmpipe; a real GPU through a player of one's own), and why (docs/testing.md,
// "Differences from real hardware").
//
// A difference is explained in two parts. Rounding: every pixel may differ by a few 8-bit
// steps (`smallDiff`), what two correct implementations of the same real-valued formula
// give. Larger differences only where a documented choice of docs/hardware.md decides a
// pixel one way and the peer the other way; each such choice is an Alternative: ours
// replayed with that choice made the peer's way (8 subpixel bits instead of the profile's
// 4), or with the exact tie it breaks nudged to both sides (texture coordinates ±2⁻¹⁴ at a
// texel edge, the cube-map direction scaled so that each axis wins a tie in turn). A pixel
// is explained when the peer's value lies within `smallDiff` of ours or of one of the
// alternatives'; a trace passes when every pixel is explained. So a large difference
// anywhere else — a wrong fill rule, a flipped cube face, a wrong address mode — fails.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "rasterizer/framebuffer.h"
#include "rasterizer/trace.h"

namespace rg::conformance {

// One documented choice made the peer's way, or one side of a tie.
struct Alternative {
    std::string name;     // "subpixel-8", "texel-edge+", ...: what conform prints
    int subpixelBits = 0; // > 0: ours replayed with this precision (ReplayOptions)
    std::function<void(raster::Trace&)> transform;  // applied to ours' copy of the trace
    // The pixels the choice can decide (width·height flags, rows top to bottom): the
    // alternative explains only these. Empty function: every pixel.
    std::function<std::vector<uint8_t>(const raster::Trace&)> region;
};

struct Explanation {
    int smallDiff = 2;         // rounding: per channel, every pixel
    std::string rounding;      // why that much
    std::string cause;         // the documented choice behind larger differences ("" if none)
    std::string section;       // where docs/hardware.md states it
    // The documented choices that decide pixels here, each a list of ways it may go
    // (the two sides of a tie, the peer's setting). Ours is replayed once for every
    // combination that takes at most one way of each choice (none included), since one
    // pixel may sit on two ties at once (a face seam at a level boundary).
    std::vector<std::vector<Alternative>> choices;
    // What the peer plays instead of the trace, when it cannot express a state: the
    // nearest it can (colours perspective-correct for raster-affine-colour); ours is then
    // also replayed that way as an alternative. Empty: the trace as it is.
    std::function<void(raster::Trace&)> peerTransform;
};

// The explanation of a golden trace (nullptr: none, so the trace is compared with
// rounding only).
const Explanation* explanationFor(const std::string& traceName);
// Whether the trace is expected to be ours-only (Mesa cannot play it at all).
bool expectedOursOnly(const std::string& traceName);

// Ours' images: the trace as it is (first, named "ours"), then one per alternative (and,
// with a peer transform, the trace as the peer plays it and its alternatives). Reference
// path, one thread: the bytes of every path.
struct OursImage {
    std::string name;
    raster::Framebuffer image;
    std::vector<uint8_t> region;  // empty: the image explains any pixel; else only these
};
std::vector<OursImage> oursAndAlternatives(const raster::Trace& trace, const Explanation& e);
// The trace as the peer plays it.
raster::Trace peerTrace(const raster::Trace& trace, const Explanation& e);

struct Comparison {
    size_t pixels = 0;
    size_t differing = 0;    // ours (as it is) against the peer: any difference
    int maxDiff = 0;         // the largest channel difference against ours
    size_t beyond = 0;       // pixels differing from ours by more than smallDiff
    size_t unexplained = 0;  // of those, no alternative within smallDiff either
    // Per alternative, the beyond pixels it explains (the first that does).
    std::vector<std::pair<std::string, size_t>> explainedBy;
    std::vector<std::pair<int, int>> firstUnexplained;  // (x, y), at most 8
    bool pass() const { return unexplained == 0; }
};
// `images`: oursAndAlternatives(), the first ours as it is.
Comparison compareWithPeer(const std::vector<OursImage>& images, const raster::Framebuffer& peer,
                           const Explanation& e);

}  // namespace rg::conformance
