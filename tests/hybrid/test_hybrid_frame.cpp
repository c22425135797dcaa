// The frame on the emulated GeForce 256: the alpha-clear polygon over every (value, alpha)
// pair, the compositing arithmetic of two premultiplied layers (the 8-bit result worked
// out by hand), the pass counts of 000 §5 (4n + clears between samples, 2n on a sample),
// the same bytes on both rasterizer paths and any thread count, and the stacked inference
// (000 §4.3) recovering a known map from two rendering matrices.
#include <gtest/gtest.h>

#include "core/error.h"

#include <algorithm>

#include "core/profile.h"
#include "hybrid_renderer.h"
#include "hybrid_test_scenes.h"
#include "inference.h"
#include "lens_scene.h"

namespace rg::hybrid {
namespace {

TEST(AlphaClear, KeepsRgbAndZeroesAlphaForEveryValueAndAlpha) {
    raster::Device device(profileByName("geforce256"), 256, 256, raster::DepthFormat::D24);
    std::vector<Rgba8> px(256 * 256);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            px[size_t(y) * 256 + size_t(x)] = {uint8_t(x), uint8_t(255 - x), uint8_t(x ^ y), uint8_t(y)};
    device.beginFrame();
    device.drawPixels(0, 0, 256, 256, px);
    drawAlphaClear(device, "alpha clear");
    device.endFrame();
    ASSERT_EQ(device.passes().size(), 1u);
    EXPECT_EQ(device.passes()[0].label, "alpha clear");
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x) {
            const Rgba8 c = device.framebuffer().pixel(x, y);
            const Rgba8 want = px[size_t(y) * 256 + size_t(x)];
            ASSERT_EQ(c.r, want.r);
            ASSERT_EQ(c.g, want.g);
            ASSERT_EQ(c.b, want.b);
            ASSERT_EQ(c.a, 0) << "at (" << x << ", " << y << ")";
        }
}

// A renderer over the test scene with constant layer maps.
struct Fixture {
    LensScene scene;
    raster::Device device;
    std::shared_ptr<tex::TextureMemory> memory;
    std::unique_ptr<HybridRenderer> renderer;
    ray::Camera camera;
    Fixture(bool withBall, int ballLayers, Path path = Path::Fast, int threads = 0,
            const char* profile = "geforce256")
        : scene(withBall ? test::ballAndBox() : boxOnly(), LensSceneOptions{}),
          device(profileByName(profile), 160, 120, raster::DepthFormat::D24, {path, threads}),
          memory(std::make_shared<tex::TextureMemory>(device.profile())) {
        std::vector<LensLayers> layers;
        for (const LensObject& L : scene.objects()) {
            LensLayers ll;
            ll.emSize = 4;
            const int n = L.name == "ball" ? ballLayers : 2;
            for (int l = 0; l < n; ++l) ll.shells.push_back(sphereShell(L.origin, 5.0f + 10.0f * float(l)));
            ll.assignment.layers.resize(size_t(n));
            layers.push_back(ll);
        }
        renderer = std::make_unique<HybridRenderer>(device, memory, scene, layers, 2, TessellationSettings{});
        camera = scene.scene().viewpointPaths[0].at(0);
        // The box straight ahead: the camera on the circle looks at the ball; turn to the box.
        if (!withBall) camera.target = {2.2f, 0.5f, 0.0f};
    }
    static ray::Scene boxOnly() {
        // A mirror box of reflectance 1 (F·G = 1 exactly, 255 in the diffuse colour).
        ray::Scene s = test::ballAndBox(24, 12, true);
        s.materials[s.objects[1].material].reflectance = glm::vec3(1.0f);
        s.objects.erase(s.objects.begin());  // the ball
        return s;
    }
    SampleMaps constantMaps(const std::vector<Rgba8>& perLayer, int view) {
        SampleMaps m;
        m.view = view;
        for (size_t i = 0; i < scene.objects().size(); ++i) {
            m.maps.emplace_back();
            for (int l = 0; l < renderer->layers(i).layers(); ++l)
                m.maps.back().push_back(renderer->uploadMap(
                    i, l, std::vector<Rgba8>(size_t(renderer->layers(i).layout(l).count()),
                                             perLayer.at(size_t(l)))));
        }
        return m;
    }
};

TEST(HybridFrame, TwoPremultipliedLayersCompositeFrontToBackInEightBits) {
    // A mirror of reflectance 1: F·G = 255. L1 = (64, α 128), L2 = (200, α 255).
    //   pass 1 (replaces): 64·255/255 = 64, α 128
    //   pass 2 (INVDESTALPHA, ONE): 64 + round(200·127/255) = 64 + 100 = 164, α 255
    // Between two samples with these maps and weight ½ the sum is the same:
    //   sample a: 32, then 32 + round(100·127/255) = 82; alpha clear; sample b: 82 + 32 =
    //   114, then 114 + 50 = 164.
    Fixture f(false, 0);
    const SampleMaps a = f.constantMaps({{64, 64, 64, 128}, {200, 200, 200, 255}}, 0);
    f.renderer->prepare(f.camera);
    for (int blended = 0; blended < 2; ++blended) {
        f.renderer->draw(a, blended ? &a : nullptr, 0.5f);
        int covered = 0;
        const auto& fb = f.device.framebuffer();
        for (int y = 0; y < fb.height(); ++y)
            for (int x = 0; x < fb.width(); ++x) {
                if (fb.depth()[size_t(y) * size_t(fb.width()) + size_t(x)] == fb.depthMax()) continue;
                ++covered;
                const Rgba8 c = fb.pixel(x, y);
                ASSERT_EQ(c.r, 164) << "at (" << x << ", " << y << "), blended " << blended;
                ASSERT_EQ(c.g, 164);
                ASSERT_EQ(c.b, 164);
            }
        EXPECT_GT(covered, 500);
    }
}

TEST(HybridFrame, PassesAre4nBetweenSamplesAnd2nOnASampleWithTheAlphaClears) {
    for (int n : {1, 2, 3}) {
        Fixture f(true, n);
        const SampleMaps a = f.constantMaps({{10, 10, 10, 128}, {20, 20, 20, 128}, {30, 30, 30, 255}}, 3);
        const SampleMaps b = f.constantMaps({{10, 10, 10, 128}, {20, 20, 20, 128}, {30, 30, 30, 255}}, 4);
        f.renderer->prepare(f.camera);
        // The ball: glass, two terms, n layers; the box: a mirror, one term, 2 layers.
        f.renderer->draw(a, &b, 0.25f);
        EXPECT_EQ(f.renderer->counts().layerPasses, 4 * n + 2 * 2);
        EXPECT_EQ(f.renderer->counts().alphaClears, 3 + 1);
        EXPECT_EQ(int(f.device.counters().passes), 4 * n + 4 + 4);
        int clears = 0;
        for (const raster::PassRecord& p : f.device.passes())
            clears += p.label.rfind("alpha clear", 0) == 0 ? 1 : 0;
        EXPECT_EQ(clears, 4);
        EXPECT_NE(f.device.passes().front().label.find("ball reflection, L1"), std::string::npos)
            << f.device.passes().front().label;
        f.renderer->draw(a);
        EXPECT_EQ(f.renderer->counts().layerPasses, 2 * n + 2);
        EXPECT_EQ(f.renderer->counts().alphaClears, 1);
        EXPECT_EQ(int(f.device.counters().passes), 2 * n + 2 + 1);
    }
}

TEST(HybridFrame, OnFourStagesTheSamplesLerpInsideAPass2nPassesAndOneClear) {
    for (int n : {1, 3}) {
        Fixture f(true, n, Path::Fast, 0, "geforce3");
        ASSERT_TRUE(f.renderer->lerpsInPass());
        const SampleMaps a = f.constantMaps({{10, 10, 10, 128}, {20, 20, 20, 128}, {30, 30, 30, 255}}, 3);
        const SampleMaps b = f.constantMaps({{10, 10, 10, 128}, {20, 20, 20, 128}, {30, 30, 30, 255}}, 4);
        f.renderer->prepare(f.camera);
        for (const SampleMaps* second : {&b, static_cast<const SampleMaps*>(nullptr)}) {
            f.renderer->draw(a, second, 0.25f);
            EXPECT_EQ(f.renderer->counts().layerPasses, 2 * n + 2) << "glass 2n, mirror n (2 layers)";
            EXPECT_EQ(f.renderer->counts().alphaClears, 1) << "before the glass's refraction term";
        }
    }
    // The compositing on four stages: lerp(64, 64) = 64 whatever the weight, then the same
    // 8-bit sums as on two stages.
    Fixture g(false, 0, Path::Fast, 0, "geforce3");
    const SampleMaps a = g.constantMaps({{64, 64, 64, 128}, {200, 200, 200, 255}}, 0);
    g.renderer->prepare(g.camera);
    g.renderer->draw(a, &a, 0.3f);
    const auto& fb = g.device.framebuffer();
    int covered = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) {
            if (fb.depth()[size_t(y) * size_t(fb.width()) + size_t(x)] == fb.depthMax()) continue;
            ++covered;
            ASSERT_EQ(fb.pixel(x, y).r, 164);
        }
    EXPECT_GT(covered, 500);
}

TEST(HybridFrame, TooManyLayersForTheCoordinateSetsIsRefused) {
    EXPECT_THROW(Fixture(true, 5), Error);  // 2 terms × 5 layers > 8 sets
}

TEST(HybridFrame, SameBytesOnBothPathsAndAnyThreadCount) {
    std::vector<std::vector<Rgba8>> frames;
    std::vector<std::vector<float>> displays, coverages;
    for (auto [path, threads] : {std::pair{Path::Reference, 1}, std::pair{Path::Fast, 1},
                                 std::pair{Path::Fast, 3}}) {
        Fixture f(true, 2, path, threads);
        const SampleMaps a = f.constantMaps({{40, 60, 80, 128}, {90, 120, 200, 255}}, 0);
        const SampleMaps b = f.constantMaps({{10, 80, 20, 200}, {200, 30, 90, 255}}, 1);
        f.renderer->tessellation().threads = threads;
        f.renderer->render(f.camera, a, &b, 0.3f);
        const raster::Framebuffer& fb = f.device.framebuffer();
        frames.emplace_back(fb.color().begin(), fb.color().end());
        // The display: each s×s block's channel sums times 1/(s²·255), and the share of
        // its samples drawn (depth below the cleared far value).
        ray::Image coverage;
        const ray::Image display = f.renderer->displayImage(&coverage);
        const int s = f.renderer->subsample();
        ASSERT_EQ(s, 2);
        ASSERT_EQ(display.width, fb.width() / s);
        ASSERT_EQ(display.height, fb.height() / s);
        const float inv = 1.0f / float(s * s * 255);
        int drawnPixels = 0;
        for (int y = 0; y < display.height; ++y)
            for (int x = 0; x < display.width; ++x) {
                int sum[3] = {0, 0, 0}, drawn = 0;
                for (int k = 0; k < s * s; ++k) {
                    const int px = x * s + k % s, py = y * s + k / s;
                    const Rgba8 c = fb.pixel(px, py);
                    sum[0] += c.r, sum[1] += c.g, sum[2] += c.b;
                    drawn += fb.depth()[size_t(py) * size_t(fb.width()) + size_t(px)] < fb.depthMax();
                }
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(display.at(x, y, c), float(sum[c]) * inv) << x << ", " << y;
                ASSERT_EQ(coverage.at(x, y, 0), float(drawn) / float(s * s)) << x << ", " << y;
                drawnPixels += drawn > 0;
            }
        EXPECT_GT(drawnPixels, 100);
        displays.push_back(display.pixels);
        coverages.push_back(coverage.pixels);
    }
    EXPECT_TRUE(frames[0] == frames[1]) << "reference and fast paths differ";
    EXPECT_TRUE(frames[1] == frames[2]) << "1 and 3 threads differ";
    EXPECT_TRUE(displays[1] == displays[2] && coverages[1] == coverages[2])
        << "the display differs between 1 and 3 threads";
}

TEST(StackedInference, TwoMatricesTogetherRecoverWhatNeitherSeesAlone) {
    // A 2D 8×8 map (all levels). A_1 sees the left half of level 0, A_2 the right half,
    // each row a texel and its right neighbour (weights ¾, ¼).
    const pem::TexelLayout L{8, 1};
    Eigen::VectorXd x(L.count());
    for (int64_t i = 0; i < L.count(); ++i) x[i] = 0.2 + 0.6 * double((i * 37) % 11) / 10.0;
    auto matrix = [&](int x0, int x1) {
        pem::RenderingMatrix m;
        m.layout = L;
        std::vector<Eigen::Triplet<double>> t;
        int r = 0;
        for (int y = 0; y < 8; ++y)
            for (int xx = x0; xx < x1; ++xx, ++r) {
                m.rowPixel.push_back(r);
                t.emplace_back(r, int(L.index(0, 0, xx, y)), 0.75);
                t.emplace_back(r, int(L.index(0, 0, std::min(7, xx + 1), y)), 0.25);
            }
        m.A.resize(r, L.count());
        m.A.setFromTriplets(t.begin(), t.end());
        return m;
    };
    const pem::RenderingMatrix A1 = matrix(0, 4), A2 = matrix(4, 8);
    const Eigen::VectorXd b1 = A1.A * x, b2 = A2.A * x;
    pem::InferenceOptions o;
    o.smoothness = 1e-6;
    o.levelCoupling = 1e-6;
    o.maxIterations = 2000;
    o.tolerance = 1e-10;
    const pem::InferenceSystem both({{&A1, {}}, {&A2, {}}}, o);
    const Eigen::VectorXd xb = both.solve(std::vector<Eigen::VectorXd>{b1, b2});
    double errBoth = 0, errLeftOnly = 0;
    const pem::InferenceSystem left({{&A1, {}}}, o);
    const Eigen::VectorXd xl = left.solve(std::vector<Eigen::VectorXd>{b1});
    for (int y = 0; y < 8; ++y)
        for (int xx = 0; xx < 8; ++xx) {
            const int64_t i = L.index(0, 0, xx, y);
            errBoth = std::max(errBoth, std::abs(xb[i] - x[i]));
            if (xx >= 5) errLeftOnly = std::max(errLeftOnly, std::abs(xl[i] - x[i]));
        }
    EXPECT_LT(errBoth, 1e-3);
    EXPECT_GT(errLeftOnly, 0.05) << "the right half is unseen by A_1 alone";
    // A block of confidence 0 has no say, whatever its right-hand side.
    Eigen::VectorXd zero = Eigen::VectorXd::Zero(A2.A.rows());
    const pem::InferenceSystem muted({{&A1, {}}, {&A2, {}}, {&A2, zero}}, o);
    const Eigen::VectorXd xm = muted.solve(
        std::vector<Eigen::VectorXd>{b1, b2, Eigen::VectorXd::Constant(A2.A.rows(), 1.0)});
    EXPECT_LT((xm - xb).cwiseAbs().maxCoeff(), 1e-6);
}

}  // namespace
}  // namespace rg::hybrid
