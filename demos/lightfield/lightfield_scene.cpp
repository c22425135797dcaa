// The scenes of the lightfield reproduction and its viewer demo.
#include "lightfield_scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include "core/error.h"
#include "raycore/scene_json.h"
#include "raycore/shapes.h"

namespace rg::lightfield {

// ---- the scene -------------------------------------------------------------------------------
// A glass torus (the paper's Fig. 4 object; Fig. 3's is not named), tilted 60° towards the
// viewer, at the origin; IOR 1.5. Or a user's first glass or mirror object (--scene).

static ray::Environment loadBlender(const std::string& name) {
    ray::Environment e;
    e.kind = ray::EnvironmentKind::Image;
    e.path = "blender:" + name;
    e.image = std::make_shared<ray::Image>(ray::readEnvironmentImage(ray::blenderWorldPath(name)));
    return e;
}

// Exposure that maps the environment's mean luminance to 0.3 (an 8-bit framebuffer clips
// the rest, as pem does).
float autoExposure(const ray::Environment& env) {
    if (env.kind != ray::EnvironmentKind::Image || !env.image) return 1.0f;
    double sum = 0;
    const ray::Image& im = *env.image;
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            const glm::vec3 c = im.rgb(x, y);
            sum += 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
        }
    const double mean = sum / double(im.width * im.height) * env.intensity;
    return mean > 0 ? float(0.3 / mean) : 1.0f;
}

LfScene makeScene(const std::string& file) {
    LfScene s;
    if (file.empty()) {
        ray::Material glass;
        glass.name = "glass";
        glass.type = ray::MaterialType::Glass;
        glass.ior = 1.5f;
        const uint32_t mesh = s.scene.addMesh(ray::makeTorus(1.0f, 0.35f, 96, 48));
        const uint32_t mat = s.scene.addMaterial(glass);
        s.object = s.scene.addObject("torus", mesh, mat, glm::rotate(glm::mat4(1.0f), glm::radians(60.0f), glm::vec3(1, 0, 0)));
        s.envA = loadBlender("interior");  // stands in for the café of [7]
        s.envB = loadBlender("courtyard");
        s.envAName = "blender:interior";
        s.envBName = "blender:courtyard";
        s.description = "glass torus (major radius 1, minor 0.35, IOR 1.5) tilted 60°";
    } else {
        std::vector<std::string> warnings;
        s.scene = ray::loadSceneByName(file, &warnings);
        bool found = false;
        for (size_t i = 0; i < s.scene.objects.size() && !found; ++i) {
            const ray::Material& m = s.scene.materials.at(s.scene.objects[i].material);
            if (m.type == ray::MaterialType::Glass || m.type == ray::MaterialType::Mirror) {
                s.object = uint32_t(i);
                s.mode = m.type == ray::MaterialType::Glass ? Interaction::Refract : Interaction::Reflect;
                s.ior = m.ior;
                found = true;
            }
        }
        if (!found) throw Error("lightfield: scene '" + file + "' has no glass or mirror object to build light fields of");
        // The object alone, centred at the origin and scaled to the built-in torus' size:
        // the slabs and cameras are laid out for that.
        ray::Mesh m = s.scene.worldMesh(s.object);
        const ray::Bounds b = ray::computeBounds(m);
        const float r = glm::length(b.hi - b.lo) * 0.5f;
        const glm::mat4 norm = glm::scale(glm::mat4(1.0f), glm::vec3(1.3f / r)) * glm::translate(glm::mat4(1.0f), -b.center());
        ray::Scene alone;
        ray::Material mat = s.scene.materials.at(s.scene.objects[s.object].material);
        const uint32_t mi = alone.addMesh(m), ma = alone.addMaterial(mat);
        alone.environment = s.scene.environment;
        s.object = alone.addObject(s.scene.objects[s.object].name, mi, ma, norm);
        s.envA = s.scene.environment;
        s.envAName = s.envA.kind == ray::EnvironmentKind::Image ? s.envA.path : "the scene's environment";
        s.envB = loadBlender("courtyard");
        s.envBName = "blender:courtyard";
        s.description = "'" + alone.objects[s.object].name + "' from " + file + (s.mode == Interaction::Refract ? " (glass)" : " (mirror)");
        s.scene = std::move(alone);
    }
    s.bounds = ray::computeBounds(s.scene.worldMesh(s.object));
    return s;
}

// The slab of the geometry light fields: eye points at z = 6 over [−1, 1]², the window at
// z = 0 over [−2, 2]² (it holds the object's shadow from every eye point: validateSlab).
LightSlab geometrySlab(int S, int U) {
    LightSlab s;
    s.stZ = 6.0f;
    s.uvZ = 0.0f;
    s.stMin = glm::vec2(-1.0f);
    s.stMax = glm::vec2(1.0f);
    s.uvMin = glm::vec2(-2.0f);
    s.uvMax = glm::vec2(2.0f);
    s.S = s.T = S;
    s.U = s.V = U;
    return s;
}

ray::Camera evalCamera(int k) {
    // Inside the slab's cone: (0) between eye points, (1) off-axis.
    ray::Camera c;
    c.eye = k == 0 ? glm::vec3(0.07f, -0.05f, 9.0f) : glm::vec3(-0.45f, 0.35f, 8.5f);
    c.target = glm::vec3(0.0f);
    c.fovYDegrees = 21.0f;
    return c;
}


}  // namespace rg::lightfield
