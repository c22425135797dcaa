// The local lens objects of a scene (000 §1, §3): each glass object (two terms, reflection
// and refraction) and each mirror (one term) is traced at run time through its own
// geometry only, and sees the rest of the scene through its layered EMs.
//
//   Scene ──▶ LensScene ──▶ LensObject: welded world mesh (the edge hash's topology),
//                │                       EM origin (area-weighted centroid), local Accel
//                └──▶ the full Accel (precompute, reference, uniform ray tracer) and the
//                     visibility Accel (every lens object: the run-time visibility rays)
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "raycore/accel.h"
#include "raycore/scene.h"

namespace rg::hybrid {

struct LensObject {
    std::string name;
    uint32_t object = 0;        // index in the full scene
    bool twoTerms = true;       // glass: reflection and refraction; mirror: reflection only
    int layers = 3;             // the layer count asked for (000 §6: teapot 3, cup 2)
    // World-space mesh. Vertices at a bit-identical position merge when their normals
    // agree within kCreaseDegrees (Newell's patches each carry their own copies of shared
    // corners; the normal is the normalised sum), and stay apart across a crease (the
    // cup's rim): a vertex is a position and the normal one side of a crease sees there.
    // positionId names the position alone: the edge hash of 000 §5 keys edges by
    // positions, so the two sides of a crease share their edges' midpoints and no crack
    // opens along it.
    std::vector<glm::vec3> positions, normals;
    std::vector<uint32_t> indices;
    std::vector<uint32_t> positionId;   // per vertex
    uint32_t positionCount = 0;
    bool closedManifold = true;
    glm::vec3 origin{0.0f};     // EM origin and LBG origin: area-weighted centroid (000 §4.2)
    float boundingRadius = 0;   // largest |vertex − origin|
    // The object alone (its own sub-scene, object 0 there), for the run-time rays.
    std::unique_ptr<ray::Scene> localScene;
    std::unique_ptr<ray::Accel> local;
    const ray::Material& material() const;
};

struct LensSceneOptions {
    std::vector<std::string> objects;  // lens objects by name; empty: every glass and mirror
    int glassLayers = 3, mirrorLayers = 2;
    bool countingTwins = false;        // also build the counting Accels (000 §6 table)
};

class LensScene {
  public:
    // rg::Error when the scene has no glass or mirror object (or a named one is missing,
    // diffuse, or has no triangle). Warnings (an open or non-manifold glass mesh, named)
    // are collected in warnings().
    LensScene(ray::Scene scene, const LensSceneOptions& options);

    const ray::Scene& scene() const { return scene_; }
    const ray::Accel& accel() const { return *accel_; }
    const ray::Accel& visibility() const { return *visibility_; }
    std::vector<LensObject>& objects() { return objects_; }
    const std::vector<LensObject>& objects() const { return objects_; }
    const std::vector<std::string>& warnings() const { return warnings_; }

    // The counting twins (built on first use): the full scene, each lens object alone, all
    // lens objects together. Never used in a timed path.
    const ray::Accel& countingAccel();
    const ray::Accel& countingLocal(size_t lens);
    const ray::Accel& countingVisibility();

  private:
    ray::Scene scene_;
    std::unique_ptr<ray::Accel> accel_;
    std::unique_ptr<ray::Scene> lensOnly_;
    std::unique_ptr<ray::Accel> visibility_;
    std::vector<LensObject> objects_;
    std::vector<std::string> warnings_;
    std::unique_ptr<ray::Accel> countingAccel_, countingVisibility_;
    std::vector<std::unique_ptr<ray::Accel>> countingLocal_;
};

constexpr float kCreaseDegrees = 30.0f;

// Merges bit-identical positions: `remap` gets each vertex's welded index.
void weldPositions(const std::vector<glm::vec3>& positions, std::vector<uint32_t>& remap,
                   std::vector<glm::vec3>& welded);

}  // namespace rg::hybrid
