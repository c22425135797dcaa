// Building the light fields by ray tracing (Heidrich et al. 1999 §1, §4, §4.1) and the
// environment maps they are lit with.
//
// Geometry light fields replace "the RGB color triplet with four numbers representing a new
// ray direction" (§1): per sample the path through the object (refraction with total
// internal reflection, one greedy child: "we will ignore ... that the ray may split", or a
// mirror bounce) and its outgoing ray, colour-coded either as dual-paraboloid coordinates
// for an environment map (§4, [10]: h_x/h_z, h_y/h_z = v_x/(1 + v_z), v_y/(1 + v_z)) or as
// the (u, v, s, t) where it crosses a second light field's slab (§4.1). Rays that miss the
// object store their own direction: the background then comes out of the same lookup.
#pragma once

#include <array>
#include <functional>
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "core/color.h"
#include "light_slab.h"
#include "raycore/accel.h"
#include "raycore/scene.h"
#include "texunit/texture.h"

namespace rg::lightfield {

// ---- dual-paraboloid coordinates (Heidrich & Seidel 1998, texunit/paraboloid_mapping.h) --
// Front map for v_z ≥ 0: (x, y) = (v_x, v_y)/(1 + v_z); back map (unmirrored, the pinned
// choice of docs/hardware.md): (v_x, v_y)/(1 − v_z); s = (x + 1)/2, t = (y + 1)/2.
struct ParaboloidCoord {
    float s = 0.5f, t = 0.5f;
    int side = 0;  // 0 front (+z), 1 back
};
ParaboloidCoord toParaboloid(glm::vec3 dir);
glm::vec3 fromParaboloid(float s, float t, int side);  // unit direction (continued past the rim)
// RGB8 of a direction: round(255·s), round(255·t), 0 or 255 for the side.
std::array<uint8_t, 3> encodeParaboloid(glm::vec3 dir);

// A dual-paraboloid environment map, 8 bits per channel: texel (x, y) of side k at
// rgb[((k·size + y)·size + x)·3]; texel centres at s = (x + ½)/size. Outside the unit disk
// each map continues the inverse formula (directions of the other hemisphere), so
// filtering across the rim reads sensible colours.
struct ParaboloidMap {
    int size = 0;
    std::vector<uint8_t> rgb;
    Rgba8 texel(int side, int x, int y) const {
        const uint8_t* p = rgb.data() + ((size_t(side) * size + size_t(y)) * size + size_t(x)) * 3;
        return {p[0], p[1], p[2], 255};
    }
};
// Resamples an environment (radiance·exposure, clamped at 1, round(255·v)) with n×n
// samples per texel.
ParaboloidMap makeParaboloidMap(const ray::Environment& env, int size, float exposure, int n = 2);
// The same from any radiance function of a direction (a near scene seen from a point).
ParaboloidMap makeParaboloidMap(const std::function<glm::vec3(glm::vec3)>& radiance, int size, int n, int threads);
// A glossy copy: each texel the cos^exponent-weighted mean of `map` around its direction
// (the prefiltered environment map of §4.2 / [11]).
ParaboloidMap prefilterPhong(const ParaboloidMap& map, int outSize, float exponent, int threads);
// The bilinear float lookup of `map` along a direction (the ray tracer's reading of the same
// 8-bit map: isolates the light field's error from the map's).
glm::vec3 sampleParaboloidMap(const ParaboloidMap& map, glm::vec3 dir);
// The map as the 3D texture the pixel-texture route samples: size × size × 2 RGB8, side
// along r (B = 0 → r = 0 the front, B = 255 → r = 1 the back), one level.
std::shared_ptr<tex::Texture> uploadParaboloidMap(tex::TextureMemory& memory, const ParaboloidMap& map);

// ---- paths through the object -----------------------------------------------------------
enum class Interaction { Refract, Reflect };

struct ExitRay {
    bool hit = false;         // the ray met the object
    glm::vec3 origin{0.0f};   // where the path leaves it (the ray's origin when it missed)
    glm::vec3 dir{0.0f};
    float fresnel = 0.0f;     // reflectance at the first hit (exact dielectric)
    glm::vec3 normal{0.0f};   // at the first hit, facing the ray
};
// Refract: Snell's law at every interface, reflection only under total internal reflection,
// at most `maxSegments` segments inside (then it leaves along its last direction).
// Reflect: one mirror bounce. `object` is the Scene::objects index of the object.
ExitRay traceExit(const ray::Accel& accel, uint32_t object, const ray::Ray& ray, Interaction mode, float ior,
                  int maxSegments = 8);

// ---- the light fields -------------------------------------------------------------------
LightField captureParaboloidField(const ray::Accel& accel, uint32_t object, const LightSlab& slab, Interaction mode,
                                  float ior, int threads);
// Exit rays as 4D coordinates of `lighting`'s slab (RGBA8 = u, v, s, t · 255, clamped).
LightField captureSlabField(const ray::Accel& accel, uint32_t object, const LightSlab& slab, const LightSlab& lighting,
                            Interaction mode, float ior, int threads);
// Radiance along each sample ray, from `radiance(ray)` (RGB8, clamped, round(255·v)).
LightField captureRadianceField(const LightSlab& slab, const std::function<glm::vec3(const ray::Ray&)>& radiance,
                                int threads);

}  // namespace rg::lightfield
