// Meshes that load but cannot be drawn (issue 16, item 6): none of a part's triangles has a
// non-zero area, or the extent is not finite in float arithmetic, given so or made so by an
// object's transform. Each reader (OBJ, PLY in ASCII and binary, glTF through assimp, scene
// files and their shapes) refuses them with an rg::Error naming the file and the problem
// (the rule: validateMesh in raycore/include/raycore/mesh.h, docs/scene-format.md).
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <tuple>

#include "core/error.h"
#include "raycore/accel.h"
#include "raycore/builtin_scenes.h"
#include "raycore/cgal_meshes.h"
#include "raycore/shapes.h"
#include "raycore/mesh_io.h"
#include "raycore/scene_json.h"
#include "raycore/shapes.h"
#include "raycore/teapot.h"
#include "test_util.h"

namespace rg::ray {
namespace {

using test::expectError;

Mesh triangles(std::vector<glm::vec3> positions) {
    Mesh m;
    m.positions = std::move(positions);
    for (uint32_t i = 0; i < m.positions.size(); ++i) m.indices.push_back(i);
    return m;
}

// ---- the rule, on meshes made in code -------------------------------------------------------

TEST(BadMeshes, ZeroAreaMeansAFloatCrossProductOfZeroLength) {
    // Three points on a point and three on a line.
    expectError([] { validateMesh(triangles({{1, 2, 3}, {1, 2, 3}, {1, 2, 3}}), "point"); },
                {"point", "no triangle of non-zero area",
                 "its one triangle has a float cross product (p1 − p0) × (p2 − p0) of zero length"});
    expectError([] { validateMesh(triangles({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {0, 0, 0}, {0, 0, 0}, {0, 0, 5}}),
                                  "line"); },
                {"line", "no triangle of non-zero area", "each of its 2 triangles"});
    // Zero in float, not in exact arithmetic: the cross product (0, 0, 1e-26) is not the
    // zero vector, but its squared length 1e-52 is below float's smallest denormal, so
    // |n| = 0 and no normal can be made of it (Accel and completeMesh would use (0, 1, 0)).
    const Mesh tiny = triangles({{0, 0, 0}, {1e-13f, 0, 0}, {0, 1e-13f, 0}});
    const glm::vec3 n = glm::cross(tiny.positions[1], tiny.positions[2]);
    ASSERT_NE(n.z, 0.0f);
    ASSERT_EQ(glm::length(n), 0.0f);
    expectError([&] { validateMesh(tiny, "tiny"); }, {"tiny", "no triangle of non-zero area"});
    // Small but normal-range: |n| = 1e-18 > 0 is accepted.
    validateMesh(triangles({{0, 0, 0}, {1e-9f, 0, 0}, {0, 1e-9f, 0}}), "small");
    // Huge triangles: a finite extent (1e10), but |n|² = 1e40 overflows float.
    expectError([] { validateMesh(triangles({{0, 0, 0}, {1e10f, 0, 0}, {0, 1e10f, 0}}), "huge"); },
                {"huge", "no triangle of finite, non-zero area", "whose length overflows float"});
}

TEST(BadMeshes, OneTriangleOfNonZeroAreaIsEnoughAndTheOthersAreKept) {
    Mesh m = triangles({{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                        {0, 0, 0}, {1, 1, 1}, {2, 2, 2}});
    validateMesh(m, "mixed");
    EXPECT_EQ(m.triangleCount(), 3u);
    // Real meshes carry degenerate triangles: the teapot's patches meet in points at the top
    // of the lid and the middle of the bottom, and it must still load whole.
    const Mesh pot = tessellateTeapot(loadTeapotPatches(dataDir() / "teapot.txt"), 6);
    int degenerate = 0;
    for (size_t t = 0; t < pot.triangleCount(); ++t) {
        const glm::vec3& a = pot.positions[pot.indices[3 * t]];
        degenerate += glm::length(glm::cross(pot.positions[pot.indices[3 * t + 1]] - a,
                                             pot.positions[pot.indices[3 * t + 2]] - a)) == 0.0f;
    }
    EXPECT_GT(degenerate, 0);
    validateMesh(pot, "teapot");
}

TEST(BadMeshes, ExtentNotFiniteInFloatArithmetic) {
    // Every coordinate finite, max − min = 6e38 is not.
    expectError([] { validateMesh(triangles({{-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 1, 0}}), "wide"); },
                {"wide", "extent not finite in float arithmetic (x from -3e+38 to 3e+38)"});
    expectError([] { validateMesh(triangles({{0, -3e38f, 0}, {1, 3e38f, 0}, {0, 0, 1}}), "tall"); },
                {"tall", "(y from -3e+38 to 3e+38)"});
    // Each axis spans 2e19, but the diagonal's squared length 8e38 is past float.
    expectError([] { validateMesh(triangles({{-1e19f, -1e19f, 0}, {1e19f, -1e19f, 0}, {1e19f, 1e19f, 0}}),
                                  "diagonal"); },
                {"diagonal", "extent not finite in float arithmetic", "diagonal"});
}

TEST(BadMeshes, EveryPartNeedsATriangleOfNonZeroArea) {
    Mesh good = triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    Mesh flat = triangles({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}});
    Mesh both;
    appendMesh(both, good, "body");
    appendMesh(both, flat, "label");
    expectError([&] { validateMesh(both, "sign.obj"); },
                {"sign.obj: part 'label': no triangle of non-zero area"});
}

TEST(BadMeshes, TheAccelRefusesThemBeforeEmbree) {
    // A scene made in code (no reader involved) reaches the renderers only through Accel.
    Scene s;
    s.name = "coded";
    s.addMaterial({});
    s.addObject("needle", s.addMesh(triangles({{0, 0, 0}, {0, 1, 0}, {0, 2, 0}})), 0);
    expectError([&] { Accel a(s); }, {"scene 'coded'", "object 'needle'", "no triangle of non-zero area"});
}

TEST(BadMeshes, EveryBuiltinSceneIsAccepted) {
    for (const std::string& name : builtinSceneNames()) {
        SCOPED_TRACE(name);
        BuiltinOptions o;
        o.teapotLevel = 6;
        EXPECT_NO_THROW(validateScene(makeBuiltinScene(name, o)));
    }
}

// ---- files ---------------------------------------------------------------------------------

// Little-endian bytes of floats and 32-bit integers, for binary PLY and glTF buffers.
template <class T>
std::string bytesOf(std::initializer_list<T> values) {
    std::string out;
    for (T v : values) {
        char b[sizeof(T)];
        std::memcpy(b, &v, sizeof(T));
        out.append(b, sizeof(T));
    }
    return out;
}

std::string base64(const std::string& in) {
    static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < in.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(in[i])) << 16;
        if (i + 1 < in.size()) v |= uint32_t(uint8_t(in[i + 1])) << 8;
        if (i + 2 < in.size()) v |= uint8_t(in[i + 2]);
        out += abc[(v >> 18) & 63];
        out += abc[(v >> 12) & 63];
        out += i + 1 < in.size() ? abc[(v >> 6) & 63] : '=';
        out += i + 2 < in.size() ? abc[v & 63] : '=';
    }
    return out;
}

void writeBytes(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
}

std::string plyHeader(const char* format, int vertices, int faces) {
    return std::string("ply\nformat ") + format + " 1.0\nelement vertex " + std::to_string(vertices) +
           "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
           std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
}

// A glTF 2.0 file with its buffer embedded as base64: one mesh per entry of `meshes`, each
// a named list of triangles (three float3 positions each, no indices).
std::string gltfOf(const std::vector<std::pair<std::string, std::vector<glm::vec3>>>& meshes) {
    std::string buffer, meshJson, views, accessors, nodes, nodeList;
    for (size_t i = 0; i < meshes.size(); ++i) {
        const auto& [name, pos] = meshes[i];
        glm::vec3 lo(1e38f), hi(-1e38f);
        const size_t offset = buffer.size();
        for (const glm::vec3& p : pos) {
            buffer += bytesOf<float>({p.x, p.y, p.z});
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        auto vec = [](glm::vec3 v) {
            char b[96];
            std::snprintf(b, sizeof b, "[%.9g, %.9g, %.9g]", double(v.x), double(v.y), double(v.z));
            return std::string(b);
        };
        const std::string sep = i ? ", " : "";
        meshJson += sep + R"({"name": ")" + name + R"(", "primitives": [{"attributes": {"POSITION": )" +
                    std::to_string(i) + "}}]}";
        views += sep + R"({"buffer": 0, "byteOffset": )" + std::to_string(offset) +
                 R"(, "byteLength": )" + std::to_string(buffer.size() - offset) + "}";
        accessors += sep + R"({"bufferView": )" + std::to_string(i) +
                     R"(, "componentType": 5126, "count": )" + std::to_string(pos.size()) +
                     R"(, "type": "VEC3", "min": )" + vec(lo) + R"(, "max": )" + vec(hi) + "}";
        nodes += sep + R"({"mesh": )" + std::to_string(i) + "}";
        nodeList += sep + std::to_string(i);
    }
    return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [)" + nodeList +
           R"(]}], "nodes": [)" + nodes + R"(], "meshes": [)" + meshJson +
           R"(], "buffers": [{"byteLength": )" + std::to_string(buffer.size()) +
           R"(, "uri": "data:application/octet-stream;base64,)" + base64(buffer) +
           R"("}], "bufferViews": [)" + views + R"(], "accessors": [)" + accessors + "]}";
}

TEST(BadMeshes, ObjFiles) {
    const auto dir = test::tempDir("obj");
    test::writeText(dir / "needle.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nv 0 0 0\nf 1 2 3\nf 1 4 4\n");
    expectError([&] { loadMesh(dir / "needle.obj"); }, {"needle.obj", "no triangle of non-zero area"});
    test::writeText(dir / "wide.obj", "v -3e38 0 0\nv 3e38 0 0\nv 0 1 0\nf 1 2 3\n");
    expectError([&] { loadMesh(dir / "wide.obj"); },
                {"wide.obj", "extent not finite in float arithmetic (x from -3"});
    // Degenerate triangles among good ones load, all of them kept.
    test::writeText(dir / "mixed.obj",
                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 3 3 3\n");
    EXPECT_EQ(loadMesh(dir / "mixed.obj").triangleCount(), 3u);
}

TEST(BadMeshes, PlyFilesAsciiAndBinary) {
    const auto dir = test::tempDir("ply");
    test::writeText(dir / "needle.ply", plyHeader("ascii", 3, 1) + "0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n");
    expectError([&] { loadMesh(dir / "needle.ply"); }, {"needle.ply", "no triangle of non-zero area"});
    const std::string face = std::string(1, '\3') + bytesOf<int32_t>({0, 1, 2});
    writeBytes(dir / "needle-binary.ply",
               plyHeader("binary_little_endian", 3, 1) +
                   bytesOf<float>({5, 5, 5, 5, 5, 5, 5, 5, 5}) + face);
    expectError([&] { loadMesh(dir / "needle-binary.ply"); },
                {"needle-binary.ply", "no triangle of non-zero area"});
    writeBytes(dir / "wide-binary.ply",
               plyHeader("binary_little_endian", 3, 1) +
                   bytesOf<float>({0, 0, -3e38f, 1, 0, 0, 0, 0, 3e38f}) + face);
    expectError([&] { loadMesh(dir / "wide-binary.ply"); },
                {"wide-binary.ply", "extent not finite in float arithmetic (z from -3e+38 to 3e+38)"});
}

TEST(BadMeshes, GltfFilesWithAnEmbeddedBuffer) {
    const auto dir = test::tempDir("gltf");
    test::writeText(dir / "needle.gltf", gltfOf({{"needle", {{0, 0, 0}, {0, 1, 0}, {0, 2, 0}}}}));
    expectError([&] { loadMesh(dir / "needle.gltf"); }, {"needle.gltf", "no triangle of non-zero area"});
    test::writeText(dir / "wide.gltf", gltfOf({{"wide", {{-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 1, 0}}}}));
    expectError([&] { loadMesh(dir / "wide.gltf"); },
                {"wide.gltf", "extent not finite in float arithmetic (x from -3e+38 to 3e+38)"});
    // Two meshes, the second one flat: the message names it as a part of the file.
    test::writeText(dir / "sign.gltf", gltfOf({{"board", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}},
                                               {"label", {{0, 0, 1}, {1, 0, 1}, {2, 0, 1}}}}));
    expectError([&] { loadMesh(dir / "sign.gltf"); },
                {"sign.gltf: part 'label': no triangle of non-zero area"});
    // The same file without the flat mesh loads: the files above fail for their geometry.
    test::writeText(dir / "board.gltf", gltfOf({{"board", {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}}));
    EXPECT_EQ(loadMesh(dir / "board.gltf").triangleCount(), 1u);
}

TEST(BadMeshes, SceneFilesNameTheSceneTheObjectAndTheMeshFile) {
    const auto dir = test::tempDir("scenes");
    test::writeText(dir / "needle.obj", "v 0 0 0\nv 1 1 1\nv 2 2 2\nf 1 2 3\n");
    test::writeText(dir / "needle.ply", plyHeader("ascii", 3, 1) + "0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n");
    writeBytes(dir / "wide.ply", plyHeader("binary_little_endian", 3, 1) +
                                     bytesOf<float>({0, 0, -3e38f, 1, 0, 0, 0, 0, 3e38f}) +
                                     std::string(1, '\3') + bytesOf<int32_t>({0, 1, 2}));
    test::writeText(dir / "needle.gltf", gltfOf({{"needle", {{0, 0, 0}, {0, 1, 0}, {0, 2, 0}}}}));
    test::writeText(dir / "wide.gltf", gltfOf({{"wide", {{-3e38f, 0, 0}, {3e38f, 0, 0}, {0, 1, 0}}}}));
    for (const char* file : {"needle.obj", "needle.ply", "wide.ply", "needle.gltf", "wide.gltf"}) {
        SCOPED_TRACE(file);
        test::writeText(dir / "s.json", std::string(R"({"materials": [{"name": "m"}],
            "objects": [{"name": "ok", "shape": "cube", "material": "m"},
                        {"name": "bad", "mesh": ")") + file + R"(", "material": "m"}]})");
        const std::string problem = std::string(file).starts_with("needle")
                                        ? "no triangle of non-zero area"
                                        : "extent not finite in float arithmetic";
        expectError([&] { loadSceneJson(dir / "s.json"); },
                    {(dir / "s.json").string() + ": objects[1] 'bad': ", file, problem});
    }
}

// ---- scene files: shapes and transforms ------------------------------------------------------

Scene sceneWith(const std::string& object, const std::string& second = "") {
    return parseSceneJson(R"({"materials": [{"name": "m"}], "cameras": [{"eye": [0, 0, 9]}],
                              "objects": [)" + object + (second.empty() ? "" : ", " + second) + "]}",
                          "/nonexistent-retroglass-test", "shapes.json");
}

TEST(BadMeshes, ShapesWhoseParametersLeaveNoArea) {
    // A sphere of radius 0: the lathe drops the rings that collapse, leaving no triangle.
    expectError([] { sceneWith(R"({"name": "dot", "shape": "sphere", "params": {"radius": 0}, "material": "m"})"); },
                {"shapes.json: objects[0] 'dot': shape 'sphere' (radius 0)", "has no triangles"});
    expectError([] { sceneWith(R"({"name": "c", "shape": "cube", "params": {"half_size": 0}, "material": "m"})"); },
                {"shapes.json", "'c'", "shape 'cube' (half_size 0)", "no triangle of non-zero area"});
    // A room of no height: floor and ceiling have area, the walls none, and the first wall
    // is named.
    expectError([] { sceneWith(R"({"name": "r", "shape": "room", "params": {"hi_y": 0}, "material": "m"})"); },
                {"shapes.json", "shape 'room' (hi_y 0)", "part 'wall_-x': no triangle of non-zero area"});
    expectError([] { sceneWith(R"({"name": "t", "shape": "torus", "params": {"major_radius": 0, "minor_radius": 0}, "material": "m"})"); },
                {"shapes.json", "shape 'torus'", "no triangle of non-zero area"});
    // Values past float: a radius of 1e39 is an infinite float.
    expectError([] { sceneWith(R"({"name": "s", "shape": "sphere", "params": {"radius": 1e39}, "material": "m"})"); },
                {"shapes.json", "shape 'sphere' (radius 1e+39)", "non-finite"});
}

TEST(BadMeshes, ShapeCountsMustBeWholeNumbersInRange) {
    // Before: int(1e300) was undefined behaviour and a negative segment count sized a
    // vector past memory (std::length_error, not an rg::Error).
    expectError([] { sceneWith(R"({"shape": "torus", "params": {"major_segments": -4}, "material": "m"})"); },
                {"shapes.json", "shape 'torus' (major_segments -4)", "major_segments must be a whole number from 3"});
    expectError([] { sceneWith(R"({"shape": "teapot", "params": {"level": 1e300}, "material": "m"})"); },
                {"shapes.json", "level must be a whole number"});
    expectError([] { sceneWith(R"({"shape": "sphere", "params": {"slices": 2.5}, "material": "m"})"); },
                {"shapes.json", "slices must be a whole number"});
    expectError([] { sceneWith(R"({"shape": "room", "params": {"part": -1}, "material": "m"})"); },
                {"shapes.json", "part must be a whole number"});
    expectError([] { sceneWith(R"({"shape": "sphere", "params": {"slices": 100000, "stacks": 100000}, "material": "m"})"); },
                {"shapes.json", "20000000000 triangles, more than 16777216"});
}

TEST(BadMeshes, TransformsThatCollapseOrOverflowAMesh) {
    const std::string cube = R"({"name": "box", "shape": "cube", "material": "m", "transform": )";
    expectError([&] { sceneWith(cube + R"({"scale": 0}})"); },
                {"shapes.json: object 'box' as placed by its transform: no triangle of non-zero area"});
    expectError([&] { sceneWith(cube + R"({"scale": 3e38}})"); },
                {"shapes.json: object 'box' as placed by its transform: extent not finite in float "
                 "arithmetic (x from -3e+38 to 3e+38)"});
    expectError([&] { sceneWith(cube + R"({"translate": [1e39, 0, 0]}})"); },
                {"shapes.json: object 'box': its transform has a non-finite entry (row 0, column 3)"});
    // Squashed flat it still has area (the top and bottom faces): accepted.
    EXPECT_NO_THROW(sceneWith(cube + R"({"scale": [1, 0, 1]}})"));
    // Each object fine, but together they span more than float can: Accel's ray offset
    // would be infinite.
    expectError([&] { sceneWith(R"({"name": "a", "shape": "cube", "material": "m", "transform": {"translate": [-2e38, 0, 0]}})",
                                R"({"name": "b", "shape": "cube", "material": "m", "transform": {"translate": [2e38, 0, 0]}})"); },
                {"shapes.json: the objects together: extent not finite in float arithmetic (x from -2e+38 to 2e+38)"});
}

// The fuzz seeds of bad meshes (fuzz/corpus/mesh_loader, fuzz/corpus/scene_json) reach the
// rules above rather than failing earlier, so that the fuzzers start from these paths.
TEST(BadMeshes, FuzzSeedsRaiseTheirErrors) {
    const auto dir = test::tempDir("seeds");
    const std::filesystem::path corpus = test::sourceDir() / "fuzz" / "corpus";
    // The mesh target's first byte picks the extension; the rest is the file.
    for (const auto& [seed, file, problem] :
         std::initializer_list<std::tuple<const char*, const char*, const char*>>{
             {"zero-area-triangles.obj.bin", "seed.obj", "no triangle of non-zero area"},
             {"extent-past-float.ply.bin", "seed.ply", "extent not finite in float arithmetic"},
             {"zero-area-part.gltf.bin", "seed.gltf", "part 'label': no triangle of non-zero area"}}) {
        SCOPED_TRACE(seed);
        std::ifstream in(corpus / "mesh_loader" / seed, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        ASSERT_GT(bytes.size(), 1u);
        writeBytes(dir / file, bytes.substr(1));
        expectError([&] { loadMesh(dir / file); }, {file, problem});
    }
    for (const auto& [seed, problem] : std::initializer_list<std::pair<const char*, const char*>>{
             {"shape-of-no-area.json", "part 'wall_-x': no triangle of non-zero area"},
             {"shape-count-negative.json", "major_segments must be a whole number"},
             {"transform-past-float.json", "object 'b' as placed by its transform: extent not finite"},
             {"transform-scale-zero.json", "object 'gone' as placed by its transform: no triangle"}}) {
        SCOPED_TRACE(seed);
        expectError([&] { loadSceneJson(corpus / "scene_json" / seed); }, {seed, problem});
    }
}

}  // namespace
}  // namespace rg::ray

namespace rg::ray {
namespace {

// cgal:NAME from the installed libcgal-demo archive, through a scene file too; an unknown
// name is an error naming the archive member.
TEST(CgalMeshes, LoadByNameAndRefuseUnknownNames) {
    Mesh dragon = loadCgalMesh("ChineseDragon-10kv");
    EXPECT_EQ(dragon.positions.size(), 10000u);
    EXPECT_FALSE(isClosedManifold(dragon));  // 6 boundary edges, as the spec notes say
    const int added = fillHoles(dragon);
    EXPECT_GT(added, 0);
    EXPECT_TRUE(isClosedManifold(dragon));
    try {
        loadCgalMesh("no-such-mesh");
        FAIL() << "unknown mesh";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("data/meshes/no-such-mesh.off"), std::string::npos) << e.what();
    }
    EXPECT_THROW(loadCgalMesh("../etc/passwd"), Error);
}

// fillHoles on a closed cube with one face removed: the square hole is fanned back closed.
TEST(CgalMeshes, FillHolesClosesAMissingFace) {
    Mesh cube = makeCube(1.0f);
    // Weld the flat-shaded cube's 24 vertices by position so that edges are shared.
    Mesh welded;
    std::vector<uint32_t> remap(cube.positions.size());
    for (size_t i = 0; i < cube.positions.size(); ++i) {
        size_t j = 0;
        while (j < welded.positions.size() && welded.positions[j] != cube.positions[i]) ++j;
        if (j == welded.positions.size()) welded.positions.push_back(cube.positions[i]);
        remap[i] = uint32_t(j);
    }
    for (size_t t = 0; t + 1 < cube.triangleCount(); ++t)  // the last triangle dropped: a hole
        for (int k = 0; k < 3; ++k) welded.indices.push_back(remap[cube.indices[3 * t + size_t(k)]]);
    welded.indices.erase(welded.indices.end() - 3, welded.indices.end());  // and its twin
    completeMesh(welded);
    EXPECT_FALSE(isClosedManifold(welded));
    EXPECT_EQ(fillHoles(welded), 2);  // a quad hole: two triangles
    EXPECT_TRUE(isClosedManifold(welded));
}

}  // namespace
}  // namespace rg::ray
