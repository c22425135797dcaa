// 000 §4.3's direct images of the environment: the nearest-record lookup against brute
// force, the confidence (0 on a record point, 1 far from every record), the direct block's
// rendering matrix (the shell seen from the camera: only texels in the camera's view,
// every row a full pixel, so a constant direct image leaves a constant map), a texel no
// lens image reaches taking its value from the direct image, and the precompute stacking
// the direct rows so that fewer texels stay unconstrained.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "core/profile.h"
#include "direct_images.h"
#include "hybrid_precompute.h"
#include "clustered_scene.h"
#include "hybrid_test_scenes.h"
#include "inference.h"
#include "texunit/cube_mapping.h"

namespace rg::hybrid {
namespace {

TEST(RecordPoints, NearestIsTheClosestPointCappedAtTheCell) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    const float cell = 0.5f;
    RecordPoints grid(cell);
    std::vector<glm::vec3> pts;
    for (int i = 0; i < 400; ++i) {
        pts.push_back({u(rng), u(rng), u(rng)});
        grid.add(pts.back());
    }
    EXPECT_EQ(grid.size(), pts.size());
    for (int q = 0; q < 2000; ++q) {
        const glm::vec3 p{u(rng), u(rng), u(rng)};
        float best = cell;
        for (const glm::vec3& r : pts) best = std::min(best, glm::length(r - p));
        ASSERT_NEAR(grid.nearest(p), best, 1e-5f) << "query " << q;
    }
    EXPECT_FLOAT_EQ(RecordPoints(cell).nearest({0, 0, 0}), cell) << "no records: the cap";
}

TEST(DirectImages, ConfidenceIsZeroOnARecordAndOneFromD0On) {
    EXPECT_FLOAT_EQ(directConfidence(0.0f, 2.0f), 0.0f);
    EXPECT_FLOAT_EQ(directConfidence(1.0f, 2.0f), 0.5f);
    EXPECT_FLOAT_EQ(directConfidence(2.0f, 2.0f), 1.0f);
    EXPECT_FLOAT_EQ(directConfidence(9.0f, 2.0f), 1.0f);
    // d0: texels of the finest level at the shell's distance (90° over emSize on a cube).
    EXPECT_NEAR(directConfidenceScale(sphereShell({}, 10.0f), 64, 4.0f),
                4.0f * 10.0f * 1.5707963f / 64.0f, 1e-5f);
}

// The direct block's A for a sphere shell around the camera: the camera at the origin looks
// along +x with a 90° field.
struct DirectMatrix {
    raster::Device device{profileByName("geforce256"), 64, 48, raster::DepthFormat::D24};
    tex::TextureMemory memory{profileByName("geforce256")};
    pem::TexelLayout layout{8, 6};
    ray::Camera camera{"direct", {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 90.0f};
    Shell shell = sphereShell({0, 0, 0}, 10.0f);
    pem::RenderingMatrix build() {
        device.textureUnits().setTextureMemory(
            std::shared_ptr<tex::TextureMemory>(&memory, [](tex::TextureMemory*) {}));
        return pem::buildMatrixByInstrumentedPass(device, memory,
                                                  directIsolating(device, camera, shell, layout, 2));
    }
};

TEST(DirectImages, TheShellSeenFromTheCameraReachesOnlyTexelsInItsViewAndEveryRowIsWhole) {
    DirectMatrix d;
    const pem::RenderingMatrix m = d.build();
    ASSERT_EQ(m.width, 32);
    ASSERT_EQ(m.height, 24);
    EXPECT_EQ(int64_t(m.rowPixel.size()), int64_t(32) * 24) << "every pixel sees the shell";
    const Eigen::VectorXd rowSums = m.A * Eigen::VectorXd::Ones(m.A.cols());
    EXPECT_LT((rowSums.array() - 1.0).abs().maxCoeff(), 1e-9) << "each pixel is the shell alone";
    // Every reached texel of the finest level points into the frustum (the corner rays have
    // x = 0.51; the filter's texels reach a texel (11° here) beyond): a flipped or mis-aimed
    // coordinate lands behind the camera.
    const int64_t finest = d.layout.levelOffset(1);
    int reached = 0;
    for (int k = 0; k < m.A.outerSize(); ++k)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(m.A, k); it; ++it) {
            if (it.col() >= finest || it.value() <= 0) continue;
            const int64_t t = it.col();
            const int face = int(t / 64), x = int(t % 64 % 8), y = int(t % 64 / 8);
            const glm::vec3 dir = glm::normalize(
                tex::cubeFaceDirection(tex::CubeFace(face), (float(x) + 0.5f) / 8.0f, (float(y) + 0.5f) / 8.0f));
            ASSERT_GT(dir.x, 0.3f) << "texel " << t << " (face " << face << ") is behind the camera";
            ++reached;
        }
    EXPECT_GT(reached, 16);
    // A constant direct image leaves a constant map where it reaches.
    pem::InferenceOptions o;
    const pem::InferenceSystem sys({{&m, {}}}, o);
    const Eigen::VectorXd x = sys.solve(Eigen::VectorXd::Constant(m.A.rows(), 0.6));
    EXPECT_LT(((m.A * x).array() - 0.6).abs().maxCoeff(), 2e-3);
}

TEST(DirectImages, ATexelNoLensImageReachesTakesItsValueFromTheDirectImage) {
    DirectMatrix d;
    const pem::RenderingMatrix direct = d.build();
    // A lens-image block that sees only the −x face (value 0.2); the direct image looks
    // along +x (value 0.8): the +x face, unseen by the lens image, must come out 0.8.
    pem::RenderingMatrix lensImage;
    lensImage.layout = d.layout;
    std::vector<Eigen::Triplet<double>> t;
    int r = 0;
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x, ++r) {
            lensImage.rowPixel.push_back(r);
            t.emplace_back(r, int(d.layout.index(0, 1, x, y)), 1.0);
        }
    lensImage.A.resize(r, d.layout.count());
    lensImage.A.setFromTriplets(t.begin(), t.end());
    pem::InferenceOptions o;
    const pem::InferenceSystem with({{&lensImage, {}}, {&direct, {}}}, o);
    const Eigen::VectorXd x = with.solve(std::vector<Eigen::VectorXd>{
        Eigen::VectorXd::Constant(r, 0.2), Eigen::VectorXd::Constant(direct.A.rows(), 0.8)});
    for (int y = 2; y < 6; ++y)
        for (int xx = 2; xx < 6; ++xx) {
            EXPECT_NEAR(x[d.layout.index(0, 0, xx, y)], 0.8, 0.02) << "+x face (" << xx << ", " << y << ")";
            EXPECT_NEAR(x[d.layout.index(0, 1, xx, y)], 0.2, 0.02) << "−x face (" << xx << ", " << y << ")";
        }
}

using Scene = test::ClusteredScene;

TEST(DirectImages, ConfidenceIsZeroWhereARecordLiesAndFullFarFromEveryRecord) {
    Scene s;
    const size_t ball = 0;
    ASSERT_EQ(s.scene.objects()[ball].name, "ball");
    const LensLayers& L = s.layers[ball];
    const ray::Camera cam = s.views[0];
    const int W = s.settings.width, H = s.settings.height;
    // Records: the outermost layer's point of the direct ray through pixel (5, 5) alone.
    std::vector<RecordPoints> records;
    for (int l = 0; l < L.layers(); ++l)
        records.emplace_back(directConfidenceScale(L.shells[size_t(l)], L.emSize, 4.0f));
    const int outer = L.layers() - 1;
    DirectImageOptions o;
    const DirectImage before = traceDirectImage(s.scene, ball, L, cam, s.settings, records, o);
    // No records at all: every pixel is a missing portion (confidence 1) in a sphere layer.
    ASSERT_TRUE(L.shells[size_t(outer)].cube());
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) ASSERT_FLOAT_EQ(before.confidence[size_t(outer)].at(x, y, 0), 1.0f);
    // The point of pixel (5, 5)'s ray in the outer layer: its first hit there, found as the
    // direct image finds it (every front-facing hit but the ball's).
    const ray::Ray r = ray::primaryRay(cam, W, H, 5.5f, 5.5f);
    glm::vec3 point(0.0f);
    bool found = false;
    for (const ray::Hit& h : s.scene.accel().allIntersections(r, true)) {
        if (h.object == s.scene.objects()[ball].object) continue;
        const int l = L.assignment.layerOfObject.at(h.object);
        if (l == outer) {
            point = r.origin + h.t * r.dir;
            found = true;
            break;
        }
    }
    ASSERT_TRUE(found);
    records[size_t(outer)].add(point);
    const DirectImage after = traceDirectImage(s.scene, ball, L, cam, s.settings, records, o);
    EXPECT_NEAR(after.confidence[size_t(outer)].at(5, 5, 0), 0.0f, 1e-3f) << "a record lies there";
    EXPECT_FLOAT_EQ(after.confidence[size_t(outer)].at(W - 5, H - 5, 0), 1.0f) << "far from it";
    // The room is closed: every ray meets something of some layer (alpha 1 in one of them).
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            float most = 0.0f;
            for (const ray::Image& b : after.b) most = std::max(most, b.at(x, y, 3));
            ASSERT_FLOAT_EQ(most, 1.0f) << "(" << x << ", " << y << ")";
        }
}

TEST(DirectImages, StackedWithTheLensImagesTheyLeaveFewerTexelsUnconstrained) {
    Scene s;
    raster::Device device(profileByName("geforce256"), s.settings.width, s.settings.height,
                          raster::DepthFormat::D24);
    auto memory = std::make_shared<tex::TextureMemory>(device.profile());
    TessellationSettings ts;
    HybridRenderer renderer(device, memory, s.scene, s.layers, 1, ts);
    const std::vector<ray::Camera> one{s.views[0]};
    RecordOptions without, with;
    with.directImages = true;
    const SampleSolution a = inferSample(renderer, 0, one, s.settings, without);
    const SampleSolution b = inferSample(renderer, 0, one, s.settings, with);
    EXPECT_EQ(a.directImages, 0);
    EXPECT_EQ(b.directImages, 1 + 6) << "the glass ball from the viewpoint, the mirror box from its centre";
    int64_t holesA = 0, holesB = 0, directRows = 0;
    for (size_t i = 0; i < a.maps.size(); ++i)
        for (size_t l = 0; l < a.maps[i].size(); ++l) {
            holesA += a.maps[i][l].unconstrained;
            holesB += b.maps[i][l].unconstrained;
            directRows += b.maps[i][l].directRows;
            EXPECT_EQ(a.maps[i][l].directRows, 0);
        }
    EXPECT_GT(directRows, 0);
    EXPECT_LT(holesB, holesA) << "direct images fill texels the lens images leave unconstrained";
}

}  // namespace
}  // namespace rg::hybrid
