// Two-plane light slabs and their parameter file (Heidrich et al. 1999 §3).
#include "light_slab.h"

#include <nlohmann/json.hpp>

#include <bit>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace rg::lightfield {

namespace fs = std::filesystem;

glm::vec3 LightSlab::eyePoint(int i, int j) const {
    const glm::vec2 d = (stMax - stMin) / glm::vec2(float(S - 1), float(T - 1));
    return {stMin.x + float(i) * d.x, stMin.y + float(j) * d.y, stZ};
}

glm::vec3 LightSlab::windowPoint(float u, float v) const {
    return {uvMin.x + u * (uvMax.x - uvMin.x), uvMin.y + v * (uvMax.y - uvMin.y), uvZ};
}

ray::Ray LightSlab::sampleRay(int i, int j, int k, int l) const {
    const glm::vec3 e = eyePoint(i, j);
    const glm::vec3 w = windowPoint((float(k) + 0.5f) / float(U), (float(l) + 0.5f) / float(V));
    ray::Ray r;
    r.origin = e;
    r.dir = glm::normalize(w - e);
    return r;
}

std::optional<glm::vec4> LightSlab::intersect(const glm::vec3& o, const glm::vec3& d) const {
    if (!(std::abs(d.z) > 1e-12f)) return std::nullopt;
    const float ts = (stZ - o.z) / d.z, tu = (uvZ - o.z) / d.z;
    const glm::vec3 ps = o + ts * d, pu = o + tu * d;
    return glm::vec4(ps.x, ps.y, pu.x, pu.y);
}

glm::vec4 LightSlab::textureCoords(const glm::vec4& stuv) const {
    const float fs = (stuv.x - stMin.x) / (stMax.x - stMin.x) * float(S - 1);
    const float ft = (stuv.y - stMin.y) / (stMax.y - stMin.y) * float(T - 1);
    return {(stuv.z - uvMin.x) / (uvMax.x - uvMin.x), (stuv.w - uvMin.y) / (uvMax.y - uvMin.y),
            (fs + 0.5f) / float(S), (ft + 0.5f) / float(T)};
}

const char* contentName(LightFieldContent c) {
    switch (c) {
        case LightFieldContent::Radiance: return "radiance";
        case LightFieldContent::ParaboloidCoordinates: return "paraboloid-coordinates";
        case LightFieldContent::SlabCoordinates: return "slab-coordinates";
    }
    return "?";
}

void validateSlab(const LightSlab& s, const std::optional<ray::Bounds>& object, const std::string& what) {
    auto fail = [&](const std::string& m) { throw Error(what + ": " + m); };
    if (s.S < 2 || s.T < 2) fail("the (s, t) plane needs at least 2×2 eye points, not " + std::to_string(s.S) + "×" + std::to_string(s.T));
    if (s.U < 1 || s.V < 1 || !std::has_single_bit(unsigned(s.U)) || !std::has_single_bit(unsigned(s.V)))
        fail("the (u, v) resolution " + std::to_string(s.U) + "×" + std::to_string(s.V) +
             " must be powers of two (texture extents on the SGI profiles)");
    if (s.S > 4096 || s.T > 4096 || s.U > 4096 || s.V > 4096) fail("a resolution above 4096");
    const float v[] = {s.stZ, s.uvZ, s.stMin.x, s.stMin.y, s.stMax.x, s.stMax.y, s.uvMin.x, s.uvMin.y, s.uvMax.x, s.uvMax.y};
    for (float x : v)
        if (!std::isfinite(x)) fail("a plane coordinate is not finite");
    if (!(std::abs(s.stZ - s.uvZ) > 1e-6f)) fail("the (s, t) and (u, v) planes coincide (z = " + std::to_string(s.stZ) + ")");
    if (!(s.stMax.x > s.stMin.x && s.stMax.y > s.stMin.y)) fail("the (s, t) plane's extent is empty");
    if (!(s.uvMax.x > s.uvMin.x && s.uvMax.y > s.uvMin.y)) fail("the (u, v) window's extent is empty");
    if (!object) return;
    const ray::Bounds& b = *object;
    const float dir = s.uvZ < s.stZ ? -1.0f : 1.0f;  // from the eye points towards the window
    const float nearZ = dir < 0 ? b.hi.z : b.lo.z;
    if (!((nearZ - s.stZ) * dir > 0.0f))
        fail("the planes do not bound the object: it reaches z = " + std::to_string(nearZ) +
             ", on the near side of the eye-point plane z = " + std::to_string(s.stZ));
    for (int ci = 0; ci < 4; ++ci) {
        const glm::vec3 e = s.eyePoint(ci & 1 ? s.S - 1 : 0, ci & 2 ? s.T - 1 : 0);
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 c(k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z);
            const auto hit = s.intersect(e, c - e);
            if (!hit || hit->z < s.uvMin.x || hit->z > s.uvMax.x || hit->w < s.uvMin.y || hit->w > s.uvMax.y)
                fail("the planes do not bound the object: seen from eye point (" + std::to_string(e.x) + ", " +
                     std::to_string(e.y) + ") its bounding box leaves the (u, v) window");
        }
    }
}

namespace {

nlohmann::json vec2Json(glm::vec2 v) { return {v.x, v.y}; }

LightFieldContent contentByName(const std::string& n, const std::string& what) {
    for (auto c : {LightFieldContent::Radiance, LightFieldContent::ParaboloidCoordinates, LightFieldContent::SlabCoordinates})
        if (n == contentName(c)) return c;
    throw Error(what + ": unknown content '" + n + "' (radiance, paraboloid-coordinates, slab-coordinates)");
}

}  // namespace

void writeLightField(const fs::path& path, const LightField& lf) {
    validateSlab(lf.slab, lf.objectBounds, path.string());
    if (lf.data.size() != lf.slab.samples() * size_t(lf.channels))
        throw Error(path.string() + ": " + std::to_string(lf.data.size()) + " data bytes for a slab of " +
                    std::to_string(lf.slab.samples() * size_t(lf.channels)));
    const LightSlab& s = lf.slab;
    fs::path dataPath = path;
    dataPath += ".bin";
    nlohmann::json j;
    j["format"] = "retroglass-light-slab";
    j["version"] = 1;
    j["content"] = contentName(lf.content);
    j["texel"] = lf.channels == 4 ? "RGBA8" : "RGB8";
    j["st_plane"] = {{"z", s.stZ}, {"min", vec2Json(s.stMin)}, {"max", vec2Json(s.stMax)}, {"samples", {s.S, s.T}}};
    j["uv_plane"] = {{"z", s.uvZ}, {"min", vec2Json(s.uvMin)}, {"max", vec2Json(s.uvMax)}, {"samples", {s.U, s.V}}};
    if (lf.objectBounds)
        j["object_bounds"] = {{"min", {lf.objectBounds->lo.x, lf.objectBounds->lo.y, lf.objectBounds->lo.z}},
                              {"max", {lf.objectBounds->hi.x, lf.objectBounds->hi.y, lf.objectBounds->hi.z}}};
    j["data"] = dataPath.filename().string();
    j["data_bytes"] = lf.data.size();
    j["layout"] = "t, s, v, u, channel; 8 bits each; eye points at grid vertices, window samples at texel centres";
    fs::create_directories(path.parent_path().empty() ? fs::path(".") : path.parent_path());
    std::ofstream(path) << j.dump(2) << "\n";
    std::ofstream out(dataPath, std::ios::binary);
    out.write(reinterpret_cast<const char*>(lf.data.data()), std::streamsize(lf.data.size()));
    if (!out) throw Error(dataPath.string() + ": could not be written");
}

LightField parseLightFieldParams(const std::string& text, const std::string& what, uint64_t* dataBytes,
                                 std::string* dataName) {
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const std::exception& e) {
        throw Error(what + ": not valid JSON (truncated?): " + e.what());
    }
    auto need = [&](const nlohmann::json& o, const char* key, const std::string& where) -> const nlohmann::json& {
        if (!o.is_object() || !o.contains(key)) throw Error(what + ": missing \"" + key + "\"" + where);
        return o.at(key);
    };
    auto number = [&](const nlohmann::json& v, const std::string& name) {
        if (!v.is_number()) throw Error(what + ": \"" + name + "\" must be a number");
        return v.get<double>();
    };
    auto integer = [&](const nlohmann::json& v, const std::string& name) -> int64_t {
        if (!v.is_number_integer()) throw Error(what + ": \"" + name + "\" must be an integer");
        return v.get<int64_t>();
    };
    auto pair = [&](const nlohmann::json& v, const std::string& name) {
        if (!v.is_array() || v.size() != 2) throw Error(what + ": \"" + name + "\" must be a pair of numbers");
        return glm::vec2(float(number(v[0], name)), float(number(v[1], name)));
    };
    try {
        if (!j.is_object()) throw Error(what + ": the parameter file is not a JSON object");
        const auto& fmt = need(j, "format", "");
        if (!fmt.is_string() || fmt.get<std::string>() != "retroglass-light-slab")
            throw Error(what + ": \"format\" is not \"retroglass-light-slab\"");
        if (integer(need(j, "version", ""), "version") != 1) throw Error(what + ": unknown version (this reader knows 1)");
        LightField lf;
        const auto& content = need(j, "content", "");
        if (!content.is_string()) throw Error(what + ": \"content\" must be a string");
        lf.content = contentByName(content.get<std::string>(), what);
        const auto& texel = need(j, "texel", "");
        if (!texel.is_string() || (texel != "RGB8" && texel != "RGBA8")) throw Error(what + ": \"texel\" must be \"RGB8\" or \"RGBA8\"");
        lf.channels = texel == "RGBA8" ? 4 : 3;
        if ((lf.content == LightFieldContent::SlabCoordinates) != (lf.channels == 4))
            throw Error(what + ": content " + contentName(lf.content) + " does not fit texel " + texel.get<std::string>());
        for (const char* plane : {"st_plane", "uv_plane"}) {
            const auto& p = need(j, plane, "");
            const std::string w = std::string(" in \"") + plane + "\"";
            const float z = float(number(need(p, "z", w), std::string(plane) + ".z"));
            const glm::vec2 lo = pair(need(p, "min", w), std::string(plane) + ".min");
            const glm::vec2 hi = pair(need(p, "max", w), std::string(plane) + ".max");
            const auto& n = need(p, "samples", w);
            if (!n.is_array() || n.size() != 2) throw Error(what + ": \"" + std::string(plane) + ".samples\" must be a pair of integers");
            const int64_t a = integer(n[0], std::string(plane) + ".samples"), b = integer(n[1], std::string(plane) + ".samples");
            if (a < 1 || b < 1 || a > 4096 || b > 4096)
                throw Error(what + ": \"" + std::string(plane) + ".samples\" outside [1, 4096]");
            if (plane[0] == 's') {
                lf.slab.stZ = z; lf.slab.stMin = lo; lf.slab.stMax = hi; lf.slab.S = int(a); lf.slab.T = int(b);
            } else {
                lf.slab.uvZ = z; lf.slab.uvMin = lo; lf.slab.uvMax = hi; lf.slab.U = int(a); lf.slab.V = int(b);
            }
        }
        if (j.contains("object_bounds")) {
            const auto& ob = j["object_bounds"];
            auto v3 = [&](const nlohmann::json& v) {
                if (!v.is_array() || v.size() != 3) throw Error(what + ": \"object_bounds\" corners must be 3 numbers");
                return glm::vec3(float(number(v[0], "object_bounds")), float(number(v[1], "object_bounds")),
                                 float(number(v[2], "object_bounds")));
            };
            ray::Bounds b;
            b.lo = v3(need(ob, "min", " in \"object_bounds\""));
            b.hi = v3(need(ob, "max", " in \"object_bounds\""));
            if (!(b.hi.x >= b.lo.x && b.hi.y >= b.lo.y && b.hi.z >= b.lo.z))
                throw Error(what + ": \"object_bounds\" max is below min");
            lf.objectBounds = b;
        }
        validateSlab(lf.slab, lf.objectBounds, what);
        const int64_t bytes = integer(need(j, "data_bytes", ""), "data_bytes");
        const uint64_t expect = uint64_t(lf.slab.samples()) * uint64_t(lf.channels);
        if (bytes < 0 || uint64_t(bytes) != expect)
            throw Error(what + ": \"data_bytes\" is " + std::to_string(bytes) + " but " + std::to_string(lf.slab.S) + "·" +
                        std::to_string(lf.slab.T) + "·" + std::to_string(lf.slab.U) + "·" + std::to_string(lf.slab.V) +
                        "·" + std::to_string(lf.channels) + " = " + std::to_string(expect));
        const auto& data = need(j, "data", "");
        if (!data.is_string() || data.get<std::string>().empty()) throw Error(what + ": \"data\" must name the data file");
        const std::string name = data.get<std::string>();
        if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos || name == "..")
            throw Error(what + ": \"data\" must be a file name beside the parameter file, not a path");
        if (dataBytes) *dataBytes = expect;
        if (dataName) *dataName = name;
        return lf;
    } catch (const nlohmann::json::exception& e) {
        throw Error(what + ": malformed parameter file: " + e.what());
    }
}

LightField readLightField(const fs::path& path) {
    std::ifstream in(path);
    if (!in) throw Error(path.string() + ": cannot open the light-field parameter file");
    std::stringstream ss;
    ss << in.rdbuf();
    uint64_t bytes = 0;
    std::string name;
    LightField lf = parseLightFieldParams(ss.str(), path.string(), &bytes, &name);
    const fs::path dataPath = path.parent_path() / name;
    std::error_code ec;
    const uintmax_t size = fs::file_size(dataPath, ec);
    if (ec) throw Error(path.string() + ": its data file " + dataPath.string() + " cannot be read");
    if (size != bytes)
        throw Error(path.string() + ": its data file " + dataPath.string() + " holds " + std::to_string(size) +
                    " bytes, the slab needs " + std::to_string(bytes) + (size < bytes ? " (truncated)" : ""));
    lf.data.resize(bytes);
    std::ifstream d(dataPath, std::ios::binary);
    d.read(reinterpret_cast<char*>(lf.data.data()), std::streamsize(bytes));
    if (!d) throw Error(path.string() + ": reading " + dataPath.string() + " failed");
    return lf;
}

}  // namespace rg::lightfield
