// The built-in scenes of the five papers.
#include "raycore/builtin_scenes.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cstdlib>
#include <numbers>

#include "core/error.h"
#include "raycore/mesh_io.h"
#include "raycore/shapes.h"
#include "raycore/teapot.h"

namespace rg::ray {

std::filesystem::path dataDir() {
    if (const char* d = std::getenv("RETROGLASS_DATA_DIR"); d && *d) return d;
    return RETROGLASS_DATA_DIR;
}

namespace {

Material diffuseMaterial(const std::string& name, glm::vec3 color, int texture = -1) {
    Material m;
    m.name = name;
    m.type = MaterialType::Diffuse;
    m.diffuse = color;
    m.diffuseTexture = texture;
    return m;
}

Material mirrorMaterial(const std::string& name, glm::vec3 F0, MirrorFresnel f) {
    Material m;
    m.name = name;
    m.type = MaterialType::Mirror;
    m.diffuse = glm::vec3(0.0f);
    m.reflectance = F0;
    m.fresnel = f;
    return m;
}

Material glassMaterial(const std::string& name, float ior, glm::vec3 transmittance) {
    Material m;
    m.name = name;
    m.type = MaterialType::Glass;
    m.diffuse = glm::vec3(0.0f);
    m.ior = ior;
    m.transmittance = transmittance;
    return m;
}

Texture texture(const std::string& name, TextureKind kind, glm::vec3 a, glm::vec3 b, float scale) {
    Texture t;
    t.name = name;
    t.kind = kind;
    t.colorA = a;
    t.colorB = b;
    t.scale = scale;
    return t;
}

glm::mat4 translate(glm::vec3 v) { return glm::translate(glm::mat4(1.0f), v); }
glm::mat4 scale(float s) { return glm::scale(glm::mat4(1.0f), glm::vec3(s)); }

uint32_t addFloor(Scene& scene, float half, float y) {
    uint32_t tex = scene.addTexture(
        texture("floor_checker", TextureKind::Checker, {0.85f, 0.85f, 0.8f}, {0.15f, 0.15f, 0.2f}, 1.0f));
    uint32_t mat = scene.addMaterial(diffuseMaterial("floor", glm::vec3(1.0f), int(tex)));
    Mesh room = makeRoom({-half, y, -half}, {half, y + 1.0f, half}, 1.0f);
    Mesh floor = extractPart(room, 0);
    floor.source = room.source;
    floor.source.params["part"] = 0;
    return scene.addObject("floor", scene.addMesh(floor), mat);
}

void addDefaultLights(Scene& scene, glm::vec3 center, float height) {
    scene.lights.push_back({"key", center + glm::vec3(3.0f, height, 4.0f), glm::vec3(0.6f)});
    scene.lights.push_back({"fill", center + glm::vec3(-4.0f, height * 0.8f, -2.0f), glm::vec3(0.25f)});
}

}  // namespace

uint32_t addTeapot(Scene& scene, int level, uint32_t material, const glm::mat4& transform) {
    Mesh m = tessellateTeapot(loadTeapotPatches(dataDir() / "teapot.txt"), level);
    return scene.addObject("teapot", scene.addMesh(std::move(m)), material, transform);
}

uint32_t addRoom(Scene& scene, glm::vec3 lo, glm::vec3 hi, const std::string& prefix) {
    // Textures sized in metres (uvScale 1): bricks 0.5 m, checker tiles 1 m.
    const uint32_t bricks = scene.addTexture(texture(prefix + "bricks", TextureKind::Bricks,
                                                     {0.62f, 0.25f, 0.16f}, {0.85f, 0.83f, 0.78f}, 0.5f));
    const uint32_t tiles = scene.addTexture(texture(prefix + "tiles", TextureKind::Checker,
                                                    {0.9f, 0.9f, 0.85f}, {0.1f, 0.12f, 0.3f}, 1.0f));
    const uint32_t wood = scene.addTexture(texture(prefix + "wood", TextureKind::WoodRings,
                                                   {0.75f, 0.55f, 0.3f}, {0.4f, 0.22f, 0.1f}, 0.8f));
    const uint32_t stripes = scene.addTexture(texture(prefix + "checker_green", TextureKind::Checker,
                                                      {0.2f, 0.55f, 0.25f}, {0.9f, 0.9f, 0.6f}, 0.5f));
    const uint32_t sky = scene.addTexture(texture(prefix + "gradient", TextureKind::Gradient,
                                                  {0.95f, 0.85f, 0.5f}, {0.3f, 0.45f, 0.85f}, 1.0f));
    Mesh room = makeRoom(lo, hi, 1.0f);
    const struct {
        const char* part;
        uint32_t tex;
        glm::vec3 tint;
    } looks[6] = {{"floor", tiles, glm::vec3(1.0f)},   {"ceiling", wood, glm::vec3(1.0f)},
                  {"wall_-x", bricks, glm::vec3(1.0f)}, {"wall_+x", stripes, glm::vec3(1.0f)},
                  {"wall_-z", bricks, {0.8f, 0.9f, 1.0f}}, {"wall_+z", sky, glm::vec3(1.0f)}};
    uint32_t first = uint32_t(scene.objects.size());
    for (const auto& l : looks) {
        int pi = room.findPart(l.part);
        Mesh part = extractPart(room, uint32_t(pi));
        part.name = prefix + l.part;
        part.source = room.source;
        part.source.params["part"] = pi;
        uint32_t mat = scene.addMaterial(diffuseMaterial(prefix + l.part, l.tint, int(l.tex)));
        scene.addObject(prefix + l.part, scene.addMesh(std::move(part)), mat);
    }
    return first;
}

uint32_t addCup(Scene& scene, uint32_t material, const glm::mat4& transform) {
    // A straight-walled cup 2 tall, radius 1, walls 0.08 thick: outer wall up, rim, inner
    // wall down, inner floor; both ends on the axis, so the lathe is closed.
    Mesh cup = makeLathe({{0.0f, 0.0f}, {0.9f, 0.0f}, {1.0f, 0.1f}, {1.0f, 2.0f}, {0.92f, 2.0f},
                          {0.92f, 0.15f}, {0.0f, 0.15f}},
                         64);
    cup.name = "cup";
    cup.source = {"cup", "", {}};
    return scene.addObject("cup", scene.addMesh(std::move(cup)), material, transform);
}

void addColumnRing(Scene& scene, glm::vec3 center, float radius, int count, float height,
                   uint32_t material) {
    Mesh column = makeCylinder(0.35f, height, 32);
    uint32_t mesh = scene.addMesh(column);
    for (int i = 0; i < count; ++i) {
        float a = 2.0f * std::numbers::pi_v<float> * float(i) / float(count);
        glm::vec3 p = center + glm::vec3(radius * std::cos(a), 0.0f, radius * std::sin(a));
        scene.addObject("column" + std::to_string(i), mesh, material, translate(p));
    }
}

std::vector<std::string> builtinSceneNames() {
    return {"teapot-in-room", "glass-teapot", "chess", "glass-cube", "mirror-sphere",
            "bunny",          "torus",        "sphere", "cube"};
}

Scene makeBuiltinScene(const std::string& name, const BuiltinOptions& opt) {
    Scene scene;
    scene.name = name;
    if (name == "teapot-in-room") {
        // 001 §6: a reflective teapot of ~40k triangles in a room, viewed from a 1D
        // viewspace circling it at 1° per view (100 views).
        uint32_t chrome = scene.addMaterial(
            mirrorMaterial("teapot_chrome", glm::vec3(0.6f), MirrorFresnel::Schlick));
        addTeapot(scene, opt.teapotLevel, chrome, glm::mat4(1.0f));
        addRoom(scene, {-10.0f, 0.0f, -10.0f}, {10.0f, 10.0f, 10.0f});
        scene.lights.push_back({"ceiling", {0.0f, 9.0f, 0.0f}, glm::vec3(0.55f)});
        scene.lights.push_back({"corner", {6.0f, 7.0f, 6.0f}, glm::vec3(0.25f)});
        scene.ambient = glm::vec3(0.3f);
        ViewpointPath path;
        path.name = "circle";
        path.center = {0.0f, 1.5f, 0.0f};
        path.radius = 8.0f;
        path.height = 2.5f;
        path.startDegrees = 0.0f;
        path.stepDegrees = 1.0f;
        path.count = 100;
        path.fovYDegrees = 40.0f;
        scene.viewpointPaths.push_back(path);
        Camera c = path.at(0);
        c.name = "default";
        scene.cameras.push_back(c);
    } else if (name == "glass-teapot") {
        // 000 §6: a glass teapot, a reflective cup, a ring of columns and distant walls.
        uint32_t glass = scene.addMaterial(glassMaterial("teapot_glass", 1.5f, {0.92f, 0.96f, 0.94f}));
        uint32_t chrome = scene.addMaterial(
            mirrorMaterial("cup_chrome", glm::vec3(0.8f, 0.7f, 0.5f), MirrorFresnel::Schlick));
        uint32_t stone = scene.addMaterial(diffuseMaterial("column_stone", {0.8f, 0.78f, 0.7f}));
        addTeapot(scene, opt.teapotLevel, glass, glm::mat4(1.0f));
        addCup(scene, chrome, translate({4.0f, 0.0f, 2.5f}));
        addColumnRing(scene, glm::vec3(0.0f), 11.0f, 12, 8.0f, stone);
        addRoom(scene, {-20.0f, 0.0f, -20.0f}, {20.0f, 14.0f, 20.0f});
        scene.lights.push_back({"ceiling", {0.0f, 12.0f, 0.0f}, glm::vec3(0.6f)});
        scene.ambient = glm::vec3(0.3f);
        ViewpointPath path;
        path.name = "circle";
        path.center = {0.0f, 1.5f, 0.0f};
        path.radius = 9.0f;
        path.height = 3.0f;
        path.stepDegrees = 8.0f;
        path.count = 45;
        scene.viewpointPaths.push_back(path);
        Camera c = path.at(0);
        c.name = "default";
        scene.cameras.push_back(c);
    } else if (name == "chess") {
        uint32_t wood = scene.addTexture(texture("board_checker", TextureKind::Checker,
                                                 {0.9f, 0.85f, 0.7f}, {0.25f, 0.15f, 0.1f}, 8.0f));
        uint32_t boardMat = scene.addMaterial(diffuseMaterial("board", glm::vec3(1.0f), int(wood)));
        scene.addObject("board", scene.addMesh(makeChessboard(1.0f)), boardMat);
        uint32_t white = scene.addMaterial(glassMaterial("glass_clear", 1.5f, {0.95f, 0.95f, 0.95f}));
        uint32_t black = scene.addMaterial(glassMaterial("glass_smoke", 1.5f, {0.55f, 0.5f, 0.6f}));
        addChessSet(scene, white, black);
        uint32_t sphereGlass = scene.addMaterial(glassMaterial("sphere_glass", 1.5f, glm::vec3(0.97f)));
        scene.addObject("glass_sphere", scene.addMesh(makeSphere(1.2f, 96, 48)), sphereGlass,
                        translate({6.0f, 1.2f, 0.0f}));
        addFloor(scene, 30.0f, -0.3f);
        scene.environment.kind = EnvironmentKind::Gradient;
        addDefaultLights(scene, glm::vec3(0.0f), 10.0f);
        scene.cameras.push_back({"default", {9.0f, 8.0f, 12.0f}, {0.0f, 0.5f, 0.0f}, {0, 1, 0}, 40.0f});
    } else if (name == "glass-cube") {
        // The TIR test: a clear glass cube against a white environment. With no absorption
        // every path ends in the white environment with weights summing to 1, so the image
        // is uniformly 1 wherever TIR is handled correctly.
        uint32_t glass = scene.addMaterial(glassMaterial("cube_glass", 1.5f, glm::vec3(1.0f)));
        scene.addObject("cube", scene.addMesh(makeCube(1.0f)), glass,
                        glm::rotate(glm::rotate(glm::mat4(1.0f), 0.6f, {0, 1, 0}), 0.5f, {1, 0, 0}));
        scene.environment.kind = EnvironmentKind::Constant;
        scene.environment.color = glm::vec3(1.0f);
        scene.ambient = glm::vec3(0.0f);
        scene.cameras.push_back({"default", {0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 45.0f});
    } else if (name == "mirror-sphere") {
        uint32_t mirror = scene.addMaterial(
            mirrorMaterial("sphere_mirror", glm::vec3(0.8f), MirrorFresnel::Constant));
        scene.addObject("sphere", scene.addMesh(makeSphere(1.0f, 128, 64)), mirror);
        scene.environment.kind = EnvironmentKind::Constant;
        scene.environment.color = {0.5f, 0.7f, 0.9f};
        scene.ambient = glm::vec3(0.0f);
        scene.cameras.push_back({"default", {0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 45.0f});
    } else if (name == "bunny" || name == "torus" || name == "sphere" || name == "cube") {
        Mesh m;
        glm::mat4 xf(1.0f);
        if (name == "bunny") {
            m = loadMesh(dataDir() / "bunny.obj");
            m.source = {"file", "bunny.obj", {}};
            Bounds b = computeBounds(m);
            float s = 2.0f / (b.hi.y - b.lo.y);  // 2 units tall, resting on y = 0
            xf = scale(s) * translate({-b.center().x, -b.lo.y, -b.center().z});
        } else if (name == "torus") {
            m = makeTorus(1.0f, 0.35f);
            xf = translate({0.0f, 0.35f, 0.0f});
        } else if (name == "sphere") {
            m = makeSphere(1.0f);
            xf = translate({0.0f, 1.0f, 0.0f});
        } else {
            m = makeCube(0.8f);
            xf = translate({0.0f, 0.8f, 0.0f});
        }
        uint32_t mat = scene.addMaterial(
            mirrorMaterial(name + "_mirror", glm::vec3(0.7f), MirrorFresnel::Schlick));
        scene.addObject(name, scene.addMesh(std::move(m)), mat, xf);
        addFloor(scene, 20.0f, 0.0f);
        scene.environment.kind = EnvironmentKind::Gradient;
        addDefaultLights(scene, glm::vec3(0.0f), 8.0f);
        scene.cameras.push_back({"default", {3.5f, 2.5f, 4.5f}, {0.0f, 0.8f, 0.0f}, {0, 1, 0}, 40.0f});
    } else {
        std::string names;
        for (const std::string& n : builtinSceneNames()) names += (names.empty() ? "" : ", ") + n;
        throw Error("unknown built-in scene '" + name + "' (known: " + names + ")");
    }
    return scene;
}

}  // namespace rg::ray
