#include "impostor_scene.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>

#include "core/error.h"
#include "raycore/builtin_scenes.h"
#include "raycore/scene_json.h"
#include "raycore/shapes.h"

namespace rg::impostors {

namespace {

bool reflective(const ray::Scene& s, const ray::Object& o) {
    const ray::MaterialType t = s.materials.at(o.material).type;
    return t == ray::MaterialType::Glass || t == ray::MaterialType::Mirror;
}

}  // namespace

void indexGlass(ImpostorScene& s) {
    s.glass.clear();
    s.vertices = s.faces = 0;
    for (size_t i = 0; i < s.scene.objects.size(); ++i) {
        const ray::Mesh& m = s.scene.meshes.at(s.scene.objects[i].mesh);
        s.vertices += int64_t(m.positions.size());
        s.faces += int64_t(m.indices.size() / 3);
        if (reflective(s.scene, s.scene.objects[i])) s.glass.push_back(uint32_t(i));
    }
}

glm::mat4 ImpostorScene::moverTransform(float u) const {
    if (mover < 0) return glm::mat4(1.0f);
    const glm::mat4& base = scene.objects.at(size_t(mover)).transform;
    return glm::translate(glm::mat4(1.0f), moverPath * u) * base;
}

ray::Scene ImpostorScene::at(float u) const {
    ray::Scene s = scene;
    if (mover >= 0) s.objects.at(size_t(mover)).transform = moverTransform(u);
    return s;
}

void setMover(ImpostorScene& s, const std::string& name) {
    const int i = s.scene.findObject(name);
    std::string names;
    for (uint32_t g : s.glass) names += (names.empty() ? "" : ", ") + s.scene.objects[g].name;
    if (i < 0)
        throw Error("impostors: scene '" + s.scene.name + "' has no object '" + name +
                    "' to move (its glass and mirror objects: " + names + ")");
    if (!reflective(s.scene, s.scene.objects[size_t(i)]))
        throw Error("impostors: the mover '" + name + "' is neither glass nor a mirror (the glass and mirror objects: " +
                    names + ")");
    s.mover = i;
}

ImpostorScene makeChessScene(const ChessOptions& o) {
    ImpostorScene s;
    ray::Scene& sc = s.scene;
    sc.name = "impostors-chess";
    // raycore's `chess`: the checker board (8×8 squares of 1, top at y = 0), clear and smoke
    // glass sets (index 1.5), a gradient sky, its two lights and ambient.
    ray::Texture checker;
    checker.name = "board_checker";
    checker.kind = ray::TextureKind::Checker;
    checker.colorA = {0.9f, 0.85f, 0.7f};
    checker.colorB = {0.25f, 0.15f, 0.1f};
    checker.scale = 8.0f;
    const uint32_t wood = sc.addTexture(checker);
    ray::Material board;
    board.name = "board";
    board.diffuse = glm::vec3(1.0f);
    board.diffuseTexture = int(wood);
    sc.addObject("board", sc.addMesh(ray::makeChessboard(1.0f)), sc.addMaterial(board));
    auto glass = [](const std::string& name, glm::vec3 transmittance) {
        ray::Material m;
        m.name = name;
        m.type = ray::MaterialType::Glass;
        m.diffuse = glm::vec3(0.0f);
        m.ior = 1.5f;
        m.transmittance = transmittance;
        return m;
    };
    const uint32_t white = sc.addMaterial(glass("glass_clear", {0.95f, 0.95f, 0.95f}));
    const uint32_t black = sc.addMaterial(glass("glass_smoke", {0.55f, 0.5f, 0.6f}));
    ray::addChessSet(sc, white, black, o.segments);
    // The 33rd glass object, standing on the board (raycore's `chess` has it off the board,
    // floating): radius 0.5 on g4, the square of one piece (§4.2's grid), between the
    // close-up camera and the mover's path.
    const uint32_t sphereGlass = sc.addMaterial(glass("sphere_glass", glm::vec3(0.97f)));
    sc.addObject("glass_sphere", sc.addMesh(ray::makeSphere(0.5f, o.sphereSlices, o.sphereSlices / 2)), sphereGlass,
                 glm::translate(glm::mat4(1.0f), {2.5f, 0.5f, -0.5f}));
    sc.environment.kind = ray::EnvironmentKind::Gradient;
    sc.lights.push_back({"key", {3.0f, 10.0f, 4.0f}, glm::vec3(0.6f)});
    sc.lights.push_back({"fill", {-4.0f, 8.0f, -2.0f}, glm::vec3(0.25f)});
    sc.ambient = glm::vec3(0.2f);
    s.camera = {"whole_scene", {9.0f, 8.0f, 12.0f}, {0.0f, 0.3f, 0.0f}, {0, 1, 0}, 40.0f};
    s.closeUp = {"through_the_sphere", {6.5f, 0.9f, -0.5f}, {-0.5f, 0.35f, -0.5f}, {0, 1, 0}, 30.0f};
    sc.cameras = {s.camera, s.closeUp};
    indexGlass(s);
    // The mover: the white d-pawn, two squares forward (d2 → d4); a mirror in Figure 9.
    setMover(s, "white_pawn3");
    s.moverPath = {0.0f, 0.0f, 2.0f};
    if (o.mirrorMover) {
        ray::Material m;
        m.name = "pawn_mirror";
        m.type = ray::MaterialType::Mirror;
        m.diffuse = glm::vec3(0.0f);
        m.reflectance = glm::vec3(0.9f);
        m.fresnel = ray::MirrorFresnel::Constant;
        sc.objects.at(size_t(s.mover)).material = sc.addMaterial(m);
    }
    if (!o.keep.empty()) {
        for (const std::string& name : o.keep)
            if (sc.findObject(name) < 0) throw Error("impostors: the chess set has no object '" + name + "' to keep");
        const std::string mover = sc.objects.at(size_t(s.mover)).name;
        std::vector<ray::Object> kept;
        for (const ray::Object& ob : sc.objects)
            if (ob.name == "board" || ob.name == mover || ob.name == "glass_sphere" ||
                std::find(o.keep.begin(), o.keep.end(), ob.name) != o.keep.end())
                kept.push_back(ob);
        sc.objects = kept;
        indexGlass(s);
        setMover(s, mover);
    }
    s.description = "raycore's glass chess set (lathes of " + std::to_string(o.segments) +
                    " segments, the knight a lathe base with an extruded head) on its 8×8 checker board, a "
                    "glass sphere of radius 0.5 on g4, a gradient sky, two point lights; the mover the white "
                    "d-pawn (d2 → d4)" + std::string(o.mirrorMover ? ", a mirror" : "");
    return s;
}

ImpostorScene impostorSceneFromFile(const std::string& fileOrName, const std::string& mover) {
    ImpostorScene s;
    s.scene = ray::loadSceneByName(fileOrName, &s.warnings);
    indexGlass(s);
    if (s.glass.empty())
        throw Error("impostors: scene '" + s.scene.name + "' has no glass or mirror object (distance impostors "
                    "are made for glass and mirror objects)");
    if (!s.scene.cameras.empty()) s.camera = s.scene.cameras[0];
    else if (!s.scene.viewpointPaths.empty()) s.camera = s.scene.viewpointPaths[0].at(0);
    else throw Error("impostors: scene '" + s.scene.name + "' has no camera");
    s.closeUp = s.scene.cameras.size() > 1 ? s.scene.cameras[1] : s.camera;
    if (!mover.empty()) setMover(s, mover);
    else s.mover = int(s.glass.back());
    s.moverPath = {1.0f, 0.0f, 0.0f};
    s.description = "the user's scene '" + s.scene.name + "', mover '" + s.scene.objects[size_t(s.mover)].name + "'";
    return s;
}

}  // namespace rg::impostors
