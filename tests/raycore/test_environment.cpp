// Image environments: an EXR written here with known texels, loaded through the JSON scene
// format and OpenImageIO, read back by direction at the documented orientation (scene.h,
// docs/scene-format.md); then the real CC0 worlds of Debian's blender-data by short name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "raycore/raytrace_command.h"
#include "raycore/scene.h"
#include "raycore/scene_json.h"
#include "test_util.h"

namespace rg::ray {
namespace {

constexpr int kW = 8, kH = 4;
const float kPi = std::numbers::pi_v<float>;

// Texel (i, j) holds (i², j, 1): red codes the column without symmetry (so +z and −z read
// differently), green the row; both are separable, so a bilinear read between texels is
// the same interpolation of the codes.
Image codedImage() {
    Image img(kW, kH, 3);
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i) img.setRgb(i, j, {float(i * i), float(j), 1.0f});
    return img;
}

// Direction of image position (u, v) by the documented mapping, written independently of
// Environment::lookup: longitude φ = 2π(u − ½) from −z towards +x, colatitude θ = πv.
glm::vec3 directionOf(float u, float v) {
    const float phi = 2.0f * kPi * (u - 0.5f), theta = kPi * v;
    return {std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta)};
}

// The coded image as a scene environment, through an EXR file and the JSON reader.
Environment loadCoded(const std::string& extraKeys = "") {
    auto dir = test::tempDir("env_coded");
    writeImage(dir / "coded.exr", codedImage());
    std::vector<std::string> warnings;  // "no cameras" only
    Scene s = parseSceneJson(R"({"environment": {"type": "image", "file": "coded.exr")" + extraKeys +
                                 R"(}, "materials": [{"name": "m"}],
                                 "objects": [{"shape": "cube", "material": "m"}]})",
                             dir, "coded.json", &warnings);
    EXPECT_EQ(s.environment.kind, EnvironmentKind::Image);
    return s.environment;
}

void expectNear(glm::vec3 got, glm::vec3 want, float tol, const std::string& what) {
    EXPECT_NEAR(got.x, want.x, tol) << what;
    EXPECT_NEAR(got.y, want.y, tol) << what;
    EXPECT_NEAR(got.z, want.z, tol) << what;
}

TEST(Environment, TexelCentresReadTheirTexels) {
    const Environment env = loadCoded();
    for (int j = 0; j < kH; ++j)
        for (int i = 0; i < kW; ++i) {
            glm::vec3 d = directionOf((float(i) + 0.5f) / kW, (float(j) + 0.5f) / kH);
            expectNear(env.lookup(d), {float(i * i), float(j), 1.0f}, 2e-3f,
                       "texel " + std::to_string(i) + "," + std::to_string(j));
        }
}

TEST(Environment, AxisDirectionsFollowTheDocumentedOrientation) {
    const Environment env = loadCoded();
    // u = ½ (−z) falls between columns 3 and 4, u = ¾ (+x) between 5 and 6, u = ¼ (−x)
    // between 1 and 2, u = 0 ≡ 1 (+z) on the seam between 7 and 0; the horizon (v = ½)
    // between rows 1 and 2.
    expectNear(env.lookup({0, 0, -1}), {(9 + 16) / 2.0f, 1.5f, 1}, 1e-3f, "-z");
    expectNear(env.lookup({1, 0, 0}), {(25 + 36) / 2.0f, 1.5f, 1}, 1e-3f, "+x");
    expectNear(env.lookup({-1, 0, 0}), {(1 + 4) / 2.0f, 1.5f, 1}, 1e-3f, "-x");
    expectNear(env.lookup({0, 0, 1}), {(49 + 0) / 2.0f, 1.5f, 1}, 1e-3f, "+z");
    // Straight up reads the top row, straight down the bottom row (v clamps, no wrap).
    EXPECT_NEAR(env.lookup({0, 1, 0}).y, 0.0f, 1e-3f);
    EXPECT_NEAR(env.lookup({0, -1, 0}).y, float(kH - 1), 1e-3f);
}

TEST(Environment, BilinearBetweenTexelCentres) {
    const Environment env = loadCoded();
    for (int i = 0; i < kW; ++i)
        for (float a : {0.25f, 0.5f, 0.75f}) {
            // A quarter, a half, three quarters of the way from column i to i + 1 (wrapping),
            // a quarter of the way from row 1 to row 2.
            glm::vec3 d = directionOf((float(i) + 0.5f + a) / kW, (1.5f + 0.25f) / kH);
            const int i1 = (i + 1) % kW;
            const float red = (1 - a) * float(i * i) + a * float(i1 * i1);
            expectNear(env.lookup(d), {red, 1.25f, 1.0f}, 5e-3f,
                       "column " + std::to_string(i) + " + " + std::to_string(a));
        }
}

TEST(Environment, IntensityScalesAndRotateTurnsAboutY) {
    const Environment plain = loadCoded();
    const Environment bright = loadCoded(R"(, "intensity": 2)");
    expectNear(bright.lookup({1, 0, 0}), 2.0f * plain.lookup({1, 0, 0}), 1e-3f, "intensity");
    // rotate = a: what was seen along −z is seen along (−sin a, 0, −cos a).
    const Environment quarter = loadCoded(R"(, "rotate": 90)");
    expectNear(quarter.lookup({-1, 0, 0}), plain.lookup({0, 0, -1}), 1e-3f, "rotate 90, -x");
    expectNear(quarter.lookup({0, 0, 1}), plain.lookup({-1, 0, 0}), 1e-3f, "rotate 90, +z");
    const Environment back = loadCoded(R"(, "rotate": -90)");
    expectNear(back.lookup({1, 0, 0}), plain.lookup({0, 0, -1}), 1e-3f, "rotate -90, +x");
    // Saved and read again, the rotation survives.
    Scene s;
    s.environment = quarter;
    EXPECT_NE(sceneToJson(s).find("\"rotate\""), std::string::npos);
}

TEST(Environment, BadImagesAreRefusedNamingTheFile) {
    auto dir = test::tempDir("env_bad");
    Image img = codedImage();
    img.at(3, 2, 1) = std::numeric_limits<float>::quiet_NaN();
    writeImage(dir / "nan.exr", img);
    try {
        parseSceneJson(R"({"environment": {"type": "image", "file": "nan.exr"},
                           "materials": [{"name": "m"}], "objects": [{"shape": "cube", "material": "m"}]})",
                       dir, "scene.json");
        ADD_FAILURE() << "a NaN texel was accepted";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("scene.json"), std::string::npos) << m;
        EXPECT_NE(m.find("nan.exr"), std::string::npos) << m;
        EXPECT_NE(m.find("(3, 2)"), std::string::npos) << m;
    }
    // Negative texels (colour-conversion noise in real HDRs) are read as 0.
    Image neg = codedImage();
    neg.at(0, 0, 2) = -0.003f;
    writeImage(dir / "neg.exr", neg);
    EXPECT_EQ(readEnvironmentImage(dir / "neg.exr").at(0, 0, 2), 0.0f);
}

// Sets an environment variable for one scope.
struct ScopedEnv {
    std::string name, old;
    bool had;
    ScopedEnv(const char* n, const char* value) : name(n) {
        const char* o = std::getenv(n);
        had = o != nullptr;
        if (had) old = o;
        setenv(n, value, 1);
    }
    ~ScopedEnv() {
        if (had) setenv(name.c_str(), old.c_str(), 1);
        else unsetenv(name.c_str());
    }
};

TEST(Environment, BlenderNamesExplainWhatIsMissing) {
    {
        ScopedEnv e("RETROGLASS_BLENDER_WORLDS", "/nonexistent/retroglass/worlds");
        try {
            blenderWorldPath("forest");
            ADD_FAILURE() << "no error";
        } catch (const Error& err) {
            EXPECT_NE(std::string(err.what()).find("blender-data"), std::string::npos) << err.what();
        }
    }
    auto dir = test::tempDir("env_worlds");
    writeImage(dir / "meadow.exr", codedImage());
    ScopedEnv e("RETROGLASS_BLENDER_WORLDS", dir.c_str());
    EXPECT_EQ(blenderWorldPath("meadow"), dir / "meadow.exr");
    try {
        blenderWorldPath("beach");
        ADD_FAILURE() << "no error";
    } catch (const Error& err) {
        EXPECT_NE(std::string(err.what()).find("known: meadow"), std::string::npos) << err.what();
    }
}

// The real thing: the launcher (./retroglass) installs blender-data, so a missing package
// is a failure with the fix in the message, not a skip.
TEST(Environment, BlenderDataWorldsLoadByShortName) {
    const auto dir = blenderWorldDir();
    ASSERT_TRUE(std::filesystem::is_directory(dir))
        << dir << " is missing: install Debian's blender-data package (apt-get install "
        << "blender-data; the launcher ./retroglass installs it)";
    std::vector<std::string> warnings;
    for (const char* name :
         {"city", "courtyard", "forest", "interior", "night", "studio", "sunrise", "sunset"}) {
        const Image img = readEnvironmentImage(blenderWorldPath(name));
        EXPECT_EQ(img.width, 1024) << name;
        EXPECT_EQ(img.height, 512) << name;
        EXPECT_GE(img.channels, 3) << name;
    }
    Scene s = parseSceneJson(R"({"environment": {"type": "image", "file": "blender:forest"},
                                 "materials": [{"name": "m"}],
                                 "objects": [{"shape": "cube", "material": "m"}]})",
                             ".", "forest.json", &warnings);
    const Environment& env = s.environment;
    ASSERT_TRUE(env.image);
    EXPECT_EQ(env.path, "blender:forest");
    // Texel centres read their texels here too (within the spread of the 2×2 neighbours,
    // as sub-texel float error in the angle moves the bilinear weights slightly).
    const Image& img = *env.image;
    for (int j = 3; j < img.height; j += 61)
        for (int i = 5; i < img.width; i += 97) {
            glm::vec3 d = directionOf((float(i) + 0.5f) / float(img.width), (float(j) + 0.5f) / float(img.height));
            glm::vec3 got = env.lookup(d), want = img.rgb(i, j);
            float spread = 0.0f;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    glm::vec3 n = img.rgb((i + di + img.width) % img.width, std::clamp(j + dj, 0, img.height - 1));
                    spread = std::max(spread, glm::length(n - want));
                }
            expectNear(got, want, 1e-6f + 2e-3f * spread, "forest texel " + std::to_string(i) + "," + std::to_string(j));
        }
}

TEST(Environment, ForestExampleSceneLoads) {
    ASSERT_TRUE(std::filesystem::is_directory(blenderWorldDir()))
        << "install Debian's blender-data package (apt-get install blender-data)";
    std::vector<std::string> warnings;
    Scene s = loadSceneJson(test::sourceDir() / "data" / "scenes" / "forest.json", &warnings);
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_EQ(s.environment.kind, EnvironmentKind::Image);
    EXPECT_TRUE(s.environment.image);
}

// End to end: `retroglass raytrace --scene forest` finds data/scenes/forest.json by its
// stem and renders it; rays missing every object see the forest, so the corner pixels
// (which look over the floor into the trees) equal the environment along their rays.
TEST(Environment, RaytraceRendersTheForestSceneByName) {
    ASSERT_TRUE(std::filesystem::is_directory(blenderWorldDir()))
        << "install Debian's blender-data package (apt-get install blender-data)";
    auto dir = test::tempDir("env_forest_render");
    RaytraceArgs a;
    a.scene = "forest";
    a.width = 32;
    a.height = 24;
    a.quiet = true;
    a.out = (dir / "forest.exr").string();
    ASSERT_EQ(runRaytraceCommand(a), 0);
    const Image img = readImage(dir / "forest.exr");
    Scene s = loadSceneByName("forest");
    const Camera& cam = s.cameras[0];
    const Ray r = primaryRay(cam, a.width, a.height, 0.5f, 0.5f);  // top-left pixel centre
    expectNear(img.rgb(0, 0), s.environment.lookup(r.dir), 1e-5f, "top-left pixel");
    EXPECT_GT(img.rgb(0, 0).y, 0.0f);
    // An unknown name lists the shipped scenes beside the built-in ones.
    try {
        loadSceneByName("no-such-scene");
        ADD_FAILURE() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("forest"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("teapot-in-room"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace rg::ray
