// `retroglass conform`: every golden trace on ours and on Mesa (llvmpipe), compared per
// trace pixel by pixel: rounding everywhere, and larger differences only where a
// documented choice of docs/hardware.md decides the pixel (conformance/include/conformance/
// conform.h; docs/testing.md, "Differences from real hardware", gives each trace's reason
// and the figures measured on llvmpipe and on an NVIDIA H100).
#include "conformance/conform.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>

#include "conformance/mesa_player.h"
#include "core/error.h"
#include "texunit/cube_mapping.h"

namespace rg::conformance {

using raster::Trace;
using raster::TraceCommand;
using raster::TraceOp;

namespace {

// ---- the alternatives: one documented choice made the peer's way, or a tie's two sides --

// The subpixel precision (docs/hardware.md, "Pinned choices": subpixel precision; "Setup
// and rasterization": snapping; "Interpolation": planes through the snapped vertices).
// Ours snaps window positions to the profile's 4 bits, llvmpipe to 8 (D3D10's): pixel
// centres within 1/32 px of an edge change sides, and every attribute plane, built
// through the snapped vertices, tilts by up to ½·2⁻⁴ px times its gradient.
Alternative subpixel8() { return {"subpixel-8", 8, nullptr, nullptr}; }

// Texel-edge ties (docs/hardware.md, "Filtering": NEAREST i = ⌊u⌋ of the 8-bit fixed-point
// coordinate). Where ours' binary32 coordinate lands exactly on a texel edge (u = 5.0 for a
// real value 4.99999994), the texel is decided by the last ulp of each implementation's
// interpolation. ±2⁻¹⁴ of a coordinate (2⁻¹² texel of a 4-texel texture) shows both sides.
Alternative texelEdge(float sign) {
    return {sign > 0 ? "texel-edge+" : "texel-edge-", 0, [sign](Trace& t) {
                const float d = sign * 0x1p-14f;
                for (TraceCommand& c : t.commands)
                    if (c.op == TraceOp::Draw)
                        for (raster::Vertex& v : c.vertices)
                            for (glm::vec4& tc : v.tex) tc += glm::vec4(d, d, d, 0.0f);
            }, nullptr};
}

// Depth order of coplanar triangles in separate draws (docs/hardware.md, "Interpolation":
// every plane, depth included, goes through the snapped vertices; "Depth": z in double,
// then quantized). Two draws of one plane with different vertices snap differently, so
// their depth planes differ by up to 2⁻⁵ px times the depth gradient (about 2⁻¹² of the
// range on raster-transform-clip-cull); llvmpipe interpolates z through the unsnapped
// positions, so the same plane has the same depth and LESSEQUAL lets the later draw win.
// Ours with each later draw nearer (or farther) by 2⁻¹² more shows both outcomes.
Alternative depthOrder(int sign) {
    return {sign > 0 ? "depth-order+" : "depth-order-", 0, [sign](Trace& t) {
                constexpr float kStep = 0x1p-12f;
                size_t draws = 0;
                for (const TraceCommand& c : t.commands) draws += c.op == TraceOp::Draw;
                // Every draw's depth range compressed into [m, 1 − m], then moved by
                // k·kStep: the order of draws k apart changes by k·kStep, nothing else.
                const float m = float(draws + 1) * kStep;
                std::vector<TraceCommand> out;
                raster::Viewport vp{};
                size_t k = 0;
                for (TraceCommand& c : t.commands) {
                    if (c.op == TraceOp::Viewport) vp = c.viewport;
                    if (c.op == TraceOp::Draw && c.space == raster::VertexSpace::Untransformed) {
                        const float shift = float(sign) * float(++k) * kStep;
                        TraceCommand v;
                        v.op = TraceOp::Viewport;
                        v.viewport = vp;
                        v.viewport.minZ = m + vp.minZ * (1.0f - 2.0f * m) + shift;
                        v.viewport.maxZ = m + vp.maxZ * (1.0f - 2.0f * m) + shift;
                        out.push_back(v);
                        out.push_back(std::move(c));
                        TraceCommand back;
                        back.op = TraceOp::Viewport;
                        back.viewport = vp;
                        out.push_back(back);
                        continue;
                    }
                    out.push_back(std::move(c));
                }
                t.commands = std::move(out);
            }, nullptr};
}

// Cube-face ties (docs/hardware.md, "Pinned choices": cube-face ties; "Cube mapping"). On
// a face seam the major axis is decided by the last ulp of each implementation's
// reflection vector; the direction scaled by (1 + 2ε, 1 + ε, 1) lets x win every tie, then
// y, then z, and (1, 1 + ε, 1 + 2ε) the reverse (ε = 2⁻¹², through the texture matrix).
Alternative cubeSeam(bool xFirst) {
    return {xFirst ? "cube-seam-xyz" : "cube-seam-zyx", 0, [xFirst](Trace& t) {
                constexpr float e = 0x1p-12f;
                const glm::vec3 s = xFirst ? glm::vec3(1 + 2 * e, 1 + e, 1) : glm::vec3(1, 1 + e, 1 + 2 * e);
                glm::mat4 d(1.0f);
                d[0][0] = s.x;
                d[1][1] = s.y;
                d[2][2] = s.z;
                for (TraceCommand& c : t.commands)
                    if (c.op == TraceOp::TexGen) {
                        c.texGen.matrix = d * (c.texGen.matrixEnabled ? c.texGen.matrix : glm::mat4(1.0f));
                        c.texGen.matrixEnabled = true;
                    }
            }, nullptr};
}

Alternative lodBias(float bias);

// λ of a quad whose pixels look at different faces (docs/hardware.md, "Cube mapping": λ
// for a quad measures all four pixels' directions on pixel 0's face). A direction of
// another face projected onto pixel 0's face lands off it, by up to |ma|/|sc| face widths,
// so the level such a quad takes is ours' choice; llvmpipe measures each face's own
// derivatives. In those quads (set 0's directions, helper pixels included), ours with the
// level moved by `levels` (a LOD bias) explains the peer: another level of the same face,
// never another face's texels.
Alternative levelAcrossFaces(int levels) {
    Alternative a = lodBias(float(levels));
    a.name = "quad-across-faces-level" + std::string(levels > 0 ? "+" : "") + std::to_string(levels);
    a.region = [](const Trace& t) {
        std::vector<uint8_t> region(size_t(t.width) * size_t(t.height), 0);
        raster::ReplayOptions o;
        o.path = Path::Reference;
        o.threads = 1;
        o.fragmentObserver = [&](const tex::FragmentQuad& q, uint8_t) {
            const tex::CubeFace f0 = tex::selectCubeFace(glm::vec3(q.texCoord[0][0])).face;
            bool across = false;
            for (int p = 1; p < 4; ++p) across |= tex::selectCubeFace(glm::vec3(q.texCoord[0][size_t(p)])).face != f0;
            if (!across) return;
            for (int p = 0; p < 4; ++p) {
                const int x = q.x + (p & 1), y = q.y + (p >> 1);
                if (x < t.width && y < t.height) region[size_t(y) * size_t(t.width) + size_t(x)] = 1;
            }
        };
        raster::replayTrace(t, o);
        return region;
    };
    return a;
}

// The level of detail (docs/hardware.md, "Level of detail", "Pinned choices": LOD log2 and
// fraction bits, nearest-mip rounding). Ours: one λ per 2×2 quad from pixel 1 − pixel 0
// and pixel 2 − pixel 0, ρ² = max(Σ(∂u/∂x)², Σ(∂u/∂y)²), a piecewise-linear log2 up to
// 0.0861 low, cube-map derivatives on pixel 0's face. llvmpipe: its own per-quad ρ from
// the face-projected derivatives and a polynomial log2. Where they straddle a level
// boundary the nearest mip level, or the blend weight, differs; a bias of ±½ (ρ scaled by
// √2, the largest ratio between the ρ formulas) shows both levels.
Alternative lodBias(float bias) {
    return {bias > 0 ? "lod+" : "lod-", 0, [bias](Trace& t) {
                for (TraceCommand& c : t.commands)
                    if (c.op == TraceOp::Sampler) c.sampler.lodBias += bias;
            }, nullptr};
}

// Colours interpolated screen-linearly (docs/hardware.md, "Pinned choices": colour
// interpolation, perspectiveColor = 0). GL always corrects for perspective, so the peer
// plays the trace with perspectiveColor = 1.
void perspectiveColour(Trace& t) {
    for (TraceCommand& c : t.commands)
        if (c.op == TraceOp::State) c.state.perspectiveColor = 1;
}

const std::map<std::string, Explanation>& explanations() {
    const char* kSnapping = "subpixel precision: ours snaps window positions to the profile's 4 bits, "
                            "llvmpipe to 8 (edge pixels change sides, attribute planes through the snapped "
                            "vertices tilt)";
    const char* kSnappingSection = "Pinned choices: subpixel precision; Setup and rasterization: snapping; "
                                   "Interpolation: planes";
    static const std::map<std::string, Explanation> table = [&] {
        std::map<std::string, Explanation> t;
        auto rounding = [&](const char* name, int small, const char* why) {
            t[name] = Explanation{small, why, "", "", {}, nullptr};
        };
        // Rounding only: no documented choice flips a pixel; a wrong blend factor, compare
        // function or mapping shows as a large difference and fails.
        rounding("alpha-test", 1,
                 "Gouraud colour ±1 (ours floor(v + ½) of a binary32 plane, llvmpipe its fixed-point "
                 "interpolation); alpha compared in 8 bits on both");
        rounding("blend-factors", 2, "blend products: ours round(x·f/255) exactly, llvmpipe's unorm8 multiply "
                                     "±1 per product, two products summed");
        rounding("blend-ops", 2, "blend products ±1 each, two per operation");
        rounding("depth-compare-d16", 1, "Gouraud colour ±1; window z quantized alike (round to nearest)");
        rounding("depth-compare-d24", 1, "Gouraud colour ±1; window z quantized alike (round to nearest)");
        rounding("fragment-scissor-mask-specular", 2, "diffuse ±1 plus specular ±1 in the colour sum");
        rounding("passes-readback", 4, "filter ±1, combine ±1 and blend ±2 over two passes");
        rounding("programmable-binary-search", 1,
                 "the search is exact on both; float to unorm8 rounds the frame's one binary32 tie to even on "
                 "llvmpipe and up on ours (bench/binary_search_workload.h)");
        rounding("stage-ops-color", 3, "combine products ±½ step before a 4× scale, then rounded: ±3");
        rounding("stage-ops-alpha", 6, "combiner alpha ±3 (as stage-ops-color), through a SRCALPHA blend of a "
                                       "colour ±1, the product rounded ±1 and the op's own ±1");
        rounding("texture-formats", 2, "bilinear weights ±1, MODULATE ±1");
        rounding("texture-mipmap-lod", 2, "bilinear and trilinear weights ±1; pre-transformed, so no snapping "
                                          "difference and every level choice is the same on both");
        rounding("texture-units-3d", 2, "filter ±1 and combine ±1; pre-transformed");

        // The fill rule: pre-transformed vertices on exact pixel centres and edges. Mesa's
        // tie rule is ours (conformance/mesa_player.cpp draws the image with row r at GL
        // window row r, where llvmpipe's bottom-left rule is Direct3D's top-left), and these
        // coordinates snap alike at 4 and 8 bits, so rounding alone: a wrong fill rule shows
        // as whole pixels along the shared edges.
        rounding("raster-fill-rule", 1, "Gouraud colour ±1 under the additive blend; every tie of the "
                                        "top-left rule decided alike");
        t["raster-fill-rule"].choices = {{subpixel8()}};
        t["raster-fill-rule"].cause = kSnapping;
        t["raster-fill-rule"].section = kSnappingSection;

        Explanation clip{2, "Gouraud colour ±1, perspective-correct on both", kSnapping +
                             std::string("; coplanar triangles of consecutive draws z-fight: their depth planes go "
                                         "through differently snapped vertices (ours), the unsnapped ones (llvmpipe)"),
                         kSnappingSection + std::string("; Depth"),
                         {{subpixel8()}, {depthOrder(+1), depthOrder(-1)}},
                         nullptr};
        t["raster-transform-clip-cull"] = clip;
        // GL cannot interpolate colours without perspective correction: Mesa plays the
        // trace with perspectiveColor = 1, ours is compared as it is and so (alternative).
        Explanation affine = clip;
        affine.cause = "colour interpolation: ours screen-linear here (perspectiveColor = 0), GL always "
                       "perspective-correct; and " + clip.cause;
        affine.section = "Pinned choices: colour interpolation; Interpolation; " + clip.section;
        affine.peerTransform = perspectiveColour;
        t["raster-affine-colour"] = affine;

        t["texgen-gl-modes"] = Explanation{
            3, "bilinear weights of noise ±2 (coordinates one binary32 step apart), MODULATE ±1",
            kSnapping + std::string(": the texture-coordinate planes of untransformed triangles tilt by up to "
                                    "1/32 px times their gradient, a tenth of a texel of minified noise"),
            kSnappingSection, {{subpixel8()}}, nullptr};
        t["texture-address-filter"] = Explanation{
            2, "bilinear weights ±1 (8 fraction bits on both), GL_CLAMP and CLAMP_TO_BORDER mixing the border "
               "colour alike",
            "texel-edge ties: NEAREST at column 4 of each cell lands on u = 5.0 exactly in ours' binary32 "
            "plane (4.99999994 in reals), so WRAP and MIRROR pick texel 1 or 0 (2 or 3) by the last ulp",
            "Filtering: NEAREST i = ⌊u⌋, address modes",
            {{texelEdge(+1), texelEdge(-1)}}, nullptr};
        t["texture-cube-reflection"] = Explanation{
            4, "bilinear weights ±1 on both faces' edge texels, MODULATE ±1, reflection vectors within binary32 "
               "rounding",
            "cube-face ties on the seams (|rx| = |rz| to the last ulp) and the level of detail (one λ per quad on "
            "pixel 0's face from a piecewise-linear log2; llvmpipe's own ρ and log2) at level boundaries; "
            "and " + std::string(kSnapping),
            "Pinned choices: cube-face ties, LOD log2 and fraction bits, nearest-mip rounding; Cube mapping; "
            "Level of detail; " + std::string(kSnappingSection),
            {{subpixel8()},
             {cubeSeam(true), cubeSeam(false)},
             {lodBias(+0.5f), lodBias(-0.5f), levelAcrossFaces(-3), levelAcrossFaces(-2), levelAcrossFaces(-1),
              levelAcrossFaces(1), levelAcrossFaces(2), levelAcrossFaces(3)}},

            nullptr};
        return t;
    }();
    return table;
}

const Explanation& defaultExplanation() {
    static const Explanation e{2, "no explanation for this trace: rounding only", "", "", {}, nullptr};
    return e;
}

int maxChannelDiff(Rgba8 a, Rgba8 b) {
    return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b), std::abs(a.a - b.a)});
}

}  // namespace

const Explanation* explanationFor(const std::string& name) {
    auto it = explanations().find(name);
    return it == explanations().end() ? nullptr : &it->second;
}

// Whether a golden trace is compared or ours-only is part of what conform checks: a
// trace with an explanation that Mesa suddenly cannot play (a player or mapping change
// made mesaUnsupported() refuse it) must fail rather than silently drop to ours-only,
// and a trace listed here that Mesa now plays needs an explanation instead. Traces in
// neither list (a --golden folder of one's own) are reported without expectation.
bool expectedOursOnly(const std::string& name) {
    static const std::set<std::string> list = {
        "color-table",         // SGI_texture_color_table
        "pixel-texture",       // SGIX_pixel_texture
        "texture-4d",          // SGIS_texture4D
        "stage-args-cascade",  // D3DTA_SPECULAR as a stage argument
        "stage-ops-d3d-only",  // the Direct3D-only stage ops
    };
    return list.count(name) > 0;
}

Trace peerTrace(const Trace& trace, const Explanation& e) {
    Trace t = trace;
    if (e.peerTransform) e.peerTransform(t);
    return t;
}

std::vector<OursImage> oursAndAlternatives(const Trace& trace, const Explanation& e) {
    std::vector<OursImage> out;
    auto play = [&](const std::string& name, const Trace& t, int subpixelBits) {
        raster::ReplayOptions o;
        o.path = Path::Reference;
        o.threads = 1;
        o.subpixelBits = subpixelBits;
        out.push_back({name, raster::replayTrace(t, o).framebuffer, {}});
    };
    // Every combination of at most one way per choice, but not none at all (that is ours):
    // the ways applied in the order of the choices, their regions intersected.
    auto withAlternatives = [&](const std::string& prefix, const Trace& base) {
        std::vector<size_t> way(e.choices.size(), 0);  // 0: this choice as ours makes it
        while (true) {
            size_t c = 0;
            while (c < way.size() && ++way[c] > e.choices[c].size()) way[c++] = 0;
            if (c == way.size()) break;
            Trace t = base;
            std::string name = prefix;
            int subpixelBits = 0;
            std::vector<const Alternative*> regions;
            for (size_t k = 0; k < way.size(); ++k) {
                if (!way[k]) continue;
                const Alternative& a = e.choices[k][way[k] - 1];
                if (a.transform) a.transform(t);
                if (a.subpixelBits) subpixelBits = a.subpixelBits;
                if (a.region) regions.push_back(&a);
                name += (name.size() > prefix.size() ? "+" : "") + a.name;
            }
            play(name, t, subpixelBits);
            for (const Alternative* a : regions) {
                const std::vector<uint8_t> r = a->region(t);
                std::vector<uint8_t>& mine = out.back().region;
                if (mine.empty()) mine = r;
                else
                    for (size_t i = 0; i < mine.size(); ++i) mine[i] &= r[i];
            }
        }
    };
    play("ours", trace, 0);
    withAlternatives("", trace);
    if (e.peerTransform) {
        const Trace p = peerTrace(trace, e);
        play("as-the-peer-plays-it", p, 0);
        withAlternatives("as-the-peer-plays-it+", p);
    }
    return out;
}

Comparison compareWithPeer(const std::vector<OursImage>& images, const raster::Framebuffer& peer,
                           const Explanation& e) {
    if (images.empty()) throw Error("conform: no image of ours to compare");
    Comparison c;
    const auto b = peer.color();
    for (const OursImage& im : images)
        if (im.image.color().size() != b.size() || (!im.region.empty() && im.region.size() != b.size()))
            throw Error("conform: '" + im.name + "' is not the peer's size");
    c.pixels = b.size();
    std::vector<size_t> explained(images.size(), 0);
    auto explains = [&](const OursImage& im, size_t i) {
        return (im.region.empty() || im.region[i]) && maxChannelDiff(im.image.color()[i], b[i]) <= e.smallDiff;
    };
    for (size_t i = 0; i < b.size(); ++i) {
        const int d = maxChannelDiff(images[0].image.color()[i], b[i]);
        c.differing += d != 0;
        c.maxDiff = std::max(c.maxDiff, d);
        if (d <= e.smallDiff) continue;
        ++c.beyond;
        size_t k = 1;
        while (k < images.size() && !explains(images[k], i)) ++k;
        if (k < images.size()) {
            ++explained[k];
        } else {
            ++c.unexplained;
            if (c.firstUnexplained.size() < 8)
                c.firstUnexplained.emplace_back(int(i % size_t(peer.width())), int(i / size_t(peer.width())));
        }
    }
    for (size_t k = 1; k < images.size(); ++k)
        if (explained[k]) c.explainedBy.emplace_back(images[k].name, explained[k]);
    return c;
}

int runConform(const std::string& goldenDir) {
    namespace fs = std::filesystem;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(goldenDir))
        if (e.path().extension() == ".trace") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw Error("no .trace files in '" + goldenDir + "'");
    std::printf("%-30s %-9s %9s %4s %6s %11s  %s\n", "trace", "result", "differing", "max", "beyond",
                "unexplained", "rounding ≤ N everywhere; beyond it, the documented choice that explains it");
    int failures = 0, compared = 0, oursOnly = 0;
    std::string renderer;
    for (const fs::path& f : files) {
        const std::string name = f.stem().string();
        const Trace trace = raster::readTraceFile(f);
        const Explanation* known = explanationFor(name);
        const Explanation& e = known ? *known : defaultExplanation();
        MesaReplay m = replayOnMesa(peerTrace(trace, e));
        if (!m.unsupported.empty()) {
            const bool unexpected = known != nullptr;
            std::printf("%-30s %-9s %9s %4s %6s %11s  %s%s\n", name.c_str(), unexpected ? "FAIL" : "ours-only",
                        "-", "-", "-", "-", oursOnlyReason(peerTrace(trace, e)).c_str(),
                        unexpected ? " — but this trace has an explanation: it used to be compared" : "");
            if (unexpected) {
                ++failures;
                std::printf("    reproduce: ./retroglass replay %s --backend mesa\n", f.string().c_str());
            }
            ++oursOnly;
            continue;
        }
        if (expectedOursOnly(name)) {
            std::printf("%-30s %-9s Mesa now plays it: give it an explanation in conformance/conform.cpp "
                        "and drop it from the ours-only list\n", name.c_str(), "FAIL");
            ++failures;
        }
        renderer = m.renderer;
        const Comparison c = compareWithPeer(oursAndAlternatives(trace, e), m.framebuffer, e);
        if (!c.pass()) ++failures;
        ++compared;
        std::string explained;
        for (const auto& [alt, n] : c.explainedBy)
            explained += (explained.empty() ? "" : ", ") + std::to_string(n) + " " + alt;
        std::printf("%-30s %-9s %9zu %4d %6zu %11zu  ≤ %d: %s\n", name.c_str(), c.pass() ? "ok" : "FAIL",
                    c.differing, c.maxDiff, c.beyond, c.unexplained, e.smallDiff, e.rounding.c_str());
        if (!e.cause.empty())
            std::printf("%-30s %-9s %9s %4s %6s %11s  beyond: %s (docs/hardware.md: %s)%s\n", "", "", "", "", "",
                        "", e.cause.c_str(), e.section.c_str(),
                        explained.empty() ? "" : ("; explained here: " + explained).c_str());
        if (!c.pass()) {
            std::string at;
            for (auto [x, y] : c.firstUnexplained) at += " (" + std::to_string(x) + ", " + std::to_string(y) + ")";
            std::printf("    unexplained at%s%s\n    reproduce: ./retroglass replay %s --out ours.png && "
                        "./retroglass replay %s --backend mesa --out mesa.png\n",
                        at.c_str(), c.unexplained > c.firstUnexplained.size() ? " …" : "", f.string().c_str(),
                        f.string().c_str());
        }
    }
    std::printf("\n%d compared against %s, %d ours-only, %d failing (a pixel no documented choice explains, "
                "or not compared/ours-only as listed)\n",
                compared, renderer.empty() ? "Mesa" : renderer.c_str(), oursOnly, failures);
    return failures ? 1 : 0;
}

}  // namespace rg::conformance
