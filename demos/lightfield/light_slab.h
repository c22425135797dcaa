// Two-plane light fields (Heidrich et al. 1999 §3, after Levoy & Hanrahan and Gortler et
// al.): a slab of two parallel planes, z = const, the (s, t) plane of eye points and the
// (u, v) plane of the image window. The paper's names (Gortler's): (s, t) = eye points,
// (u, v) = the window; LightPack swaps them.
//
//   eye points (s_i, t_j) = stMin + (i, j)·(stMax − stMin)/(S − 1, T − 1)   grid vertices
//   window samples u_k   = uvMin + (k + ½)·(uvMax − uvMin)/U                 texel centres
//
// A light field is S·T slices of U·V samples: slice (i, j) is the perspective image from
// eye point (i, j) through the window, so it is directly the 2D texture the Gortler
// reconstruction maps (texel k's centre is the texture coordinate (k + ½)/U). Storage is
// [t][s][v][u][channel], 8 bits a channel: RGB8 radiance or colour-coded directions, RGBA8
// for 4D coordinates (§4.1). The parameter file (JSON, docs in writeLightField) says all
// of this; readLightField refuses a truncated, inconsistent or object-cutting one with an
// rg::Error naming the file.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "raycore/camera.h"
#include "raycore/mesh.h"

namespace rg::lightfield {

struct LightSlab {
    float stZ = 4.0f;   // the plane of eye points
    float uvZ = 0.0f;   // the window plane
    glm::vec2 stMin{-1.0f}, stMax{1.0f};
    glm::vec2 uvMin{-1.5f}, uvMax{1.5f};
    int S = 8, T = 8, U = 64, V = 64;

    glm::vec3 eyePoint(int i, int j) const;
    // The world point of window coordinates (u, v) in [0, 1]² (0 and 1 the window's edges).
    glm::vec3 windowPoint(float u, float v) const;
    // The ray stored at sample (i, j, k, l): from eye point (i, j) through texel (k, l)'s
    // centre (unit direction).
    ray::Ray sampleRay(int i, int j, int k, int l) const;
    // Where a line meets both planes, as world (s, t, u, v); nullopt when parallel to them.
    std::optional<glm::vec4> intersect(const glm::vec3& origin, const glm::vec3& dir) const;
    // World (s, t, u, v) → 4D texture coordinates in [0, 1]: u, v as the window's fraction
    // (texel centres at (k + ½)/U), s, t so that eye point i sits at texel centre (i + ½)/S.
    glm::vec4 textureCoords(const glm::vec4& stuv) const;
    size_t samples() const { return size_t(S) * T * U * V; }
};

// How the samples' bytes are to be read.
enum class LightFieldContent : uint8_t {
    Radiance,              // RGB8: colour, as rendered
    ParaboloidCoordinates, // RGB8: R, G = dual-paraboloid (s, t)·255, B = 0 front / 255 back (§4)
    SlabCoordinates,       // RGBA8: (u, v, s, t) of a second light field as 4D texture coordinates (§4.1)
};
const char* contentName(LightFieldContent c);

struct LightField {
    LightSlab slab;
    LightFieldContent content = LightFieldContent::Radiance;
    int channels = 3;
    std::vector<uint8_t> data;
    std::optional<ray::Bounds> objectBounds;  // what the slab was built around

    size_t sliceBytes() const { return size_t(slab.U) * slab.V * size_t(channels); }
    size_t offset(int i, int j, int k, int l) const {
        return (((size_t(j) * slab.S + size_t(i)) * slab.V + size_t(l)) * slab.U + size_t(k)) * size_t(channels);
    }
    const uint8_t* slice(int i, int j) const { return data.data() + offset(i, j, 0, 0); }
    uint64_t bytes() const { return data.size(); }
};

// Checks a slab: positive resolutions (S, T ≥ 2: eye points span a grid), power-of-two
// U and V (texture extents on the SGI profiles), finite planes that do not coincide,
// windows of positive extent. And, with `object`: the planes bound the object — it lies
// wholly beyond the eye-point plane, and every ray from an eye point through it crosses
// the window (its bounding box seen from the four corner eye points projects inside).
// rg::Error starting with `what`.
void validateSlab(const LightSlab& slab, const std::optional<ray::Bounds>& object, const std::string& what);

// The parameter file and its data: `path` (JSON) and `path` with ".bin" (the samples).
//
//   {"format": "retroglass-light-slab", "version": 1,
//    "content": "radiance" | "paraboloid-coordinates" | "slab-coordinates",
//    "texel": "RGB8" | "RGBA8",
//    "st_plane": {"z": 4, "min": [-1, -1], "max": [1, 1], "samples": [8, 8]},
//    "uv_plane": {"z": 0, "min": [-1.5, -1.5], "max": [1.5, 1.5], "samples": [64, 64]},
//    "object_bounds": {"min": [x, y, z], "max": [x, y, z]},      (optional)
//    "data": "NAME.bin", "data_bytes": S·T·U·V·channels,
//    "layout": "t, s, v, u, channel; 8 bits each"}
void writeLightField(const std::filesystem::path& path, const LightField& lf);
// Reads and validates: the JSON (malformed, truncated, a missing or mistyped key), the
// slab (validateSlab), the texel against the content, data_bytes against S·T·U·V·channels
// and against the data file's size. Every error names the file.
LightField readLightField(const std::filesystem::path& path);
// The JSON alone (the fuzz target): the same checks without the data file.
LightField parseLightFieldParams(const std::string& json, const std::string& what, uint64_t* dataBytes = nullptr,
                                 std::string* dataName = nullptr);

}  // namespace rg::lightfield
