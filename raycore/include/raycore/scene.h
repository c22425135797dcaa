// raycore::Scene — the one scene description both renderers draw: meshes (with parts),
// objects placing them with a transform and a material, textures, cameras, point lights,
// the environment, and named viewpoint paths. Plain data; the ray tracer builds its Embree
// acceleration structure from it (accel.h), the rasterizer demos read the meshes directly.
#pragma once

#include <glm/glm.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "raycore/camera.h"
#include "raycore/image.h"
#include "raycore/material.h"
#include "raycore/mesh.h"
#include "raycore/texture.h"

namespace rg::ray {

enum class EnvironmentKind { Constant, Gradient, Image };

// Radiance arriving from infinitely far away along a direction that leaves the scene.
struct Environment {
    EnvironmentKind kind = EnvironmentKind::Constant;
    glm::vec3 color{0.0f};                       // Constant
    glm::vec3 zenith{0.3f, 0.5f, 0.9f};          // Gradient: +y, horizon and −y colours
    glm::vec3 horizon{0.9f, 0.9f, 0.95f};
    glm::vec3 ground{0.25f, 0.22f, 0.2f};
    std::string path;                            // Image: equirectangular (lat-long) file
    float intensity = 1.0f;                      // Image: scale
    std::shared_ptr<const Image> image;

    glm::vec3 lookup(glm::vec3 dir) const;
};

struct PointLight {
    std::string name;
    glm::vec3 position{0.0f, 5.0f, 0.0f};
    glm::vec3 intensity{1.0f};  // radiance scale, no distance fall-off (see lighting.cpp)
    friend bool operator==(const PointLight&, const PointLight&) = default;
};

struct Object {
    std::string name;
    uint32_t mesh = 0;      // index into Scene::meshes
    uint32_t material = 0;  // index into Scene::materials
    glm::mat4 transform{1.0f};
};

struct Scene {
    std::string name;
    std::vector<Mesh> meshes;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Object> objects;
    std::vector<Camera> cameras;
    std::vector<PointLight> lights;
    std::vector<ViewpointPath> viewpointPaths;
    Environment environment;
    glm::vec3 ambient{0.2f};  // diffuse surfaces receive ambient·albedo unshadowed
    std::filesystem::path sourceFile;  // the JSON file it came from, if any

    // Lookups by name; -1 when absent.
    int findObject(const std::string& name) const;
    int findMaterial(const std::string& name) const;
    int findTexture(const std::string& name) const;
    int findCamera(const std::string& name) const;
    int findViewpointPath(const std::string& name) const;

    // Adds and returns the index.
    uint32_t addMesh(Mesh m);
    uint32_t addMaterial(Material m);
    uint32_t addTexture(Texture t);
    uint32_t addObject(std::string name, uint32_t mesh, uint32_t material,
                       const glm::mat4& transform = glm::mat4(1.0f));

    // The mesh of an object with its transform applied, for the rasterizer demos.
    Mesh worldMesh(uint32_t object) const;
};

// Checks references and meshes. Problems that make rendering impossible (a material or
// mesh index out of range, NaN positions, an empty mesh) raise rg::Error naming the object;
// doubtful ones (glass on a mesh that is not closed) are returned as warnings.
std::vector<std::string> validateScene(const Scene& scene);

}  // namespace rg::ray
