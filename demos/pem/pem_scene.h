// The reflector as the PEM viewer sees it: one object of a raycore scene split into the
// parts that get their own layered EMs (001 §6: the lid apart from the spout, body and
// handle), with each part's EM geometries and convex-hull classification.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "em_geometry.h"
#include "raycore/layers_pem.h"
#include "raycore/scene.h"

namespace rg::pem {

struct PemPart {
    std::string name;               // "lid", "body", or the object name
    ray::Segment segment;
    // World-space geometry of the part alone (its own vertex arrays).
    std::vector<glm::vec3> positions, normals;
    std::vector<uint32_t> indices;
    // PTM baseline: a texture atlas over the surface. Each connected component of the
    // part (a Bézier patch of the teapot) gets a square tile; its uvs map into the tile.
    std::vector<glm::vec2> atlasUv;
    int atlasTiles = 0;
    // Per triangle: 1 when it lies on the object's convex hull. Such triangles can never
    // show a self-reflection and are drawn with the distant EM only (001 §4).
    std::vector<uint8_t> onHull;
    glm::vec3 emOrigin{0.0f};       // area-weighted mean of triangle centroids
    EmGeometry local;               // bounding ellipsoid (001 §4 "Layered EMs")
    EmGeometry distant;             // box map: bottom on the support plane, sides at the
                                    // mean distance to the environment
    EmGeometry infinite;            // sphere at infinity (single-EM baseline)
};

struct PemSceneOptions {
    std::string object = "teapot";
    std::vector<std::string> parts = {"body", "lid"};  // empty: the whole object
    int boxRays = 4096;             // rays that measure the distance to the environment
};

struct PemScene {
    ray::Scene scene;
    int object = -1;
    std::vector<PemPart> parts;
    float supportPlaneY = 0.0f;     // the floor the object stands on (lowest vertex)
    size_t triangles = 0;           // of the whole reflector
    size_t hullTriangles = 0;
};

// The reflector of any scene: its first mirror object, split into body and lid when its
// mesh names both parts (the teapot). rg::Error when the scene has no mirror object.
PemSceneOptions reflectorOptionsFor(const ray::Scene& scene);

// Raises rg::Error when the object or a part does not exist, or the object is not a mirror.
PemScene makePemScene(ray::Scene scene, const PemSceneOptions& options);

// Exact convex-hull test per triangle: the triangle's plane supports the point set
// (max over points of n·(q − p0) ≤ ε). O(triangles × points), parallel.
// Connected components of a triangle mesh (shared vertex indices), numbered from 0 in
// order of first appearance; returns the component of each vertex.
std::vector<int> connectedComponents(size_t vertexCount, const std::vector<uint32_t>& indices,
                                     int* count);

std::vector<uint8_t> classifyHullTriangles(const std::vector<glm::vec3>& points,
                                           const std::vector<glm::vec3>& positions,
                                           const std::vector<uint32_t>& indices, float epsilon);

}  // namespace rg::pem
