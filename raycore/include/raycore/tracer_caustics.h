// The photon-traced reference for 002 §7's caustics: photons shot from each point light
// through each glass object's exact geometry (Embree), refracted in and out by Snell's law
// at the interpolated normals (total internal reflection followed inside), or reflected
// once by each mirror object (its reflectance, constant or Schlick's), met with the
// board plane, and splatted into a light map over the board's texture space with the
// Gaussian kernel of the emulated splats (demos/impostors/impostor_caustics.h). Many more
// photons than the emulated photon maps, the same framing of each object from the light,
// the same power model, so that what differs is the geometry: the refractor-map search
// against exact intersections.
//
// As 002 §7 does, the photons see one object at a time: each object is traced in an Embree
// scene of its own (other objects, the board included, neither block nor refract a photon),
// and only the board plane receives them.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "raycore/image.h"
#include "raycore/scene.h"

namespace rg::ray {

// The receiving plane y = y, its texture space u = uv[0]·x + uv[1]·z + uv[2],
// v = uv[3]·x + uv[4]·z + uv[5], and its extent in x and z.
struct CausticBoard {
    float y = 0.0f;
    float uv[6] = {0.125f, 0, 0.5f, 0, 0.125f, 0.5f};
    glm::vec2 lo{-4.0f}, hi{4.0f};
};

struct CausticTraceOptions {
    int lightMapSize = 512;       // the light map's edge, texels
    int photonsPerAxis = 128;     // photons per object and light: n × n over its framing
    float sigmaTexels = 1.5f;     // the splat kernel's σ; radius 3σ, normalised over the disc
    int maxInterfaces = 8;        // refractions and internal reflections followed per photon
    CausticBoard board;
    std::vector<uint32_t> objects;  // Scene::objects shooting photons (glass and mirrors; others are skipped)
};

struct CausticTraceResult {
    Image lightMap;               // rgb: the caustic irradiance on the board
    double boardPower = 0.0;      // Σ of the photons' power (mean of rgb) that reached the board
    int64_t photons = 0;          // shot at an object's framing
    int64_t boardHits = 0;
    // Photons that met their object and did not reach the board, by why: no exit found
    // inside (a leak), still inside after maxInterfaces, leaving upward or level, landing
    // off the board.
    int64_t objectHits = 0, lostInside = 0, lostInterfaces = 0, lostUpward = 0, lostOffBoard = 0;
};

// Each light × object: a camera at the light aimed at the object's world bounding-box
// centre, square, its half-angle tangent the largest |x|/z, |y|/z of the box's corners times
// 1.02; one photon through each of n × n image-plane cells' centres, power I·r²·cos³θ·a
// (a the cell's area at distance 1) times Schlick's 1 − F at the entry and
// transmittance^length inside. Deterministic: photons are traced in parallel per
// (light, object) and splatted in that order, one thread, in double.
CausticTraceResult traceCausticLightMap(const Scene& scene, const CausticTraceOptions& options);

}  // namespace rg::ray
