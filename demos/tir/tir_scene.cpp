#include "tir_scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

#include "core/error.h"
#include "raycore/builtin_scenes.h"
#include "raycore/cgal_meshes.h"
#include "raycore/mesh_io.h"
#include "raycore/scene_json.h"
#include "raycore/shapes.h"

namespace rg::tir {

namespace {

using ray::Material;
using ray::MaterialType;

uint32_t addMaterial(ray::Scene& s, const std::string& name, MaterialType type, glm::vec3 diffuse,
                     float ior = 1.5f, int texture = -1) {
    Material m;
    m.name = name;
    m.type = type;
    m.diffuse = type == MaterialType::Diffuse ? diffuse : glm::vec3(0.0f);
    m.diffuseTexture = texture;
    m.ior = ior;
    m.transmittance = glm::vec3(1.0f);  // 004 never mentions absorption
    return s.addMaterial(m);
}

// A mesh scaled to `height` units tall, standing on y = 0, centred on x = z = 0, turned by
// `yawDegrees` about +y, then moved to `at`. `upright` first turns models whose files stand
// along another axis (CGAL's man.off lies along z).
glm::mat4 standing(ray::Mesh& m, float height, float yawDegrees, glm::vec3 at,
                   const glm::mat4& upright = glm::mat4(1.0f)) {
    if (upright != glm::mat4(1.0f)) ray::transformMesh(m, upright);
    const ray::Bounds b = ray::computeBounds(m);
    const float s = height / (b.hi.y - b.lo.y);
    glm::mat4 xf = glm::translate(glm::mat4(1.0f), at);
    xf = glm::rotate(xf, glm::radians(yawDegrees), glm::vec3(0, 1, 0));
    xf = glm::scale(xf, glm::vec3(s));
    return glm::translate(xf, glm::vec3(-b.center().x, -b.lo.y, -b.center().z));
}

void setImageWorld(ray::Scene& s, const std::string& name, float rotate = 0.0f) {
    s.environment.kind = ray::EnvironmentKind::Image;
    s.environment.path = "blender:" + name;
    s.environment.rotateDegrees = rotate;
    s.environment.image =
        std::make_shared<const ray::Image>(ray::readEnvironmentImage(ray::blenderWorldPath(name)));
}

void checkRefractor(TirScene& t) {
    const ray::Object& o = t.scene.objects.at(t.refractor);
    const ray::Mesh& m = t.scene.meshes.at(o.mesh);
    if (!ray::isClosedManifold(m))
        t.warnings.push_back("the refractor '" + o.name + "' (mesh '" + m.name +
                             "') is not a closed 2-manifold: the back map has holes where its "
                             "far side is missing, and paths through them leave the glass early");
}

// The Macbeth ColorChecker's 24 patches as a 6×4 image (sRGB values published by X-Rite,
// converted to linear): the chart of Figure 1.
ray::Texture macbethTexture() {
    static const unsigned char srgb[24][3] = {
        {115, 82, 68},  {194, 150, 130}, {98, 122, 157}, {87, 108, 67},  {133, 128, 177}, {103, 189, 170},
        {214, 126, 44}, {80, 91, 166},   {193, 90, 99},  {94, 60, 108},  {157, 188, 64},  {224, 163, 46},
        {56, 61, 150},  {70, 148, 73},   {175, 54, 60},  {231, 199, 31}, {187, 86, 149},  {8, 133, 161},
        {243, 243, 242}, {200, 200, 200}, {160, 160, 160}, {122, 122, 121}, {85, 85, 85}, {52, 52, 52}};
    auto linear = [](unsigned char c) {
        const double v = c / 255.0;
        return float(v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4));
    };
    // 16×16 texels a patch inside a 2-texel black frame, so filtering keeps patches apart.
    constexpr int kPatch = 20;
    auto img = std::make_shared<ray::Image>(6 * kPatch, 4 * kPatch, 3, 0.03f);
    for (int i = 0; i < 24; ++i)
        for (int y = 2; y < kPatch - 2; ++y)
            for (int x = 2; x < kPatch - 2; ++x)
                img->setRgb((i % 6) * kPatch + x, (i / 6) * kPatch + y,
                            {linear(srgb[i][0]), linear(srgb[i][1]), linear(srgb[i][2])});
    ray::Texture t;
    t.name = "macbeth";
    t.kind = ray::TextureKind::Image;
    t.path = "(built in: the ColorChecker's published values)";
    t.image = img;
    t.scale = 1.0f;
    return t;
}

ray::Mesh quadMesh(float w, float h) {
    ray::Mesh m;
    m.name = "chart";
    m.positions = {{-w / 2, 0, 0}, {w / 2, 0, 0}, {w / 2, h, 0}, {-w / 2, h, 0}};
    m.normals.assign(4, glm::vec3(0, 0, 1));
    m.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    m.indices = {0, 1, 2, 0, 2, 3};
    return m;
}

}  // namespace

std::vector<std::string> tirSceneNames() { return {"kitchen", "statue", "dragon", "prism"}; }

TirScene makeTirScene(const std::string& name, bool paper) {
    TirScene t;
    ray::Scene& s = t.scene;
    s.name = "tir-" + name;
    if (name == "kitchen") {
        // Figure 10: "A refractive Stanford Bunny in a kitchen with the Utah Teapot".
        ray::addRoom(s, {-5.0f, 0.0f, -5.0f}, {5.0f, 4.5f, 5.0f});
        const uint32_t clay = addMaterial(s, "teapot_clay", MaterialType::Diffuse, {0.75f, 0.35f, 0.25f});
        const uint32_t pot = ray::addTeapot(s, paper ? 16 : 8, clay, glm::mat4(1.0f));
        ray::Mesh& potMesh = s.meshes.at(s.objects.at(pot).mesh);
        s.objects.at(pot).transform = standing(potMesh, 1.1f, 30.0f, {-1.6f, 0.0f, -1.2f});
        ray::Mesh bunny = ray::loadMesh(ray::dataDir() / "bunny.obj");
        bunny.source = {"file", "bunny.obj", {}};
        const glm::mat4 xf = standing(bunny, 2.0f, 0.0f, {0.3f, 0.0f, 0.0f});
        const uint32_t glass = addMaterial(s, "bunny_glass", MaterialType::Glass, {}, 1.5f);
        t.refractor = s.addObject("bunny", s.addMesh(std::move(bunny)), glass, xf);
        s.lights.push_back({"ceiling", {0.0f, 4.3f, 0.0f}, glm::vec3(0.5f)});
        s.lights.push_back({"corner", {3.5f, 3.5f, 3.5f}, glm::vec3(0.25f)});
        s.ambient = glm::vec3(0.3f);
        t.camera = {"default", {1.2f, 2.4f, 4.6f}, {0.0f, 0.95f, 0.0f}, {0, 1, 0}, 40.0f};
        t.substitutes = "bunny: the Stanford bunny (data/bunny.obj, closed); teapot: Newell's "
                        "patches (data/teapot.txt); kitchen: raycore's textured room";
    } else if (name == "statue" || name == "dragon") {
        const bool statue = name == "statue";
        ray::Mesh glassMesh = ray::loadCgalMesh(statue ? "armadillo" : "ChineseDragon-10kv");
        ray::fillHoles(glassMesh);
        const glm::mat4 xf = statue ? standing(glassMesh, 2.2f, 180.0f, {0.0f, 0.0f, 0.6f})
                                    : standing(glassMesh, 1.4f, 90.0f, {0.0f, 0.0f, 0.4f});
        const uint32_t glass = addMaterial(s, "glass", MaterialType::Glass, {}, 1.5f);
        t.refractor = s.addObject(statue ? "statue" : "dragon", s.addMesh(std::move(glassMesh)), glass, xf);
        const uint32_t floorTex = s.addTexture([] {
            ray::Texture f;
            f.name = "floor_tiles";
            f.kind = ray::TextureKind::Checker;
            f.colorA = {0.85f, 0.85f, 0.8f};
            f.colorB = {0.25f, 0.25f, 0.3f};
            f.scale = 8.0f;
            return f;
        }());
        const uint32_t floorMat = addMaterial(s, "floor", MaterialType::Diffuse, glm::vec3(1.0f), 1.0f, int(floorTex));
        ray::Mesh floor = ray::makeRoom({-4.0f, 0.0f, -4.0f}, {4.0f, 4.0f, 4.0f});
        const int floorPart = floor.findPart("floor");
        s.addObject("floor", s.addMesh(floorPart >= 0 ? ray::extractPart(floor, uint32_t(floorPart)) : floor),
                    floorMat);
        if (statue) {
            ray::Mesh venus = ray::loadCgalMesh("man");
            const uint32_t marble = addMaterial(s, "marble", MaterialType::Diffuse, {0.85f, 0.83f, 0.8f});
            // man.off stands along +z: turned −90° about x, z becomes y.
            const glm::mat4 vx = standing(venus, 2.6f, 0.0f, {0.0f, 0.0f, -1.6f},
                                          glm::rotate(glm::mat4(1.0f), glm::radians(-90.0f), glm::vec3(1, 0, 0)));
            s.addObject("venus", s.addMesh(std::move(venus)), marble, vx);
            setImageWorld(s, "interior");
            t.camera = {"default", {0.0f, 1.5f, 4.6f}, {0.0f, 1.2f, 0.0f}, {0, 1, 0}, 40.0f};
            t.substitutes = "Buddha (250K vertices): the Stanford armadillo (cgal:armadillo, 26,002 "
                            "vertices); Venus: a human figure (cgal:man); Uffizi: blender:interior";
        } else {
            const uint32_t chartTex = s.addTexture(macbethTexture());
            const uint32_t chartMat = addMaterial(s, "chart", MaterialType::Diffuse, glm::vec3(1.0f), 1.0f, int(chartTex));
            s.addObject("chart", s.addMesh(quadMesh(3.0f, 2.0f)), chartMat,
                        glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.2f, -1.2f)));
            setImageWorld(s, "studio");
            t.camera = {"default", {0.0f, 1.2f, 3.8f}, {0.0f, 0.7f, 0.0f}, {0, 1, 0}, 40.0f};
            t.substitutes = "dragon (250K): the Chinese dragon (cgal:ChineseDragon-10kv, 10,000 "
                            "vertices, its 6 boundary edges closed); Macbeth chart: a 6×4 texture "
                            "of the ColorChecker's published sRGB values; world: blender:studio";
        }
        s.lights.push_back({"key", {2.0f, 4.0f, 3.0f}, glm::vec3(0.6f)});
        s.ambient = glm::vec3(0.35f);
    } else if (name == "prism") {
        // A thick block turned about two axes: most paths from the eye meet one face past
        // the critical angle (41.8° at η = 1.5) at least once.
        ray::Mesh block = ray::makeCube(0.6f);
        for (glm::vec3& p : block.positions) p.y *= 1.6f;
        glm::mat4 xf = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
        xf = glm::rotate(xf, 0.7f, glm::vec3(0, 1, 0));
        xf = glm::rotate(xf, 0.45f, glm::vec3(1, 0, 0));
        const uint32_t glass = addMaterial(s, "glass", MaterialType::Glass, {}, 1.5f);
        t.refractor = s.addObject("block", s.addMesh(std::move(block)), glass, xf);
        setImageWorld(s, "courtyard");
        s.ambient = glm::vec3(0.0f);
        t.camera = {"default", {0.0f, 1.3f, 3.6f}, {0.0f, 1.0f, 0.0f}, {0, 1, 0}, 40.0f};
        t.substitutes = "Figures 8 and 11 do not name their model: a glass block (our choice)";
    } else {
        std::string names;
        for (const auto& n : tirSceneNames()) names += (names.empty() ? "" : ", ") + n;
        throw Error("tir: unknown scene '" + name + "' (built in: " + names + ")");
    }
    checkRefractor(t);
    return t;
}

TirScene tirSceneFromFile(const std::string& fileOrName) {
    TirScene t;
    t.scene = ray::loadSceneByName(fileOrName, &t.warnings);
    int glass = -1;
    for (size_t i = 0; i < t.scene.objects.size(); ++i)
        if (t.scene.materials.at(t.scene.objects[i].material).type == MaterialType::Glass) {
            glass = int(i);
            break;
        }
    if (glass < 0)
        throw Error("tir: scene '" + t.scene.name + "' has no glass object to refract through");
    t.refractor = uint32_t(glass);
    if (!t.scene.cameras.empty()) t.camera = t.scene.cameras[0];
    else if (!t.scene.viewpointPaths.empty()) t.camera = t.scene.viewpointPaths[0].at(0);
    else throw Error("tir: scene '" + t.scene.name + "' has no camera");
    t.substitutes = "the user's scene";
    refractorIor(t);
    checkRefractor(t);
    return t;
}

float refractorIor(const TirScene& s) {
    const ray::Object& o = s.scene.objects.at(s.refractor);
    const float ior = s.scene.materials.at(o.material).ior;
    if (!(ior > 0.0f) || !std::isfinite(ior))
        throw Error("tir: the refractor '" + o.name + "' has index of refraction " +
                    std::to_string(ior) + " (it must be a positive finite number)");
    return ior;
}

}  // namespace rg::tir
