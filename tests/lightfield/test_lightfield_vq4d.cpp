// The 4D-texture rendering of VQ light fields (Heidrich et al. 1999 §5, "4D VQ"): the 2^4
// basis textures sum to one (one-hot) or two ("two pixels"), an identity codebook
// reproduces the uncompressed light field drawn as one 4D texture, the 4D passes agree with
// the 2D alpha-basis passes where their (s, t) interpolants coincide, and a profile without
// 4D textures is refused by name.
#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "gortler_renderer.h"
#include "lf4d_renderer.h"
#include "vq.h"

namespace rg::lightfield {
namespace {

LightSlab slab8() {
    LightSlab s;
    s.stZ = 6.0f;
    s.uvZ = 0.0f;
    s.stMin = glm::vec2(-1.0f);
    s.stMax = glm::vec2(1.0f);
    s.uvMin = glm::vec2(-2.0f);
    s.uvMax = glm::vec2(2.0f);
    s.S = s.T = 8;
    s.U = s.V = 16;
    return s;
}

ray::Camera camera() {
    ray::Camera c;
    c.eye = glm::vec3(0.1f, -0.05f, 9.0f);
    c.fovYDegrees = 18.0f;
    return c;
}

constexpr int kSize = 96;

// Every block its own codeword (K = the block count): decoding is exact, so whatever the
// passes lose is the rendering's, not the quantizer's.
VqLightField identityVq(const LightField& lf, const BlockShape& sh) {
    VqLightField vq;
    vq.slab = lf.slab;
    vq.shape = sh;
    vq.K = vq.blocksS() * vq.blocksT() * vq.blocksU() * vq.blocksV();
    const int D = sh.dims();
    vq.codebook.assign(size_t(vq.K) * size_t(D), 0);
    vq.indices.resize(size_t(vq.K));
    for (size_t b = 0; b < vq.indices.size(); ++b) vq.indices[b] = uint16_t(b);
    for (int j = 0; j < lf.slab.T; ++j)
        for (int i = 0; i < lf.slab.S; ++i)
            for (int l = 0; l < lf.slab.V; ++l)
                for (int k = 0; k < lf.slab.U; ++k) {
                    const size_t b = vq.blockIndex(i / sh.s, j / sh.t, k / sh.u, l / sh.v);
                    const uint8_t* p = lf.data.data() + lf.offset(i, j, k, l);
                    std::copy(p, p + 3, vq.codebook.begin() + std::ptrdiff_t(b * size_t(D) + size_t(3 * vq.parity(i, j, k, l))));
                }
    return vq;
}

// Independent random samples: a block read from the wrong parity or the neighbouring
// block is off by tens of LSB, not by rounding.
LightField randomField() {
    LightField lf;
    lf.slab = slab8();
    lf.data.resize(lf.slab.samples() * 3);
    std::mt19937 rng(7);
    for (auto& b : lf.data) b = uint8_t(rng() & 0xff);
    return lf;
}

// Affine in the eye point (i, j) for every window sample (k, l): the hexagon's barycentric
// hat and the 4D texture's bilinear (s, t) tent both reproduce it exactly, so the 2D and
// 4D passes must agree to rounding.
LightField affineInStField() {
    LightField lf;
    lf.slab = slab8();
    lf.data.resize(lf.slab.samples() * 3);
    std::mt19937 rng(11);
    std::vector<uint8_t> base(size_t(lf.slab.U) * lf.slab.V * 3);
    for (auto& b : base) b = uint8_t(rng() % 150);
    for (int j = 0; j < lf.slab.T; ++j)
        for (int i = 0; i < lf.slab.S; ++i)
            for (int l = 0; l < lf.slab.V; ++l)
                for (int k = 0; k < lf.slab.U; ++k)
                    for (int c = 0; c < 3; ++c)
                        lf.data[lf.offset(i, j, k, l) + size_t(c)] =
                            uint8_t(base[(size_t(l) * lf.slab.U + size_t(k)) * 3 + size_t(c)] + 8 * i + 6 * j);
    return lf;
}

// Pixels whose ray crosses the window at least half a window sample inside it (the
// polygon's edges are rasterized by coverage, not by the ray).
std::vector<size_t> windowPixels(const LightSlab& s) {
    std::vector<size_t> px;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const ray::Ray r = ray::primaryRay(camera(), kSize, kSize, x + 0.5f, y + 0.5f);
            const auto stuv = s.intersect(r.origin, r.dir);
            if (!stuv) continue;
            const glm::vec4 c = s.textureCoords(*stuv);
            const float m = 0.5f / float(s.U);
            if (c.x > m && c.x < 1 - m && c.y > m && c.y < 1 - m) px.push_back(size_t(y) * kSize + size_t(x));
        }
    return px;
}

int worstRgb(const std::vector<Rgba8>& a, const std::vector<Rgba8>& b, const std::vector<size_t>& px) {
    int worst = 0;
    for (size_t i : px)
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int((&a[i].r)[c]) - int((&b[i].r)[c])));
    return worst;
}

TEST(Vq4DBasis, OneHotSumsToOneAndTwoPixelsToTwo) {
    // Each basis pass is one quadrilinear sample of a 0/255 texture, rounded once (half
    // up, docs/hardware.md "Filtering"): off by at most ½ LSB, and the 16 passes take
    // complementary tap weights that sum to 2^32 exactly. So |Σ − 255| ≤ 16·½ = 8.
    const LightField lf = randomField();
    const VqLightField vq = identityVq(lf, {2, 2, 2, 2});
    const std::vector<size_t> px = windowPixels(lf.slab);
    ASSERT_GT(px.size(), 3000u);
    for (BasisReading reading : {BasisReading::OneHot, BasisReading::TwoPixels}) {
        const Profile& octane = profile(ProfileId::SgiOctaneMxe);
        auto mem = std::make_shared<tex::TextureMemory>(octane);
        const VqTextures4D tx(mem, vq, reading);
        raster::Device dev(octane, kSize, kSize, raster::DepthFormat::None);
        dev.beginFrame();
        Vq4DProbe probe;
        const VqStats st = renderVq4D(dev, tx, vq, camera(), &probe);
        EXPECT_EQ(st.tableLoads, 16);
        EXPECT_EQ(st.colorPasses, 16);
        const int want = reading == BasisReading::OneHot ? 255 : 510;
        int worst = 0;
        for (size_t i : px) worst = std::max(worst, std::abs(probe.basisSum[i] - want));
        EXPECT_LE(worst, reading == BasisReading::OneHot ? 8 : 16) << basisReadingName(reading);
        std::printf("4D basis, %s: max |sum - %d| = %d LSB\n", basisReadingName(reading), want, worst);
    }
}

TEST(Vq4DPasses, IdentityCodebookReproducesTheUncompressed4DTexture) {
    // Reference: one quadrilinear sample per pixel, rounded once (≤ ½). The passes: per
    // parity class the basis rounded (≤ ½ LSB of alpha, so ≤ ½ of the colour) and the
    // product DESTALPHA·src rounded (≤ ½): ≤ 1 per class whose basis is nonzero, at most 16
    // classes. Bound 16 + ½ → 16. (Without the ½-sample index offset a quarter of each
    // hat reads the neighbouring block: tens of LSB on this random field.)
    const LightField lf = randomField();
    const VqLightField vq = identityVq(lf, {2, 2, 2, 2});
    ASSERT_EQ(decode(vq).data, lf.data);
    const Profile& octane = profile(ProfileId::SgiOctaneMxe);
    auto mem = std::make_shared<tex::TextureMemory>(octane);
    const VqTextures4D tx(mem, vq);
    raster::Device dev(octane, kSize, kSize, raster::DepthFormat::None);
    dev.beginFrame();
    const VqStats st = renderVq4D(dev, tx, vq, camera());
    const std::vector<Rgba8> got = dev.readPixels(0, 0, kSize, kSize);
    auto mem2 = std::make_shared<tex::TextureMemory>(octane);
    const LightFieldTexture4D ref4(mem2, lf);
    raster::Device ref(octane, kSize, kSize, raster::DepthFormat::None);
    ref.beginFrame();
    const LightField4DStats rs = renderLightField4D(ref, ref4, lf.slab, camera());
    const std::vector<Rgba8> want = ref.readPixels(0, 0, kSize, kSize);
    // One polygon per colour pass: 16 times the uncompressed 4D route's fragments.
    EXPECT_EQ(st.colorFragments, 16 * rs.fragments);
    const std::vector<size_t> px = windowPixels(lf.slab);
    const int worst = worstRgb(got, want, px);
    EXPECT_LE(worst, 16);
    double sum = 0;
    for (size_t i : px)
        for (int c = 0; c < 3; ++c) sum += std::abs(int((&got[i].r)[c]) - int((&want[i].r)[c]));
    EXPECT_LE(sum / double(3 * px.size()), 2.0);  // rounding, not misread blocks
    std::printf("4D VQ (identity codebook) vs the uncompressed 4D texture: max %d LSB, mean %.3f\n", worst,
                sum / double(3 * px.size()));
}

TEST(Vq4DPasses, AgreesWithTheAlphaBasisPassesWhereTheirStInterpolantsCoincide) {
    // The 2D route weights eye points by the hexagon's barycentric hat, the 4D route by the
    // 4D texture's bilinear (s, t) tent: different interpolants, equal for data affine in
    // (s, t). On such data the two differ only by rounding: the 4D passes' ≤ 16 (above),
    // the 2D route's 4 (u, v) parities × 3 eye points, each product and weight rounded
    // (≤ 1½ each: basis, MODULATE by the Gouraud weight, blend), ≤ 18. Bound 34; measured
    // in the report.
    const LightField lf = affineInStField();
    const VqLightField vq = identityVq(lf, {2, 2, 2, 2});
    const Profile& octane = profile(ProfileId::SgiOctaneMxe);
    auto mem = std::make_shared<tex::TextureMemory>(octane);
    const VqTextures4D tx4(mem, vq);
    raster::Device d4(octane, kSize, kSize, raster::DepthFormat::None);
    d4.beginFrame();
    renderVq4D(d4, tx4, vq, camera());
    auto mem2 = std::make_shared<tex::TextureMemory>(octane);
    const VqTextures tx2(mem2, vq);
    raster::Device d2(octane, kSize, kSize, raster::DepthFormat::None);
    d2.beginFrame();
    renderVq(d2, tx2, vq, camera());
    const std::vector<size_t> px = windowPixels(lf.slab);
    const std::vector<Rgba8> a = d4.readPixels(0, 0, kSize, kSize), b = d2.readPixels(0, 0, kSize, kSize);
    const int worst = worstRgb(a, b, px);
    EXPECT_LE(worst, 34);
    double sum = 0;
    for (size_t i : px)
        for (int c = 0; c < 3; ++c) sum += std::abs(int((&a[i].r)[c]) - int((&b[i].r)[c]));
    EXPECT_LE(sum / double(3 * px.size()), 2.0);
    std::printf("4D vs 2D alpha-basis VQ on an (s, t)-affine field: max %d LSB, mean %.3f\n", worst,
                sum / double(3 * px.size()));
}

TEST(Vq4DPasses, AProfileWithout4DTexturesIsRefusedByName) {
    const LightField lf = randomField();
    const VqLightField vq = identityVq(lf, {2, 2, 2, 2});
    try {
        VqTextures4D tx(std::make_shared<tex::TextureMemory>(profile(ProfileId::SgiO2)), vq);
        ADD_FAILURE() << "sgi-o2 built 4D VQ textures";
    } catch (const UnsupportedFeature& e) {
        EXPECT_NE(std::string(e.what()).find("sgi-o2"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("4D"), std::string::npos) << e.what();
    }
    try {
        LightFieldTexture4D t(std::make_shared<tex::TextureMemory>(profile(ProfileId::SgiO2)), lf);
        ADD_FAILURE() << "sgi-o2 built a 4D light-field texture";
    } catch (const UnsupportedFeature& e) {
        EXPECT_NE(std::string(e.what()).find("sgi-o2"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace rg::lightfield

#include "figure6.h"

namespace rg::lightfield {
namespace {

TEST(Figure6Sums, OneHotIsAPartitionOfUnityAndTwoPixelsSumToTwo) {
    // 2D: 4 bilinear passes, each rounded once (≤ ½): |Σ − 255| ≤ 2. 4D: 16 passes, ≤ 8.
    // "Two pixels" one texture per class: every texel counted twice, Σ = 510 within twice
    // those; the distinct textures (2 in 2D, 8 in 4D) each cover two classes, Σ = 255.
    const Figure6 f = makeFigure6(profile(ProfileId::SgiOctaneMxe), 4000);
    EXPECT_LE(f.sums["2d"]["one_hot"]["max_error_lsb"].get<int>(), 2);
    EXPECT_LE(f.sums["2d"]["two_pixels_one_per_class"]["max_error_lsb"].get<int>(), 4);
    EXPECT_LE(f.sums["2d"]["two_pixels_distinct"]["max_error_lsb"].get<int>(), 1);
    EXPECT_LE(f.sums["4d"]["one_hot"]["max_error_lsb"].get<int>(), 8);
    EXPECT_LE(f.sums["4d"]["two_pixels_one_per_class"]["max_error_lsb"].get<int>(), 16);
    EXPECT_LE(f.sums["4d"]["two_pixels_distinct"]["max_error_lsb"].get<int>(), 4);
    EXPECT_EQ(f.sums["4d"]["two_pixels_distinct"]["textures"].get<int>(), 8);
    EXPECT_GT(f.image.width, 0);
    EXPECT_THROW(makeFigure6(profile(ProfileId::SgiO2), 10), UnsupportedFeature);
}

}  // namespace
}  // namespace rg::lightfield

namespace rg::lightfield {
namespace {

TEST(VqSwapping, IndexTexturesThatDoNotFitAreStreamedAndDrawTheSameFrame) {
    // The Octane's 4 MiB filled to 1 KiB short: the 16 index textures of 128 B (2 KiB)
    // cannot all be resident, one streaming texture and the 4-byte basis can. The frame is
    // the resident one byte for byte; each colour pass whose block differs from the last
    // uploads its 128 bytes.
    const LightField lf = randomField();
    const VqLightField vq = identityVq(lf, {2, 2, 2, 2});
    const Profile& octane = profile(ProfileId::SgiOctaneMxe);
    auto frame = [&](bool fill, uint64_t* uploads, bool* resident) {
        auto mem = std::make_shared<tex::TextureMemory>(octane);
        std::vector<std::shared_ptr<tex::Texture>> ballast;
        if (fill)
            for (int k = 0; k < 12; ++k) {  // 2 MiB, 1 MiB, ... 1 KiB of RGBA8
                const int w = 1024 >> ((k + 1) / 2), h = 512 >> (k / 2);
                ballast.push_back(mem->create({tex::TextureTarget::Texture2D, tex::TexelFormat::RGBA8, w, h, 1, 1, 1}));
            }
        if (fill) {
            EXPECT_EQ(mem->residentBytes(), octane.textureMemoryBytes - 1024);
        }
        const VqTextures tx(mem, vq);
        *resident = tx.resident();
        raster::Device dev(octane, kSize, kSize, raster::DepthFormat::None);
        dev.textureUnits().setTextureMemory(mem);
        dev.beginFrame();
        const VqStats st = renderVq(dev, tx, vq, camera());
        dev.endFrame();
        *uploads = dev.textureUnits().counters().uploadBytes;
        EXPECT_EQ(st.colorPasses, 4 * lf.slab.S * lf.slab.T);
        return dev.readPixels(0, 0, kSize, kSize);
    };
    uint64_t upResident = 0, upSwapped = 0;
    bool resident = false, swappedResident = true;
    const std::vector<Rgba8> a = frame(false, &upResident, &resident);
    const std::vector<Rgba8> b = frame(true, &upSwapped, &swappedResident);
    EXPECT_TRUE(resident);
    EXPECT_FALSE(swappedResident);
    EXPECT_EQ(a, b);
    EXPECT_EQ(upResident, 0u);
    // Eye points in parity order: every colour pass draws another block's indices.
    EXPECT_EQ(upSwapped, uint64_t(4 * lf.slab.S * lf.slab.T) * 128u);
}

}  // namespace
}  // namespace rg::lightfield
