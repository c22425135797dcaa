// Metrics with hand-computed values, and image files round-tripping.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/error.h"
#include "raycore/metrics.h"
#include "test_util.h"

namespace rg::ray {
namespace {

Image ramp(int w, int h) {
    Image img(w, h, 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.setRgb(x, y, {float(x) / w, float(y) / h, float((x * 7 + y * 3) % 11) / 10.0f});
    return img;
}

TEST(Metrics, PsnrOfAConstantOffset) {
    Image a(16, 16, 3, 0.5f), b(16, 16, 3, 0.6f);
    EXPECT_NEAR(meanSquaredError(a, b), 0.01, 1e-8);
    EXPECT_NEAR(psnr(a, b), 20.0, 1e-4);  // 10·log10(1/0.01)
    EXPECT_TRUE(std::isinf(psnr(a, a)));
    EXPECT_THROW(psnr(a, Image(8, 8, 3)), Error);
}

TEST(Metrics, SsimIsOneForEqualImagesAndLowerOtherwise) {
    Image a = ramp(40, 30);
    EXPECT_NEAR(ssim(a, a), 1.0, 1e-9);
    Image noisy = a;
    for (size_t i = 0; i < noisy.pixels.size(); ++i) noisy.pixels[i] += (i % 2 ? 0.1f : -0.1f);
    double s = ssim(a, noisy);
    EXPECT_LT(s, 0.99);
    EXPECT_GT(s, 0.0);
    // Small images fall back to one global window.
    Image t1 = ramp(5, 5);
    EXPECT_NEAR(ssim(t1, t1), 1.0, 1e-9);
}

TEST(Metrics, ErrorStatsMeanP95Max) {
    // 100 pixels: 90 exact, 9 off by 0.1, 1 off by 0.5 (in every channel).
    Image a(10, 10, 3, 0.0f), b(10, 10, 3, 0.0f);
    for (int i = 90; i < 99; ++i) b.setRgb(i % 10, i / 10, glm::vec3(0.1f));
    b.setRgb(9, 9, glm::vec3(0.5f));
    ErrorStats s = compareImages(a, b);
    EXPECT_NEAR(s.mean, (9 * 0.1 + 0.5) / 100.0, 1e-6);
    EXPECT_NEAR(s.p95, 0.1, 1e-6);  // the 95th of 100 sorted errors
    EXPECT_NEAR(s.max, 0.5, 1e-6);
    std::string json = errorStatsJson(s);
    for (const char* key : {"\"mean\"", "\"p95\"", "\"max\"", "\"psnr\"", "\"ssim\""})
        EXPECT_NE(json.find(key), std::string::npos) << key;
    auto dir = test::tempDir("metrics");
    writeErrorStatsJson(dir / "m.json", s);
    std::ifstream in(dir / "m.json");
    std::stringstream ss;
    ss << in.rdbuf();
    EXPECT_EQ(ss.str(), json + "\n");
    Image heat = errorHeatMap(a, b);
    EXPECT_EQ(heat.rgb(0, 0), glm::vec3(0.0f));       // no error: black
    EXPECT_EQ(heat.rgb(9, 9), glm::vec3(1.0f));       // the maximum: white
}

// SSIM against closed forms (issue 24 item 1: it was only checked to lie in (0, 0.99)).
// Constant images have zero variance in every window: SSIM = (2μxμy + C1)/(μx² + μy² + C1).
// An image and itself shifted by c have equal variances and covariance = variance, so the
// structure term is 1 and each window scores (2μ(μ + c) + C1)/(μ² + (μ + c)² + C1); on a
// grey ramp along x a symmetric window's weighted mean is the ramp at its centre.
TEST(Metrics, SsimMatchesItsClosedFormOnKnownPairs) {
    const double C1 = 0.0001;
    Image a(40, 30, 3, 0.5f), b(40, 30, 3, 0.6f);
    const double y = double(0.6f);  // the float the image holds
    EXPECT_NEAR(ssim(a, b), (2 * 0.5 * y + C1) / (0.25 + y * y + C1), 1e-9);
    const int w = 64, h = 24;
    const double c = 0.125;
    Image ramp(w, h, 1), shifted(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            ramp.at(x, y, 0) = float(x) / 128.0f;  // exact in float
            shifted.at(x, y, 0) = float(x) / 128.0f + float(c);
        }
    double sum = 0;
    int windows = 0;
    for (int cy = 5; cy < h - 5; ++cy)
        for (int cx = 5; cx < w - 5; ++cx) {
            const double mu = cx / 128.0;
            sum += (2 * mu * (mu + c) + C1) / (mu * mu + (mu + c) * (mu + c) + C1);
            ++windows;
        }
    EXPECT_NEAR(ssim(ramp, shifted), sum / windows, 1e-6);
}

// Masked measurements (the object, not the frame). Oracles: a constant offset gives
// MSE = offset², so PSNR = 20 dB at 0.1; two constant windows of means μx, μy have SSIM
// (2μxμy + C1)/(μx² + μy² + C1) with C1 = 0.0001 (the variances and covariance are 0).
TEST(Metrics, MaskedScoresCountOnlyTheMask) {
    const int w = 40, h = 30;
    Image truth(w, h, 3, 0.5f), ours(w, h, 3, 0.6f), mask(w, h, 1, 0.0f);
    // The mask: a 10×8 block whose every 11×11 window lies inside the constant region.
    for (int y = 11; y < 19; ++y)
        for (int x = 10; x < 20; ++x) mask.at(x, y, 0) = 1.0f;
    // Outside the windows of the mask, wild differences that a whole-frame score would see.
    for (int y = 0; y < h; ++y)
        for (int x = 26; x < w; ++x) {
            truth.setRgb(x, y, glm::vec3(float((x * 13 + y * 7) % 10) / 10.0f));
            ours.setRgb(x, y, glm::vec3(float((x * 3 + y * 11) % 10) / 10.0f));
        }
    MaskedScore s = compareMasked(truth, ours, mask, "test object");
    EXPECT_EQ(s.pixels, 80);
    EXPECT_NEAR(s.mse, 0.01, 1e-7);
    EXPECT_NEAR(s.psnr, 20.0, 1e-4);
    const double c1 = 0.0001, expected = (2 * 0.5 * 0.6 + c1) / (0.25 + 0.36 + c1);
    EXPECT_NEAR(s.ssim, expected, 1e-6);
    EXPECT_LT(psnr(truth, ours), 19.0);  // the whole frame is worse: the mask matters
    EXPECT_LT(ssim(truth, ours), expected - 0.05);
    // The reference is clamped to what an 8-bit framebuffer can hold.
    Image bright(w, h, 3, 1.7f), white(w, h, 3, 1.0f);
    EXPECT_EQ(compareMasked(bright, white, mask, "clamped").mse, 0.0);
    EXPECT_TRUE(std::isinf(compareMasked(bright, white, mask, "clamped").psnr));
}

TEST(Metrics, AnEmptyMaskIsAnErrorNamingWhatWasMeasured) {
    Image a(16, 16, 3, 0.5f), b(16, 16, 3, 0.5f), mask(16, 16, 1, 0.0f);
    mask.at(3, 3, 0) = 0.49f;  // below one half: not counted
    try {
        compareMasked(a, b, mask, "object 'teapot' in view 'above'");
        FAIL() << "an empty mask must not measure";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("object 'teapot' in view 'above'"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("covers no pixel"), std::string::npos) << e.what();
    }
    EXPECT_THROW(compareMasked(a, b, Image(8, 8, 1, 1.0f), "wrong size"), Error);
    // One counted pixel in an image too small for a window: measured, not an error.
    Image small(5, 5, 3, 0.2f), mask5(5, 5, 1, 0.0f);
    mask5.at(2, 2, 0) = 1.0f;
    EXPECT_EQ(compareMasked(small, small, mask5, "one pixel").pixels, 1);
}

TEST(ImageIO, PngQuantizesByRoundingAndEXRKeepsFloats) {
    auto dir = test::tempDir("image_io");
    Image a(4, 2, 3);
    const float values[] = {0.0f, 1.0f, 0.5f, 0.25f, 2.0f, -1.0f, 0.999f, 0.001f};
    for (int i = 0; i < 8; ++i) a.setRgb(i % 4, i / 4, glm::vec3(values[i], 0.3f, 0.7f));
    writeImage(dir / "a.png", a);
    Image p = readImage(dir / "a.png");
    ASSERT_EQ(p.width, 4);
    ASSERT_EQ(p.channels, 3);
    for (int i = 0; i < 8; ++i)
        EXPECT_EQ(quantize8(p.at(i % 4, i / 4, 0)), quantize8(values[i])) << values[i];
    EXPECT_EQ(quantize8(0.5f), 128);
    EXPECT_EQ(quantize8(2.0f), 255);
    EXPECT_EQ(quantize8(-1.0f), 0);
    EXPECT_EQ(quantize8(std::nanf("")), 0);
    writeImage(dir / "a.exr", a);
    Image e = readImage(dir / "a.exr");
    EXPECT_EQ(e.pixels, a.pixels);
    writeImage(dir / "a.hdr", a);
    EXPECT_EQ(readImage(dir / "a.hdr").width, 4);
}

// A written image is its pixels and format only: no time stamp, so writing the same image
// again gives the same bytes (OpenImageIO stamps EXR headers with DateTime by default).
TEST(ImageIO, FilesAreTheSameBytesOnEveryWrite) {
    auto dir = test::tempDir("image_io_bytes");
    Image a(5, 3, 3);
    for (int i = 0; i < 15; ++i) a.setRgb(i % 5, i / 5, glm::vec3(0.1f * float(i), 0.5f, 2.0f));
    auto bytesOf = [](const std::filesystem::path& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    };
    for (const char* name : {"a.exr", "a.hdr", "a.png"}) {
        SCOPED_TRACE(name);
        writeImage(dir / name, a);
        const std::string first = bytesOf(dir / name);
        ASSERT_FALSE(first.empty());
        // A stamp as OpenImageIO writes it (EXR's capDate attribute): "2026:11:22 03:04:24".
        EXPECT_FALSE(std::regex_search(first, std::regex("[0-9]{4}:[0-9]{2}:[0-9]{2} [0-9]{2}:[0-9]{2}:[0-9]{2}")));
        writeImage(dir / name, a);
        EXPECT_EQ(bytesOf(dir / name), first);
    }
}

}  // namespace
}  // namespace rg::ray

#include "raycore/scene_json.h"
#include "raycore/texture.h"

namespace rg::ray {
namespace {

TEST(ImageIO, ImageTextureAndLatLongEnvironmentReadTheirTexels) {
    auto dir = test::tempDir("env_image");
    // 8×4 lat-long: top two rows red (the sky), bottom two blue (the ground).
    Image env(8, 4, 3);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) env.setRgb(x, y, y < 2 ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1));
    writeImage(dir / "sky.exr", env);
    Image tex(2, 2, 3);
    tex.setRgb(0, 0, {1, 1, 1});
    tex.setRgb(1, 0, {0, 0, 0});
    tex.setRgb(0, 1, {0, 0, 0});
    tex.setRgb(1, 1, {1, 1, 1});
    writeImage(dir / "tex.png", tex);
    test::writeText(dir / "s.json", R"({
      "environment": {"type": "image", "file": "sky.exr", "intensity": 2},
      "textures": [{"name": "t", "type": "image", "file": "tex.png"}],
      "materials": [{"name": "m", "texture": "t"}],
      "objects": [{"shape": "cube", "material": "m"}]
    })");
    std::vector<std::string> warnings;
    Scene s = loadSceneJson(dir / "s.json", &warnings);
    EXPECT_EQ(s.environment.lookup({0, 1, 0}), glm::vec3(2, 0, 0));   // straight up: sky ×2
    EXPECT_EQ(s.environment.lookup({0, -1, 0}), glm::vec3(0, 0, 2));  // straight down
    // Texel centres of the 2×2 checker.
    EXPECT_EQ(s.textures[0].eval({0.25f, 0.25f}), glm::vec3(1.0f));
    EXPECT_EQ(s.textures[0].eval({0.75f, 0.25f}), glm::vec3(0.0f));
    EXPECT_EQ(s.textures[0].eval({1.25f, 0.25f}), glm::vec3(1.0f));  // wraps
}

}  // namespace
}  // namespace rg::ray

#include "raycore/texture_procedural.h"

namespace rg::ray {
namespace {

TEST(Textures, ProceduralPatternsHaveTheirDocumentedStructure) {
    const glm::vec3 a(1.0f), b(0.0f);
    // Checker: scale squares per uv unit, alternating.
    EXPECT_EQ(checkerPattern({0.05f, 0.05f}, 4.0f, a, b), a);
    EXPECT_EQ(checkerPattern({0.30f, 0.05f}, 4.0f, a, b), b);
    EXPECT_EQ(checkerPattern({0.30f, 0.30f}, 4.0f, a, b), a);
    // Bricks: mortar on row boundaries, brick inside (shaded 0.8..1 of the brick colour).
    EXPECT_EQ(bricksPattern({0.3f, 0.0f}, 1.0f, a, b), b);
    glm::vec3 brick = bricksPattern({0.3f, 0.25f}, 1.0f, a, b);
    EXPECT_GE(brick.x, 0.8f);
    // Gradient: ends and middle.
    EXPECT_EQ(gradientPattern({0.0f, 0.0f}, a, b), a);
    EXPECT_EQ(gradientPattern({0.0f, 1.0f}, a, b), b);
    EXPECT_NEAR(gradientPattern({0.0f, 0.5f}, a, b).x, 0.5f, 1e-6f);
    // Wood: stays between its two colours.
    for (int i = 0; i < 100; ++i) {
        glm::vec3 w = woodRingsPattern({i * 0.0137f, i * 0.0071f}, 4.0f, a, b);
        EXPECT_GE(w.x, 0.0f);
        EXPECT_LE(w.x, 1.0f);
    }
    // Baking samples texel centres.
    Texture t;
    t.kind = TextureKind::Checker;
    t.scale = 2.0f;
    t.colorA = a;
    t.colorB = b;
    Image img = bakeTexture(t, 4, 4);
    EXPECT_EQ(img.rgb(0, 0), a);
    EXPECT_EQ(img.rgb(2, 0), b);
    EXPECT_EQ(img.rgb(2, 2), a);
}

}  // namespace
}  // namespace rg::ray
