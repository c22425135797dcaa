// The JSON scene format: the documented example loads, scenes survive a round trip.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "raycore/builtin_scenes.h"
#include "raycore/scene_json.h"
#include "test_util.h"

namespace rg::ray {
namespace {

void expectSameScene(const Scene& a, const Scene& b) {
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.ambient, b.ambient);
    EXPECT_EQ(a.materials, b.materials);
    EXPECT_EQ(a.cameras, b.cameras);
    EXPECT_EQ(a.lights, b.lights);
    EXPECT_EQ(a.viewpointPaths, b.viewpointPaths);
    ASSERT_EQ(a.textures.size(), b.textures.size());
    for (size_t i = 0; i < a.textures.size(); ++i) {
        EXPECT_EQ(a.textures[i].name, b.textures[i].name);
        EXPECT_EQ(a.textures[i].kind, b.textures[i].kind);
        EXPECT_EQ(a.textures[i].colorA, b.textures[i].colorA);
        EXPECT_EQ(a.textures[i].scale, b.textures[i].scale);
    }
    ASSERT_EQ(a.objects.size(), b.objects.size());
    for (size_t i = 0; i < a.objects.size(); ++i) {
        EXPECT_EQ(a.objects[i].name, b.objects[i].name);
        EXPECT_EQ(a.objects[i].material, b.objects[i].material);
        EXPECT_EQ(a.objects[i].transform, b.objects[i].transform) << a.objects[i].name;
        const Mesh& ma = a.meshes[a.objects[i].mesh];
        const Mesh& mb = b.meshes[b.objects[i].mesh];
        EXPECT_EQ(ma.triangleCount(), mb.triangleCount()) << a.objects[i].name;
        EXPECT_EQ(ma.positions, mb.positions) << a.objects[i].name;
        EXPECT_EQ(ma.parts, mb.parts) << a.objects[i].name;
    }
    EXPECT_EQ(a.environment.kind, b.environment.kind);
    EXPECT_EQ(a.environment.color, b.environment.color);
}

TEST(SceneJson, DocumentedExampleLoads) {
    std::vector<std::string> warnings;
    Scene s = loadSceneJson(test::sourceDir() / "data" / "scenes" / "example.json", &warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_GE(s.findObject("teapot"), 0);
    EXPECT_GE(s.findObject("bunny"), 0);
    EXPECT_FALSE(s.cameras.empty());
    EXPECT_FALSE(s.viewpointPaths.empty());
    EXPECT_FALSE(s.lights.empty());
    int teapot = s.findObject("teapot");
    EXPECT_GE(s.meshes[s.objects[size_t(teapot)].mesh].findPart("lid"), 0);
}

// Docs that can't go stale: every built-in scene is listed in docs/scene-format.md.
TEST(SceneJson, EveryBuiltinSceneIsDocumented) {
    std::ifstream in(test::sourceDir() / "docs" / "scene-format.md");
    std::stringstream doc;
    doc << in.rdbuf();
    for (const std::string& name : builtinSceneNames())
        EXPECT_NE(doc.str().find("`" + name + "`"), std::string::npos)
            << "docs/scene-format.md does not list the built-in scene " << name;
}

TEST(SceneJson, ExampleRoundTrips) {
    Scene a = loadSceneJson(test::sourceDir() / "data" / "scenes" / "example.json");
    auto dir = test::tempDir("json_example");
    // Mesh files are named relative to the example's folder; writing next to it keeps them.
    saveSceneJson(a, dir / "again.json");
    Scene b = parseSceneJson(sceneToJson(a), test::sourceDir() / "data" / "scenes", "again.json");
    expectSameScene(a, b);
}

TEST(SceneJson, BuiltinScenesRoundTrip) {
    BuiltinOptions o;
    o.teapotLevel = 5;
    for (const char* name : {"teapot-in-room", "glass-teapot", "chess", "bunny", "glass-cube"}) {
        SCOPED_TRACE(name);
        Scene a = makeBuiltinScene(name, o);
        std::vector<std::string> warnings;
        Scene b = parseSceneJson(sceneToJson(a), test::sourceDir() / "data", name, &warnings);
        expectSameScene(a, b);
    }
}

TEST(SceneJson, UnknownKeysAreWarningsNamingTheEntry) {
    std::vector<std::string> warnings;
    Scene s = parseSceneJson(R"({"objects":[{"shape":"sphere","material":"m","colour":1}],
        "materials":[{"name":"m"}], "cameras":[{"eye":[0,0,5]}]})",
                             ".", "mine.json", &warnings);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("mine.json"), std::string::npos);
    EXPECT_NE(warnings[0].find("colour"), std::string::npos);
    EXPECT_EQ(s.objects.size(), 1u);
}

}  // namespace
}  // namespace rg::ray
