// The JSON scene format (docs/scene-format.md).
#include "raycore/scene_json.h"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include "core/error.h"
#include "raycore/builtin_scenes.h"
#include "raycore/cgal_meshes.h"
#include "raycore/mesh_io.h"
#include "raycore/shapes.h"
#include "raycore/teapot.h"

namespace rg::ray {

using nlohmann::json;

namespace {

struct Ctx {
    std::string what;  // the file, for messages
    std::filesystem::path baseDir;
    std::vector<std::string>* warnings;
    void warn(const std::string& w) const {
        if (warnings) warnings->push_back(what + ": " + w);
        else std::fprintf(stderr, "warning: %s: %s\n", what.c_str(), w.c_str());
    }
    void warnAsIs(const std::string& w) const {  // a warning already naming the file
        if (warnings) warnings->push_back(w);
        else std::fprintf(stderr, "warning: %s\n", w.c_str());
    }
    [[noreturn]] void fail(const std::string& e) const { throw Error(what + ": " + e); }
    std::filesystem::path resolve(const std::string& p) const {
        std::filesystem::path path(p);
        if (path.is_absolute()) return path;
        std::filesystem::path local = baseDir / path;
        if (std::filesystem::exists(local)) return local;
        std::filesystem::path data = dataDir() / path;  // built-in data (bunny.obj, ...)
        if (std::filesystem::exists(data)) return data;
        return local;
    }
};

void checkKeys(const Ctx& c, const json& j, const std::string& where,
               std::initializer_list<const char*> known) {
    if (!j.is_object()) c.fail(where + " must be a JSON object");
    std::set<std::string> k(known.begin(), known.end());
    for (auto it = j.begin(); it != j.end(); ++it)
        if (!k.count(it.key())) c.warn(where + ": unknown key '" + it.key() + "' ignored");
}

glm::vec3 vec3Of(const Ctx& c, const json& j, const std::string& where) {
    if (j.is_number()) return glm::vec3(j.get<float>());
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
        c.fail(where + " must be a number or an array of three numbers");
    return {j[0].get<float>(), j[1].get<float>(), j[2].get<float>()};
}

glm::vec3 vec3Or(const Ctx& c, const json& j, const char* key, glm::vec3 def, const std::string& where) {
    return j.contains(key) ? vec3Of(c, j[key], where + "." + key) : def;
}

float floatOr(const Ctx& c, const json& j, const char* key, float def, const std::string& where) {
    if (!j.contains(key)) return def;
    if (!j[key].is_number()) c.fail(where + "." + key + " must be a number");
    return j[key].get<float>();
}

std::string stringOr(const Ctx& c, const json& j, const char* key, const std::string& def,
                     const std::string& where) {
    if (!j.contains(key)) return def;
    if (!j[key].is_string()) c.fail(where + "." + key + " must be a string");
    return j[key].get<std::string>();
}

json toJson(glm::vec3 v) { return json::array({v.x, v.y, v.z}); }

glm::mat4 transformOf(const Ctx& c, const json& t, const std::string& where) {
    checkKeys(c, t, where, {"matrix", "translate", "rotate", "scale"});
    if (t.contains("matrix")) {
        const json& m = t["matrix"];
        if (!m.is_array() || m.size() != 16) c.fail(where + ".matrix must have 16 numbers");
        glm::mat4 out;
        for (int i = 0; i < 16; ++i) {
            if (!m[size_t(i)].is_number()) c.fail(where + ".matrix must have 16 numbers");
            glm::value_ptr(out)[i] = m[size_t(i)].get<float>();  // column-major, as GLSL/glm
        }
        return out;
    }
    // translate · rotate · scale, applied to the mesh in the order scale, rotate, translate.
    glm::mat4 m(1.0f);
    if (t.contains("translate")) m = glm::translate(m, vec3Of(c, t["translate"], where + ".translate"));
    if (t.contains("rotate")) {
        const json& r = t["rotate"];
        if (!r.is_array() || r.size() != 4)
            c.fail(where + ".rotate must be [axis_x, axis_y, axis_z, degrees]");
        glm::vec3 axis(r[0].get<float>(), r[1].get<float>(), r[2].get<float>());
        if (glm::length(axis) == 0.0f) c.fail(where + ".rotate has a zero axis");
        m = glm::rotate(m, glm::radians(r[3].get<float>()), glm::normalize(axis));
    }
    if (t.contains("scale")) m = glm::scale(m, vec3Of(c, t["scale"], where + ".scale"));
    return m;
}

double param(const std::map<std::string, double>& p, const char* k, double def) {
    auto it = p.find(k);
    return it == p.end() ? def : it->second;
}

// A count parameter (segments, stacks, level, part): a whole number from `lo` up, or the
// default. Checked before the conversion, since int(1e300) is undefined and a negative
// count sized a vector past memory.
int countParam(const std::map<std::string, double>& p, const char* k, int def, int lo) {
    const double v = param(p, k, def);
    if (!(v >= lo && v <= double(1 << 20) && v == std::floor(v)))
        throw Error(std::string(k) + " must be a whole number from " + std::to_string(lo) +
                    " to " + std::to_string(1 << 20));
    return int(v);
}

// Shapes a scene may ask for, at most: 2^24 triangles (a sphere of 4096 × 2048, the teapot
// at level 512), so that a typing slip is an error rather than an allocation of terabytes.
constexpr double kMaxShapeTriangles = double(1 << 24);

void limitTriangles(double triangles) {
    if (triangles > kMaxShapeTriangles)
        throw Error("the parameters ask for " + std::to_string(int64_t(triangles)) +
                    " triangles, more than " + std::to_string(int64_t(kMaxShapeTriangles)));
}

// A built-in shape from its parameters. Bad ones raise rg::Error saying which parameter;
// meshFromSource adds the file and the object.
Mesh makeShape(const MeshSource& s) {
    const auto& p = s.params;
    if (s.kind == "sphere") {
        const int slices = countParam(p, "slices", 64, 3), stacks = countParam(p, "stacks", 32, 2);
        limitTriangles(2.0 * slices * stacks);
        return makeSphere(float(param(p, "radius", 1)), slices, stacks);
    }
    if (s.kind == "cube") return makeCube(float(param(p, "half_size", 1)));
    if (s.kind == "torus") {
        const int major = countParam(p, "major_segments", 64, 3);
        const int minor = countParam(p, "minor_segments", 32, 3);
        limitTriangles(2.0 * major * minor);
        return makeTorus(float(param(p, "major_radius", 1)), float(param(p, "minor_radius", 0.35)),
                         major, minor);
    }
    if (s.kind == "cylinder") {
        const int segments = countParam(p, "segments", 48, 3);
        limitTriangles(4.0 * segments);
        return makeCylinder(float(param(p, "radius", 1)), float(param(p, "height", 1)), segments);
    }
    if (s.kind == "room") {
        glm::vec3 lo(param(p, "lo_x", -5), param(p, "lo_y", 0), param(p, "lo_z", -5));
        glm::vec3 hi(param(p, "hi_x", 5), param(p, "hi_y", 5), param(p, "hi_z", 5));
        Mesh m = makeRoom(lo, hi, float(param(p, "uv_scale", 1)));
        if (p.count("part")) {
            const int pi = countParam(p, "part", 0, 0);
            if (pi >= int(m.parts.size())) throw Error("room part out of range");
            m = extractPart(m, uint32_t(pi));
        }
        return m;
    }
    if (s.kind == "teapot") {
        const int level = countParam(p, "level", 25, 1);
        limitTriangles(2.0 * 32 * level * level);  // Newell's 32 patches, level² quads each
        return tessellateTeapot(loadTeapotPatches(dataDir() / "teapot.txt"), level);
    }
    if (s.kind == "cup") {
        Scene tmp;
        tmp.materials.push_back({});
        addCup(tmp, 0, glm::mat4(1.0f));
        return tmp.meshes[0];
    }
    if (s.kind == "chessboard") return makeChessboard(float(param(p, "square_size", 1)));
    return makeChessPiece(s.path, countParam(p, "segments", 40, 3));  // chess_piece
}

// " (radius 0, slices 8)": a shape's parameters as the scene gives them, for messages.
std::string paramsText(const MeshSource& s) {
    std::string out;
    if (!s.path.empty()) out = "piece " + s.path;
    for (const auto& [k, v] : s.params) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", v);
        out += (out.empty() ? "" : ", ") + k + " " + buf;
    }
    return out.empty() ? out : " (" + out + ")";
}

// The mesh an object names: a file (loadMesh has validated it) or a built-in shape, which
// is validated here with its parameters in the message (a cube of half_size 0 has no
// triangle of non-zero area). Every error names the scene file and the object.
Mesh meshFromSource(const Ctx& c, const MeshSource& s, const std::string& where) {
    static const std::set<std::string> shapes = {"sphere", "cube",  "torus",      "cylinder",   "room",
                                                 "teapot", "cup",   "chessboard", "chess_piece"};
    Mesh m;
    if (s.kind == "file") {
        try {
            // "cgal:NAME": a mesh of Debian's libcgal-demo (cgal_meshes.h), closed if it has holes.
            if (s.path.rfind("cgal:", 0) == 0) {
                m = loadCgalMesh(s.path.substr(5));
                fillHoles(m);
            } else {
                m = loadMesh(c.resolve(s.path));
            }
        } catch (const Error& e) {
            c.fail(where + ": " + e.what());
        }
    } else if (shapes.count(s.kind)) {
        const std::string shape = where + ": shape '" + s.kind + "'" + paramsText(s);
        try {
            m = makeShape(s);
        } catch (const Error& e) {
            c.fail(shape + ": " + e.what());
        }
        validateMesh(m, c.what + ": " + shape);
    } else {
        c.fail(where + ": unknown shape '" + s.kind +
               "' (sphere, cube, torus, cylinder, room, teapot, cup, chessboard, chess_piece)");
    }
    m.source = s;
    return m;
}

}  // namespace

Scene parseSceneJson(const std::string& text, const std::filesystem::path& baseDir,
                     const std::string& what, std::vector<std::string>* warnings) {
    Ctx c{what, baseDir, warnings};
    json root;
    try {
        root = json::parse(text);
    } catch (const json::exception& e) {  // parse_error, and out_of_range for numbers
        c.fail(std::string("malformed JSON: ") + e.what());  // past double (fuzz/regressions/)
    }
    checkKeys(c, root, "scene", {"name", "ambient", "environment", "textures", "materials", "objects",
                                 "cameras", "lights", "viewpoint_paths"});
    Scene scene;
    scene.name = stringOr(c, root, "name", std::filesystem::path(what).stem().string(), "scene");
    scene.ambient = vec3Or(c, root, "ambient", scene.ambient, "scene");
    auto arrayOf = [&](const char* key) -> const json& {
        static const json empty = json::array();
        if (!root.contains(key)) return empty;
        if (!root[key].is_array()) c.fail(std::string(key) + " must be an array");
        return root[key];
    };
    if (root.contains("environment")) {
        const json& e = root["environment"];
        checkKeys(c, e, "environment",
                  {"type", "color", "zenith", "horizon", "ground", "file", "intensity", "rotate"});
        Environment& env = scene.environment;
        std::string type = stringOr(c, e, "type", "constant", "environment");
        env.color = vec3Or(c, e, "color", env.color, "environment");
        env.zenith = vec3Or(c, e, "zenith", env.zenith, "environment");
        env.horizon = vec3Or(c, e, "horizon", env.horizon, "environment");
        env.ground = vec3Or(c, e, "ground", env.ground, "environment");
        env.intensity = floatOr(c, e, "intensity", 1.0f, "environment");
        env.rotateDegrees = floatOr(c, e, "rotate", 0.0f, "environment");
        if (!(env.intensity >= 0.0f)) c.fail("environment.intensity must be ≥ 0");
        if (type == "constant") env.kind = EnvironmentKind::Constant;
        else if (type == "gradient") env.kind = EnvironmentKind::Gradient;
        else if (type == "image") {
            env.kind = EnvironmentKind::Image;
            env.path = stringOr(c, e, "file", "", "environment");
            if (env.path.empty()) c.fail("environment of type image needs a file");
            // "blender:NAME": one of the CC0 worlds of Debian's blender-data (scene.h).
            const std::string prefix = "blender:";
            try {
                const std::filesystem::path file = env.path.rfind(prefix, 0) == 0
                                                       ? blenderWorldPath(env.path.substr(prefix.size()))
                                                       : c.resolve(env.path);
                env.image = std::make_shared<Image>(readEnvironmentImage(file));
            } catch (const Error& err) {
                c.fail(std::string("environment: ") + err.what());
            }
        } else c.fail("environment: unknown type '" + type + "' (constant, gradient, image)");
    }
    for (size_t i = 0; i < arrayOf("textures").size(); ++i) {
        const json& t = root["textures"][i];
        const std::string where = "textures[" + std::to_string(i) + "]";
        checkKeys(c, t, where, {"name", "type", "color_a", "color_b", "scale", "file"});
        Texture tex;
        tex.name = stringOr(c, t, "name", "", where);
        if (tex.name.empty()) c.fail(where + " needs a name");
        try {
            tex.kind = textureKindFromName(stringOr(c, t, "type", "checker", where));
        } catch (const Error& e) {
            c.fail(where + " '" + tex.name + "': " + e.what());
        }
        tex.colorA = vec3Or(c, t, "color_a", tex.colorA, where);
        tex.colorB = vec3Or(c, t, "color_b", tex.colorB, where);
        tex.scale = floatOr(c, t, "scale", tex.kind == TextureKind::Image ? 1.0f : tex.scale, where);
        if (tex.kind == TextureKind::Image) {
            tex.path = stringOr(c, t, "file", "", where);
            try {
                tex.image = std::make_shared<Image>(readImage(c.resolve(tex.path)));
            } catch (const Error& e) {
                // A missing picture should not stop a render: magenta marks it (Texture::eval).
                c.warn("texture '" + tex.name + "': " + e.what() + "; drawn magenta");
            }
        }
        scene.addTexture(tex);
    }
    for (size_t i = 0; i < arrayOf("materials").size(); ++i) {
        const json& m = root["materials"][i];
        const std::string where = "materials[" + std::to_string(i) + "]";
        checkKeys(c, m, where, {"name", "type", "diffuse", "texture", "reflectance", "fresnel", "ior",
                                "transmittance"});
        Material mat;
        mat.name = stringOr(c, m, "name", "", where);
        if (mat.name.empty()) c.fail(where + " needs a name");
        try {
            mat.type = materialTypeFromName(stringOr(c, m, "type", "diffuse", where));
        } catch (const Error& e) {
            c.fail(where + " '" + mat.name + "': " + e.what());
        }
        mat.diffuse = vec3Or(c, m, "diffuse", mat.type == MaterialType::Diffuse ? mat.diffuse : glm::vec3(0.0f), where);
        mat.reflectance = vec3Or(c, m, "reflectance", mat.reflectance, where);
        mat.ior = floatOr(c, m, "ior", mat.ior, where);
        mat.transmittance = vec3Or(c, m, "transmittance", mat.transmittance, where);
        std::string fres = stringOr(c, m, "fresnel", "constant", where);
        if (fres == "schlick") mat.fresnel = MirrorFresnel::Schlick;
        else if (fres == "constant") mat.fresnel = MirrorFresnel::Constant;
        else c.fail(where + ": unknown fresnel '" + fres + "' (constant, schlick)");
        if (m.contains("texture")) {
            std::string tn = stringOr(c, m, "texture", "", where);
            mat.diffuseTexture = scene.findTexture(tn);
            if (mat.diffuseTexture < 0) c.fail(where + " '" + mat.name + "': unknown texture '" + tn + "'");
        }
        if (mat.type == MaterialType::Glass && !(mat.ior > 0.0f)) c.fail(where + ": ior must be > 0");
        scene.addMaterial(mat);
    }
    std::map<std::string, uint32_t> meshCache;
    for (size_t i = 0; i < arrayOf("objects").size(); ++i) {
        const json& o = root["objects"][i];
        const std::string where = "objects[" + std::to_string(i) + "]";
        checkKeys(c, o, where, {"name", "shape", "mesh", "params", "piece", "material", "transform"});
        std::string name = stringOr(c, o, "name", "object" + std::to_string(i), where);
        MeshSource src;
        if (o.contains("mesh")) {
            src.kind = "file";
            src.path = stringOr(c, o, "mesh", "", where);
        } else if (o.contains("shape")) {
            src.kind = stringOr(c, o, "shape", "", where);
            src.path = stringOr(c, o, "piece", "", where);
            if (o.contains("params")) {
                if (!o["params"].is_object()) c.fail(where + ".params must be an object");
                for (auto it = o["params"].begin(); it != o["params"].end(); ++it) {
                    if (!it.value().is_number()) c.fail(where + ".params." + it.key() + " must be a number");
                    src.params[it.key()] = it.value().get<double>();
                }
            }
        } else {
            c.fail(where + " '" + name + "' needs a \"shape\" or a \"mesh\" file");
        }
        std::string matName = stringOr(c, o, "material", "", where);
        int mat = scene.findMaterial(matName);
        if (mat < 0) c.fail(where + " '" + name + "': unknown material '" + matName + "'");
        std::string key = json({src.kind, src.path, src.params}).dump();
        auto it = meshCache.find(key);
        uint32_t mesh;
        if (it != meshCache.end()) {
            mesh = it->second;
        } else {
            mesh = scene.addMesh(meshFromSource(c, src, where + " '" + name + "'"));
            meshCache[key] = mesh;
        }
        glm::mat4 xf = o.contains("transform") ? transformOf(c, o["transform"], where + ".transform")
                                               : glm::mat4(1.0f);
        scene.addObject(name, mesh, uint32_t(mat), xf);
    }
    for (size_t i = 0; i < arrayOf("cameras").size(); ++i) {
        const json& j = root["cameras"][i];
        const std::string where = "cameras[" + std::to_string(i) + "]";
        checkKeys(c, j, where, {"name", "eye", "target", "up", "fov"});
        Camera cam;
        cam.name = stringOr(c, j, "name", "camera" + std::to_string(i), where);
        cam.eye = vec3Or(c, j, "eye", cam.eye, where);
        cam.target = vec3Or(c, j, "target", cam.target, where);
        cam.up = vec3Or(c, j, "up", cam.up, where);
        cam.fovYDegrees = floatOr(c, j, "fov", cam.fovYDegrees, where);
        if (!(cam.fovYDegrees > 0.0f && cam.fovYDegrees < 180.0f)) c.fail(where + ": fov must be in (0, 180)");
        scene.cameras.push_back(cam);
    }
    for (size_t i = 0; i < arrayOf("lights").size(); ++i) {
        const json& j = root["lights"][i];
        const std::string where = "lights[" + std::to_string(i) + "]";
        checkKeys(c, j, where, {"name", "position", "intensity"});
        PointLight l;
        l.name = stringOr(c, j, "name", "light" + std::to_string(i), where);
        l.position = vec3Or(c, j, "position", l.position, where);
        l.intensity = vec3Or(c, j, "intensity", l.intensity, where);
        scene.lights.push_back(l);
    }
    for (size_t i = 0; i < arrayOf("viewpoint_paths").size(); ++i) {
        const json& j = root["viewpoint_paths"][i];
        const std::string where = "viewpoint_paths[" + std::to_string(i) + "]";
        checkKeys(c, j, where, {"name", "center", "radius", "height", "start", "step", "count", "fov"});
        ViewpointPath p;
        p.name = stringOr(c, j, "name", "path" + std::to_string(i), where);
        p.center = vec3Or(c, j, "center", p.center, where);
        p.radius = floatOr(c, j, "radius", p.radius, where);
        p.height = floatOr(c, j, "height", p.height, where);
        p.startDegrees = floatOr(c, j, "start", p.startDegrees, where);
        p.stepDegrees = floatOr(c, j, "step", p.stepDegrees, where);
        float count = floatOr(c, j, "count", float(p.count), where);
        if (!(count >= 1.0f)) c.fail(where + ": count must be ≥ 1");
        p.count = uint32_t(count);
        p.fovYDegrees = floatOr(c, j, "fov", p.fovYDegrees, where);
        scene.viewpointPaths.push_back(p);
    }
    if (scene.objects.empty()) c.fail("the scene has no objects");
    if (scene.cameras.empty()) {
        c.warn("no cameras; adding one looking at the origin from +z");
        scene.cameras.push_back({"default", {0, 2, 10}, {0, 0, 0}, {0, 1, 0}, 40.0f});
    }
    // The meshes again as each object's transform places them, and the scene's extent;
    // the messages name this file (scene.sourceFile is set by loadSceneJson, afterwards).
    for (const std::string& w : validateScene(scene, c.what)) c.warnAsIs(w);
    return scene;
}

Scene loadSceneJson(const std::filesystem::path& path, std::vector<std::string>* warnings) {
    std::ifstream in(path);
    if (!in) throw Error(path.string() + ": cannot open scene file");
    std::stringstream ss;
    ss << in.rdbuf();
    if (ss.str().find_first_not_of(" \t\r\n") == std::string::npos)
        throw Error(path.string() + ": scene file is empty");
    Scene s = parseSceneJson(ss.str(), path.parent_path(), path.string(), warnings);
    s.sourceFile = path;
    return s;
}

std::string sceneToJson(const Scene& scene) {
    json root;
    root["name"] = scene.name;
    root["ambient"] = toJson(scene.ambient);
    const Environment& e = scene.environment;
    json env;
    switch (e.kind) {
        case EnvironmentKind::Constant: env = {{"type", "constant"}, {"color", toJson(e.color)}}; break;
        case EnvironmentKind::Gradient:
            env = {{"type", "gradient"}, {"zenith", toJson(e.zenith)}, {"horizon", toJson(e.horizon)},
                   {"ground", toJson(e.ground)}};
            break;
        case EnvironmentKind::Image:
            env = {{"type", "image"}, {"file", e.path}, {"intensity", e.intensity}};
            if (e.rotateDegrees != 0.0f) env["rotate"] = e.rotateDegrees;
            break;
    }
    root["environment"] = env;
    root["textures"] = json::array();
    for (const Texture& t : scene.textures) {
        json j = {{"name", t.name}, {"type", textureKindName(t.kind)}, {"scale", t.scale}};
        if (t.kind == TextureKind::Image) j["file"] = t.path;
        else j["color_a"] = toJson(t.colorA), j["color_b"] = toJson(t.colorB);
        root["textures"].push_back(j);
    }
    root["materials"] = json::array();
    for (const Material& m : scene.materials) {
        json j = {{"name", m.name}, {"type", materialTypeName(m.type)}, {"diffuse", toJson(m.diffuse)}};
        if (m.diffuseTexture >= 0) j["texture"] = scene.textures[size_t(m.diffuseTexture)].name;
        if (m.type == MaterialType::Mirror) {
            j["reflectance"] = toJson(m.reflectance);
            j["fresnel"] = m.fresnel == MirrorFresnel::Schlick ? "schlick" : "constant";
        }
        if (m.type == MaterialType::Glass) {
            j["ior"] = m.ior;
            j["transmittance"] = toJson(m.transmittance);
        }
        root["materials"].push_back(j);
    }
    root["objects"] = json::array();
    for (const Object& o : scene.objects) {
        const Mesh& mesh = scene.meshes[o.mesh];
        json j = {{"name", o.name}, {"material", scene.materials[o.material].name}};
        if (mesh.source.kind == "file") {
            j["mesh"] = mesh.source.path;
        } else if (!mesh.source.kind.empty()) {
            j["shape"] = mesh.source.kind;
            if (!mesh.source.path.empty()) j["piece"] = mesh.source.path;
            if (!mesh.source.params.empty()) j["params"] = mesh.source.params;
        } else {
            throw Error("object '" + o.name + "': its mesh has no source to write (made in code)");
        }
        json m = json::array();
        for (int i = 0; i < 16; ++i) m.push_back(glm::value_ptr(o.transform)[i]);
        j["transform"] = {{"matrix", m}};
        root["objects"].push_back(j);
    }
    root["cameras"] = json::array();
    for (const Camera& c : scene.cameras)
        root["cameras"].push_back({{"name", c.name}, {"eye", toJson(c.eye)}, {"target", toJson(c.target)},
                                   {"up", toJson(c.up)}, {"fov", c.fovYDegrees}});
    root["lights"] = json::array();
    for (const PointLight& l : scene.lights)
        root["lights"].push_back(
            {{"name", l.name}, {"position", toJson(l.position)}, {"intensity", toJson(l.intensity)}});
    root["viewpoint_paths"] = json::array();
    for (const ViewpointPath& p : scene.viewpointPaths)
        root["viewpoint_paths"].push_back({{"name", p.name}, {"center", toJson(p.center)},
                                           {"radius", p.radius}, {"height", p.height},
                                           {"start", p.startDegrees}, {"step", p.stepDegrees},
                                           {"count", p.count}, {"fov", p.fovYDegrees}});
    return root.dump(2);
}

void saveSceneJson(const Scene& scene, const std::filesystem::path& path) {
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path);
    if (!out) throw Error(path.string() + ": cannot write scene file");
    out << sceneToJson(scene) << "\n";
}

Scene loadSceneByName(const std::string& fileOrName, std::vector<std::string>* warnings) {
    std::filesystem::path p(fileOrName);
    if (p.extension() == ".json" || std::filesystem::exists(p)) return loadSceneJson(p, warnings);
    const std::vector<std::string> builtin = builtinSceneNames();
    if (std::find(builtin.begin(), builtin.end(), fileOrName) != builtin.end()) {
        // The same warnings a scene file gets (a glass mesh that is not closed: the
        // teapot of glass-teapot), not only those of files.
        Scene scene = makeBuiltinScene(fileOrName);
        for (const std::string& w : validateScene(scene)) {
            if (warnings) warnings->push_back(w);
            else std::fprintf(stderr, "warning: %s\n", w.c_str());
        }
        return scene;
    }
    // The scenes shipped in data/scenes/ by their stem: `--scene forest`.
    const std::filesystem::path shipped = dataDir() / "scenes" / (fileOrName + ".json");
    std::error_code ec;
    if (fileOrName.find('/') == std::string::npos && std::filesystem::is_regular_file(shipped, ec))
        return loadSceneJson(shipped, warnings);
    std::string known;
    for (const std::string& n : builtin) known += (known.empty() ? "" : ", ") + n;
    std::set<std::string> files;  // sorted: the message does not depend on the file system
    for (const auto& e : std::filesystem::directory_iterator(dataDir() / "scenes", ec))
        if (e.path().extension() == ".json") files.insert(e.path().stem().string());
    for (const std::string& n : files) known += ", " + n;
    throw Error("unknown scene '" + fileOrName + "': not a file, a built-in scene or a scene in " +
                (dataDir() / "scenes").lexically_normal().string() + " (known: " + known + ")");
}

}  // namespace rg::ray
