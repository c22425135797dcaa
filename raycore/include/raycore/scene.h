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
    std::string path;                            // Image: equirectangular (lat-long) file,
                                                 // as written in the scene ("blender:forest")
    float intensity = 1.0f;                      // Image: scale
    float rotateDegrees = 0.0f;                  // Image: turn about +y (below)
    std::shared_ptr<const Image> image;

    // Image orientation (docs/scene-format.md): a unit direction d reads the image at
    //     u = 1/2 + atan2(d.x, −d.z) / 2π      (the centre column is seen along −z,
    //     v = acos(d.y) / π                      three quarters of the width along +x)
    // bilinearly, u wrapping and v clamped (v = 0, the top row, is straight up), after
    // turning d by −rotateDegrees about +y: with rotateDegrees = a, what was seen along −z
    // is seen along (−sin a, 0, −cos a).
    glm::vec3 lookup(glm::vec3 dir) const;
};

// The CC0 equirectangular worlds of Debian's blender-data package (studiolights/world:
// city, courtyard, forest, interior, night, studio, sunrise, sunset; 1024×512 EXR). The
// folder is /usr/share/blender/datafiles/studiolights/world unless the environment
// variable RETROGLASS_BLENDER_WORLDS names another.
std::filesystem::path blenderWorldDir();
// "forest" → the path of forest.exr there. Raises rg::Error naming the package to install
// when the folder is missing, and listing the names present when `name` is not one.
std::filesystem::path blenderWorldPath(const std::string& name);
// Reads an equirectangular environment image: rg::Error naming the file and the texel when
// it cannot be read or holds a NaN or infinite value (a ray tracer would spread it).
// Negative values are set to 0: HDR photographs carry slightly negative texels from colour
// conversion (blender-data's worlds down to −0.004), and radiance cannot be negative.
Image readEnvironmentImage(const std::filesystem::path& path);

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

// The objects `keep` of `scene` alone, in that order (object i of the result is
// scene.objects[keep[i]]): 000 §5's local geometry, which the run-time rays trace instead
// of the whole scene. Meshes, materials, textures, lights and the environment are copied
// whole so that indices stay valid. rg::Error for an index out of range or an empty list.
Scene subScene(const Scene& scene, const std::vector<uint32_t>& keep);

// Checks references and meshes. Problems that make rendering impossible (a material or
// mesh index out of range, NaN positions, an empty mesh, a mesh or object without a
// triangle of non-zero area or with an extent not finite in float arithmetic, as given or
// as its transform places it: validatePlacedMesh in mesh.h; the objects together spanning
// such an extent) raise rg::Error naming the scene and the object; doubtful ones (glass on a
// mesh that is not closed) are returned as warnings. Messages start with `label`, or else
// the scene's sourceFile, or else "scene 'name'".
std::vector<std::string> validateScene(const Scene& scene, const std::string& label = {});

}  // namespace rg::ray
