// Texture-coordinate generation and the texture matrix, per vertex
// (docs/hardware.md, "Coordinate generation").
#pragma once

#include <array>
#include <cstdint>

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

namespace rg::tex {

struct VertexEye;

enum class TexGenMode : uint8_t {
    // Direct3D 7 D3DTSS_TEXCOORDINDEX flags
    PassThru,                      // D3DTSS_TCI_PASSTHRU: the vertex's own coordinates
    CameraSpaceNormal,             // D3DTSS_TCI_CAMERASPACENORMAL: (nx, ny, nz, 1)
    CameraSpacePosition,           // D3DTSS_TCI_CAMERASPACEPOSITION: (x, y, z, 1)
    CameraSpaceReflectionVector,   // D3DTSS_TCI_CAMERASPACEREFLECTIONVECTOR: (rx, ry, rz, 1)
    // OpenGL 1.2 glTexGen (+ ARB_texture_cube_map's two modes)
    ObjectLinear,                  // per component: dot(objectPlane, object position)
    EyeLinear,                     // per component: dot(eyePlane, eye position)
    SphereMap,                     // GL 1.2 §2.10.4
    ReflectionMap,                 // REFLECTION_MAP_ARB: same vector as the D3D7 mode
    NormalMap,                     // NORMAL_MAP_ARB: same vector as the D3D7 mode
};

struct TexGenState {
    TexGenMode mode = TexGenMode::PassThru;
    // ObjectLinear/EyeLinear planes for s, t, r, q. Eye planes are given in eye space
    // (GL transforms them by the inverse modelview when specified; the application does).
    std::array<glm::vec4, 4> planes{glm::vec4(1, 0, 0, 0), glm::vec4(0, 1, 0, 0),
                                    glm::vec4(0, 0, 1, 0), glm::vec4(0, 0, 0, 1)};
    // The texture matrix (D3DTRANSFORMSTATE_TEXTUREn / GL_TEXTURE), applied to the
    // column vector (s, t, r, q) when enabled; projection (the q divide) happens per pixel.
    bool matrixEnabled = false;
    glm::mat4 matrix{1.0f};
    // The per-pixel divide of (s, t, r) by q for 1D/2D/3D textures: D3DTTFF_PROJECTED in
    // Direct3D 7 (off by default, so two-component coordinates with q = 0 are fine);
    // OpenGL always divides, so GL-style code sets it and submits q = 1. Cube maps
    // ignore it (a direction needs no divide) and 4D textures use q as a coordinate.
    bool projected = false;
};

// Generation then the texture matrix. `in` is the vertex's submitted coordinate set.
glm::vec4 generateTexCoord(const TexGenState& g, const VertexEye& v, const glm::vec4& in);
// The reflection vector both APIs define: u = normalize(eye position), r = u − 2(n·u)n.
glm::vec3 eyeReflectionVector(const VertexEye& v);

}  // namespace rg::tex
