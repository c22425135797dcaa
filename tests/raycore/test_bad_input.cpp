// Bad input: each refused with an rg::Error (or a warning) naming the file and the
// problem, never a crash.
#include <gtest/gtest.h>

#include <limits>

#include "core/error.h"
#include "raycore/accel.h"
#include "raycore/image.h"
#include "raycore/mesh_io.h"
#include "raycore/scene_json.h"
#include "raycore/teapot.h"
#include "raycore/tracer_whitted.h"
#include "test_util.h"

namespace rg::ray {
namespace {

using test::expectError;

TEST(BadInput, EmptyMeshFile) {
    auto dir = test::tempDir("empty_mesh");
    test::writeText(dir / "empty.obj", "");
    expectError([&] { loadMesh(dir / "empty.obj"); }, {"empty.obj", "empty"});
    test::writeText(dir / "comments.obj", "# only a comment\n");
    expectError([&] { loadMesh(dir / "comments.obj"); }, {"comments.obj"});
}

TEST(BadInput, MalformedMeshFile) {
    auto dir = test::tempDir("malformed_mesh");
    test::writeText(dir / "bad.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                     "end_header\n1 2\n");
    expectError([&] { loadMesh(dir / "bad.ply"); }, {"bad.ply"});
    test::writeText(dir / "faces.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
    expectError([&] { loadMesh(dir / "faces.obj"); }, {"faces.obj"});
}

TEST(BadInput, MissingMeshFile) {
    expectError([] { loadMesh("/nonexistent/where.obj"); }, {"where.obj", "not found"});
}

TEST(BadInput, NaNPositions) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, std::numeric_limits<float>::quiet_NaN(), 0}};
    m.indices = {0, 1, 2};
    expectError([&] { validateMesh(m, "nan-mesh"); }, {"nan-mesh", "vertex 2", "non-finite"});
    // Through a scene: the Accel refuses it before Embree sees it.
    Scene s;
    s.name = "nan";
    s.addMaterial({});
    s.addObject("broken", s.addMesh(m), 0);
    expectError([&] { Accel a(s); }, {"broken", "non-finite"});
}

TEST(BadInput, NaNInAnObjFile) {
    auto dir = test::tempDir("nan_obj");
    test::writeText(dir / "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    // assimp's OBJ reader may turn "nan" into NaN or into 0; either way no crash, and if it
    // is NaN the error names the file.
    try {
        Mesh m = loadMesh(dir / "nan.obj");
        for (const glm::vec3& p : m.positions) EXPECT_TRUE(std::isfinite(p.x));
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("nan.obj"), std::string::npos) << e.what();
    }
}

TEST(BadInput, IndexOutOfRange) {
    Mesh m;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices = {0, 1, 5};
    expectError([&] { validateMesh(m, "short"); }, {"short", "vertex 5"});
}

TEST(BadInput, MissingTextureIsAWarningAndRenders) {
    auto dir = test::tempDir("missing_texture");
    test::writeText(dir / "s.json", R"({
      "textures": [{"name": "photo", "type": "image", "file": "nowhere.png"}],
      "materials": [{"name": "wall", "type": "diffuse", "texture": "photo"}],
      "objects": [{"name": "box", "shape": "cube", "material": "wall"}],
      "cameras": [{"name": "c", "eye": [0, 0, 5], "target": [0, 0, 0]}],
      "lights": [{"position": [2, 3, 4]}]
    })");
    std::vector<std::string> warnings;
    Scene s = loadSceneJson(dir / "s.json", &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("nowhere.png"), std::string::npos) << warnings[0];
    Accel accel(s);
    RenderOptions o;
    o.width = 8;
    o.height = 8;
    Image img = renderWhitted(accel, s.cameras[0], o);
    EXPECT_GT(img.rgb(4, 4).x, img.rgb(4, 4).y) << "drawn magenta";
}

TEST(BadInput, UnknownMaterialAndTextureAndShape) {
    expectError([] {
        parseSceneJson(R"({"materials":[{"name":"a"}],
                           "objects":[{"name":"o","shape":"cube","material":"chrome"}]})",
                       ".", "scene.json");
    }, {"scene.json", "objects[0]", "unknown material 'chrome'"});
    expectError([] {
        parseSceneJson(R"({"materials":[{"name":"a","texture":"marble"}],"objects":[]})", ".", "t.json");
    }, {"t.json", "unknown texture 'marble'"});
    expectError([] {
        parseSceneJson(R"({"materials":[{"name":"a","type":"velvet"}],"objects":[]})", ".", "v.json");
    }, {"v.json", "velvet"});
    expectError([] {
        parseSceneJson(R"({"materials":[{"name":"a"}],"objects":[{"shape":"dodecahedron","material":"a"}]})",
                       ".", "d.json");
    }, {"d.json", "dodecahedron"});
    expectError([] {
        parseSceneJson(R"({"materials":[{"name":"a"}],"objects":[{"mesh":"gone.obj","material":"a"}]})",
                       "/nonexistent-retroglass-test", "m.json");
    }, {"gone.obj", "not found"});
}

TEST(BadInput, MalformedAndEmptySceneFiles) {
    auto dir = test::tempDir("bad_scene");
    test::writeText(dir / "broken.json", "{\"objects\": [");
    expectError([&] { loadSceneJson(dir / "broken.json"); }, {"broken.json", "malformed JSON"});
    test::writeText(dir / "empty.json", "");
    expectError([&] { loadSceneJson(dir / "empty.json"); }, {"empty.json", "empty"});
    test::writeText(dir / "none.json", "{}");
    expectError([&] { loadSceneJson(dir / "none.json"); }, {"none.json", "no objects"});
    expectError([&] { loadSceneJson(dir / "absent.json"); }, {"absent.json"});
    expectError([] { loadSceneByName("no-such-builtin"); }, {"no-such-builtin", "teapot-in-room"});
}

TEST(BadInput, NonClosedGlassIsAWarning) {
    std::vector<std::string> warnings;
    Scene s = parseSceneJson(R"({
      "materials": [{"name": "glass", "type": "glass", "ior": 1.5}],
      "objects": [{"name": "pot", "shape": "teapot", "params": {"level": 3}, "material": "glass"}],
      "cameras": [{"eye": [0, 2, 8]}]
    })", ".", "glass.json", &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("pot"), std::string::npos);
    EXPECT_NE(warnings[0].find("not closed"), std::string::npos);
    Accel accel(s);  // still renders
    RenderOptions o;
    o.width = 6;
    o.height = 6;
    EXPECT_EQ(renderWhitted(accel, s.cameras[0], o).width, 6);
}

TEST(BadInput, MissingAndBrokenImages) {
    expectError([] { readImage("/nonexistent/env.exr"); }, {"env.exr", "not found"});
    auto dir = test::tempDir("bad_image");
    test::writeText(dir / "fake.png", "this is not a png");
    expectError([&] { readImage(dir / "fake.png"); }, {"fake.png"});
}

TEST(BadInput, MalformedTeapotFile) {
    auto dir = test::tempDir("bad_teapot");
    test::writeText(dir / "t.txt", "patches 1\nlid 1 2 3\nvertices 0\n");
    expectError([&] { loadTeapotPatches(dir / "t.txt"); }, {"t.txt:2", "16"});
    test::writeText(dir / "u.txt", "patches 1\nlid 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 99\nvertices 1\n0 0 0\n");
    expectError([&] { loadTeapotPatches(dir / "u.txt"); }, {"u.txt", "control point 2", "past"});
}

}  // namespace
}  // namespace rg::ray

namespace rg::ray {
namespace {

TEST(MeshFiles, PlyAndGltfLoadThroughAssimp) {
    auto dir = test::tempDir("mesh_formats");
    // A tetrahedron as ASCII PLY.
    test::writeText(dir / "tet.ply",
                    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
                    "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    Mesh ply = loadMesh(dir / "tet.ply");
    EXPECT_EQ(ply.triangleCount(), 4u);
    EXPECT_EQ(ply.normals.size(), ply.positions.size());
    // One triangle as glTF 2.0 with an external buffer: 3 float3 positions, 3 uint16 indices.
    {
        std::ofstream bin(dir / "tri.bin", std::ios::binary);
        const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
        const uint16_t idx[4] = {0, 1, 2, 0};  // padded to 4-byte alignment
        bin.write(reinterpret_cast<const char*>(pos), sizeof pos);
        bin.write(reinterpret_cast<const char*>(idx), sizeof idx);
    }
    test::writeText(dir / "tri.gltf", R"({
      "asset": {"version": "2.0"},
      "scenes": [{"nodes": [0]}], "scene": 0, "nodes": [{"mesh": 0}],
      "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
      "buffers": [{"uri": "tri.bin", "byteLength": 44}],
      "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                      {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
      "accessors": [
        {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
         "min": [0, 0, 0], "max": [1, 1, 0]},
        {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]
    })");
    Mesh gltf = loadMesh(dir / "tri.gltf");
    EXPECT_EQ(gltf.triangleCount(), 1u);
    EXPECT_EQ(gltf.positions.size(), 3u);
}

TEST(BadInput, BuiltinScenesWarnLikeSceneFiles) {
    // `raytrace --scene glass-teapot` warns as the same scene written as a file would:
    // Newell's teapot is open (spout, handle and lid meet the body without sharing edges).
    std::vector<std::string> warnings;
    loadSceneByName("glass-teapot", &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("glass-teapot"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("'teapot'"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("not closed"), std::string::npos) << warnings[0];
    warnings.clear();
    loadSceneByName("glass-cube", &warnings);
    EXPECT_TRUE(warnings.empty());
}

}  // namespace
}  // namespace rg::ray
