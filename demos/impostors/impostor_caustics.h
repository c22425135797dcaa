// 002 §7's caustics, after Szirmay-Kalos et al. 2005 ([5]), on the emulated geforce8800:
//
//   photon map   per glass or mirror piece and light: the piece rendered from the light (a
//                camera at the light aimed at the piece's bounding box), N × N (32² by
//                default: our choice, the paper gives none). Rasterisation finds the first
//                hit; a mirror reflects there (its reflectance is the photon's power); glass
//                refracts in (Schlick's transmittance 1 − F and the absorption
//                inside are the photon's power), finds the exit in the piece's refractor
//                distance map (the same search as the frame, tracePaths), refracts out and
//                meets the board plane only ("we neglect the fact that the ray might interact
//                with other pieces"). Target 0 (RGBA32F): the photon hit in the board's texture
//                space (u, v), 1 where there is a hit; target 1 (RGBA32F): its power (rgb).
//   splatting    one quad per photon-map texel: the vertex program reads the photon hit and
//                power from the photon map (vertex texture fetch, texelFetch) and places a
//                square of 2·3σ light-map texels about the hit; the fragment program weighs
//                the power by a Gaussian of σ (in light-map texels) normalised so that the
//                splat integrates to the photon's power over the board, added into an
//                RGBA32F caustic light map with ONE, ONE blending (binary32, unclamped). The
//                device blends each pixel's fragments in primitive order, so the sums are the
//                same bytes for any thread count.
//
// The board's shading then adds the caustic irradiance to what the shadows leave
// (CausticDiffuseFP): albedo·texture·(ambient + Σ_i I_i·max(n·l_i, 0)·visibility_i +
// caustic_static + caustic_mover). Shadows multiply (the light maps' visibility), caustics
// add (the light that the glass casters' opaque shadows remove comes back, focused, where
// the pieces send it).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>

#include "impostor_programs.h"
#include "impostor_shading.h"
#include "rasterizer/program.h"
#include "rasterizer/programmable_device.h"

namespace rg::impostors {

// Units of the photon-map program (the piece's refractor distance map) and of the splats.
constexpr int kUnitPhotonRefractor = 0;
constexpr int kUnitPhotonHit = 0, kUnitPhotonPower = 1;
// Units of the caustic board program: DiffuseFP's three and the two caustic maps.
constexpr int kUnitCausticStatic = 3, kUnitCausticMover = 4;
// Splats reach 3σ: beyond it the Gaussian keeps e^(−4.5) ≈ 1.1 % of the power, which the
// normalisation returns to the kept disc.
constexpr float kSplatRadiusSigmas = 3.0f;

// The board plane as the photon hits see it: y = boardY, uv an affine function of (x, z)
// (GridConstants' layout), and the board's extent.
struct PhotonBoard {
    float boardY = 0.0f;
    float uv[6] = {0.125f, 0, 0.5f, 0, 0.125f, 0.5f};
    float lo[2] = {-4, -4}, hi[2] = {4, 4};
};

// Pass 1: a glass piece seen from a point light (varyings of WorldVP: world position,
// normal). Photon power: the light's intensity (raycore's point lights have no fall-off:
// irradiance I across the ray) times the area the photon-map texel covers across the ray,
// r²·cos³θ·a (a: the texel's area on the image plane at distance 1, θ its angle to the
// axis), times 1 − F at the entry and the absorption along the inside path.
struct PhotonFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b11;
    static constexpr uint32_t kUnits = 0b1;
    static constexpr bool kWritesDepth = false;
    ObjectFrame self;
    int32_t iterations = 8;
    float light[3] = {0, 10, 0};
    float intensity[3] = {1, 1, 1};
    float axis[3] = {0, -1, 0};  // the photon camera's viewing direction (unit)
    float texelArea = 1.0f;      // a: (2·tan(fov/2)/N)²
    PhotonBoard board;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using M = typename Q::Mask;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0), nrm = q.varying(1);
        const M live = q.active();
        auto refr = [&q](const V3& d, const M& m) {
            return q.sampleLevel(kUnitPhotonRefractor, V4(d.x, d.y, d.z, F(0.0f)), F(0.0f), m);
        };
        const V3 P(pos.x, pos.y, pos.z);
        const V3 toP = P - splat3<F>(light);
        const F r2 = dot3(toP, toP);
        const V3 V = normalize3(toP);
        const F cosT = dot3(V, splat3<F>(axis));
        const F area = r2 * (cosT * cosT * cosT) * F(texelArea);
        // The photon leaves the piece from exitOrigin along exitDir with the power
        // I·carried·weight (per channel; the glass's product in its earlier order, so its
        // bytes are unchanged).
        V3 exitOrigin, exitDir, carried;
        F weight = area;
        if (self.mirror) {
            // A mirror (002 §7: "refracting and reflecting materials can focus the light"):
            // the photon leaves the rasterised hit along the mirror direction with the
            // mirror's reflectance, constant or Schlick's with it as F0 — as the frame
            // shades the mirror (shadeOwn).
            const V3 n = facing(normalize3(V3(nrm.x, nrm.y, nrm.z)), V);
            exitOrigin = P;
            exitDir = reflect3(V, n);
            const F cosI = -dot3(V, n);
            carried = self.mirrorSchlick ? V3(fresnelSchlick(cosI, self.reflectance[0]),
                                              fresnelSchlick(cosI, self.reflectance[1]),
                                              fresnelSchlick(cosI, self.reflectance[2]))
                                         : splat3<F>(self.reflectance);
        } else {
            // Through the piece: 002 §7 "multiple refraction is calculated by searching in
            // the refractor map" — the frame's own tracing (impostor_shading.h); Schlick's
            // transmittance 1 − F at the entry and the absorption inside.
            const GlassPaths<F, M> g = tracePaths(self, iterations, P, V3(nrm.x, nrm.y, nrm.z), V, live, refr);
            exitOrigin = g.exitOrigin;
            exitDir = g.exitDir;
            carried = g.transmit;
            weight = (F(1.0f) - g.fresnel) * area;
        }
        // The photon hit: the exit ray meets the board plane y = boardY (other pieces
        // neglected), within the board. A photon leaving through a base that stands on the
        // board (its exit at or below the plane) lands where it leaves: t = max(t, 0).
        const F t = max((F(board.boardY) - exitOrigin.y) / exitDir.y, F(0.0f));
        const V3 X = exitOrigin + exitDir * t;
        const F u = (X.x * F(board.uv[0]) + X.z * F(board.uv[1])) + F(board.uv[2]);
        const F v = (X.x * F(board.uv[3]) + X.z * F(board.uv[4])) + F(board.uv[5]);
        const M hit = (exitDir.y < F(0.0f)) & (X.x >= F(board.lo[0])) & (X.x <= F(board.hi[0])) &
                      (X.z >= F(board.lo[1])) & (X.z <= F(board.hi[1]));
        const V3 power = V3(carried.x * F(intensity[0]), carried.y * F(intensity[1]), carried.z * F(intensity[2])) * weight;
        const F zero(0.0f);
        q.output(0, V4(select(hit, u, zero), select(hit, v, zero), select(hit, F(1.0f), zero), zero));
        q.output(1, V4(select(hit, power.x, zero), select(hit, power.y, zero), select(hit, power.z, zero), zero));
    }
};

// A corner of photon (x, y)'s splat quad: six per photon (two triangles), corners ±1.
struct SplatVertex {
    int32_t texel[2] = {0, 0};
    float corner[2] = {0, 0};
};

// Pass 2's vertex program: the photon's hit and power from the photon map (vertex texture
// fetch, units 0 and 1, texelFetch: no filtering) place a square of half-edge R = 3σ
// light-map texels about the hit's texel position (u·M, v·M); a texel without a hit sends
// all six corners to one point outside the viewport (nothing drawn). Varyings: 0 the offset
// from the hit in texels (affine over the square, so each pixel centre gets its own
// offset), 1 the power times the kernel's normalisation 1/(2πσ²·(1 − e^(−R²/2σ²))·A_texel),
// A_texel the world area of a light-map texel: the splat's texels then hold irradiance.
struct SplatVP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kVertexUnits = 0b11;
    float size = 512.0f;  // the light map's edge M, texels
    float radius = 4.5f;  // R = 3σ, texels
    float norm = 1.0f;    // 1/(2πσ²·(1 − e^(−R²/2σ²))·A_texel)
    glm::vec4 operator()(const SplatVertex& sv, raster::Varyings& out, raster::VertexContext& t) const {
        const glm::vec4 hit = t.texelFetch(kUnitPhotonHit, {sv.texel[0], sv.texel[1]});
        const glm::vec4 power = t.texelFetch(kUnitPhotonPower, {sv.texel[0], sv.texel[1]});
        if (!(hit.z > 0.0f)) {
            out[0] = out[1] = glm::vec4(0.0f);
            return {-4.0f, -4.0f, 0.5f, 1.0f};
        }
        const float ox = sv.corner[0] * radius, oy = sv.corner[1] * radius;
        const float x = hit.x * size + ox, y = hit.y * size + oy;
        out[0] = glm::vec4(ox, oy, 0.0f, 0.0f);
        out[1] = glm::vec4(power.x * norm, power.y * norm, power.z * norm, 0.0f);
        return {x * (2.0f / size) - 1.0f, 1.0f - y * (2.0f / size), 0.5f, 1.0f};
    }
};

// Pass 2's fragment program: the Gaussian e^(−r²/2σ²) of the pixel's offset (expNeg), 0
// beyond R (discarded), times the splat's power; alpha the weight alone (the photon density).
struct SplatFP {
    static constexpr int kVaryings = 2;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    float inv2Sigma2 = 1.0f / (2.0f * 1.5f * 1.5f);
    float radius2 = 4.5f * 4.5f;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V4 = typename Q::Vec4;
        const V4 o = q.varying(0), p = q.varying(1);
        const F r2 = o.x * o.x + o.y * o.y;
        q.discard(r2 > F(radius2));
        const F w = expNeg(r2 * F(inv2Sigma2));
        q.output(0, V4(p.x * w, p.y * w, p.z * w, w));
    }
};

// The board with caustics: DiffuseFP's lighting (impostor_programs.h) plus the caustic
// irradiance of units 3 and 4 (static pieces, the mover) on the board's top face.
struct CausticDiffuseFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b11111;
    static constexpr bool kWritesDepth = false;
    DiffuseFP base;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        base.shade(q, [&q, this](const auto& top, V3& light) {
            if (!base.lightMapped) return;
            const V4 cs = q.sample(kUnitCausticStatic, 2), cm = q.sample(kUnitCausticMover, 2);
            const F zero(0.0f);
            light = light + V3(select(top, cs.x + cm.x, zero), select(top, cs.y + cm.y, zero),
                               select(top, cs.z + cm.z, zero));
        });
    }
};

// The six corners of every photon of an n × n photon map, photon (x, y) at 6·(y·n + x):
// the splats' primitive order, which fixes the order of the additive blend at each texel.
std::vector<SplatVertex> splatVertices(int n);

// The draws of this file's programs; their kernels are instantiated in impostor_caustics.cpp.
void drawPhotons(raster::ProgrammableDevice& device, const WorldVP& vp, const PhotonFP& fp,
                 std::span<const ImpostorVertex> vertices, std::span<const uint32_t> indices);
void drawSplats(raster::ProgrammableDevice& device, const SplatVP& vp, const SplatFP& fp,
                std::span<const SplatVertex> vertices);
void drawCausticBoard(raster::ProgrammableDevice& device, const WorldVP& vp, const CausticDiffuseFP& fp,
                      std::span<const ImpostorVertex> vertices, std::span<const uint32_t> indices);

// Registers the programs above under "impostors/caustics/…" (traces); idempotent.
void registerCausticPrograms();

}  // namespace rg::impostors
