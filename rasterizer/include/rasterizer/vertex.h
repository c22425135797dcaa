// Vertices as the application submits them (a superset of the Direct3D 7 FVF formats).
#pragma once

#include <array>
#include <cstdint>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "core/color.h"
#include "texunit/texture_units.h"

namespace rg::raster {

struct Vertex {
    // Untransformed: object-space (x, y, z, 1), transformed by world, view, projection.
    // Pre-transformed (D3DFVF_XYZRHW): (x, y) in window pixels, z in [0, 1], and
    // w = RHW, the reciprocal of the homogeneous w (used for perspective correction).
    glm::vec4 position{0.0f, 0.0f, 0.0f, 1.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    Rgba8 diffuse{255, 255, 255, 255};
    Rgba8 specular{0, 0, 0, 0};
    std::array<glm::vec4, tex::kMaxTexCoordSets> tex{};
};

// D3DFVF_XYZ | D3DFVF_DIFFUSE: the 16-byte vertex of a Direct3D 7 vertex buffer for an
// unlit, untextured mesh, an object-space position and a diffuse colour (as an OpenGL
// program would hand over a float xyz array and an unsigned-byte colour array). A draw of
// these is the draw of the Vertex toVertex gives, byte for byte; the fast path reads the
// 16 bytes instead of Vertex's 164 (Device::draw).
struct VertexXyzDiffuse {
    glm::vec3 position{0.0f, 0.0f, 0.0f};
    Rgba8 diffuse{255, 255, 255, 255};
};
static_assert(sizeof(VertexXyzDiffuse) == 16);

// The Vertex a VertexXyzDiffuse stands for: w = 1, Vertex's defaults elsewhere (normal
// (0, 0, 1), specular 0, texture coordinates 0).
inline Vertex toVertex(const VertexXyzDiffuse& v) {
    Vertex out;
    out.position = glm::vec4(v.position, 1.0f);
    out.diffuse = v.diffuse;
    return out;
}

enum class VertexSpace : uint8_t { Untransformed, Pretransformed };

enum class Primitive : uint8_t { TriangleList, TriangleStrip, TriangleFan };

}  // namespace rg::raster
