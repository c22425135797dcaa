// The light fields on the emulated devices: the Gortler reconstruction of a constant light
// field, the two lookup routes (pixel texture and software) byte for byte, the VQ passes
// against the uncompressed rendering, VQ bad input, and the claims at a small setting.
#include <gtest/gtest.h>

#include <cstring>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "gortler_renderer.h"
#include "lightfield_demo.h"
#include "lookup.h"
#include "reproduce_lightfield.h"
#include "scratch_dir.h"
#include "vq.h"

namespace rg::lightfield {
namespace {

LightSlab slab(int S, int U) {
    LightSlab s;
    s.stZ = 6.0f;
    s.uvZ = 0.0f;
    s.stMin = glm::vec2(-1.0f);
    s.stMax = glm::vec2(1.0f);
    s.uvMin = glm::vec2(-2.0f);
    s.uvMax = glm::vec2(2.0f);
    s.S = s.T = S;
    s.U = s.V = U;
    return s;
}

ray::Camera camera() {
    ray::Camera c;
    c.eye = glm::vec3(0.1f, -0.05f, 9.0f);
    c.fovYDegrees = 18.0f;
    return c;
}

TEST(GortlerDevice, ConstantLightFieldReproducesItsColourWithWeightsSummingToOne) {
    // Every sample (200, 100, 50): wherever the eye points cover the ray, each channel is
    // Σ round(c·w/255) over three weights that sum to 255 (± the rounding of each
    // interpolated weight): within 2 of c, and the alpha (Σ w) within 2 of 255.
    LightField lf;
    lf.slab = slab(5, 16);
    lf.data.resize(lf.slab.samples() * 3);
    for (size_t i = 0; i < lf.data.size(); i += 3) lf.data[i] = 200, lf.data[i + 1] = 100, lf.data[i + 2] = 50;
    for (ProfileId id : {ProfileId::SgiOctaneMxe, ProfileId::SgiO2}) {
        auto mem = std::make_shared<tex::TextureMemory>(profile(id));
        SliceTextures slices(mem, lf);
        raster::Device dev(profile(id), 96, 96, raster::DepthFormat::None);
        dev.beginFrame();
        renderGortler(dev, slices, lf, camera());
        const std::vector<Rgba8> px = dev.readPixels(0, 0, 96, 96);
        int inside = 0;
        for (int y = 0; y < 96; ++y)
            for (int x = 0; x < 96; ++x) {
                const ray::Ray r = ray::primaryRay(camera(), 96, 96, x + 0.5f, y + 0.5f);
                const auto st = lf.slab.intersect(r.origin, r.dir);
                if (!st || std::abs(st->x) > 0.95f || std::abs(st->y) > 0.95f) continue;
                ++inside;
                const Rgba8 c = px[size_t(y) * 96 + x];
                ASSERT_NEAR(c.r, 200, 2) << x << "," << y;
                ASSERT_NEAR(c.g, 100, 2) << x << "," << y;
                ASSERT_NEAR(c.b, 50, 2) << x << "," << y;
                ASSERT_NEAR(c.a, 255, 2) << x << "," << y;
            }
        EXPECT_GT(inside, 1000);
    }
}

// A light field that does not fit is swapped slice by slice through two groups of slots,
// the next group uploaded on another thread while the current one is drawn
// (SliceTextures). The oracle is the same light field drawn resident, uploaded once before
// the frame: the same pixels, and the swapped frame counts one slice's bytes per eye point,
// at every thread count and in a second frame through the same slots.
TEST(GortlerDevice, SwappedSlicesDrawWhatResidentSlicesDraw) {
    LightField lf;
    lf.slab = slab(8, 16);  // 64 slices of 768 bytes: more than two groups of 16
    lf.data.resize(lf.slab.samples() * 3);
    uint32_t h = 7u;
    for (uint8_t& b : lf.data) {
        h = h * 747796405u + 2891336453u;
        b = uint8_t(h >> 24);
    }
    const Profile& octane = profile(ProfileId::SgiOctaneMxe);
    const uint64_t all = uint64_t(lf.slab.S) * lf.slab.T * lf.sliceBytes();
    for (int threads : {1, 2, 3}) {
        SCOPED_TRACE("threads " + std::to_string(threads));
        auto residentMem = std::make_shared<tex::TextureMemory>(octane);
        SliceTextures resident(residentMem, lf);
        ASSERT_TRUE(resident.resident());
        raster::Device ref(octane, 96, 96, raster::DepthFormat::None, {Path::Fast, threads});
        ref.beginFrame();
        renderGortler(ref, resident, lf, camera());
        const std::vector<Rgba8> want = ref.readPixels(0, 0, 96, 96);

        // Fill the memory until the light field no longer fits but the slots do.
        auto mem = std::make_shared<tex::TextureMemory>(octane);
        std::vector<std::shared_ptr<tex::Texture>> filler;
        for (int n = 1024; n >= 8; n /= 2)
            while (octane.textureMemoryBytes - mem->residentBytes() >= uint64_t(n) * n * 4 + all / 2)
                filler.push_back(mem->create({tex::TextureTarget::Texture2D, tex::TexelFormat::RGBA8, n, n, 1, 1, 1}));
        SliceTextures swapped(mem, lf);
        ASSERT_FALSE(swapped.resident());
        raster::Device dev(octane, 96, 96, raster::DepthFormat::None, {Path::Fast, threads});
        for (int frame = 0; frame < 2; ++frame) {
            dev.beginFrame();
            mem->resetFrameCounters();
            const GortlerStats st = renderGortler(dev, swapped, lf, camera());
            EXPECT_EQ(mem->uploadBytes(), uint64_t(st.eyePoints) * lf.sliceBytes());
            EXPECT_EQ(st.uploadBytes, mem->uploadBytes());
            EXPECT_GE(st.eyePoints, 2 * SliceTextures::kGroup + 1);
            const std::vector<Rgba8> got = dev.readPixels(0, 0, 96, 96);
            ASSERT_EQ(got.size(), want.size());
            size_t differ = 0;
            for (size_t i = 0; i < got.size(); ++i)
                differ += std::memcmp(&got[i], &want[i], sizeof(Rgba8)) != 0;
            EXPECT_EQ(differ, 0u) << "frame " << frame;
        }
    }
}

TEST(LightFieldRoutes, PixelTextureEqualsSoftwareFor3DMapsAnd4DLightFields) {
    // Random read-backs through a random dual-paraboloid map (RGB mode) and a random 4D
    // light field (RGBA mode): the Octane's pixel texture and the O2's software lookup.
    ParaboloidMap map;
    map.size = 64;
    map.rgb.resize(64 * 64 * 2 * 3);
    for (size_t i = 0; i < map.rgb.size(); ++i) map.rgb[i] = uint8_t((i * 2654435761u) >> 13);
    LightField lf;
    lf.slab = slab(8, 16);
    lf.data.resize(lf.slab.samples() * 3);
    for (size_t i = 0; i < lf.data.size(); ++i) lf.data[i] = uint8_t((i * 40503u) >> 5);
    std::vector<Rgba8> coords(80 * 60);
    for (size_t i = 0; i < coords.size(); ++i) {
        const uint32_t h = uint32_t(i) * 2246822519u + 3266489917u;
        coords[i] = {uint8_t(h >> 3), uint8_t(h >> 11), uint8_t(h >> 19), uint8_t(h >> 24)};
    }
    const Profile& octane = profile(ProfileId::SgiOctaneMxe);
    auto mem = std::make_shared<tex::TextureMemory>(octane);
    auto tex3 = uploadParaboloidMap(*mem, map);
    auto tex4 = mem->create({tex::TextureTarget::Texture4D, tex::TexelFormat::RGB8, 16, 16, 8, 8, 1});
    mem->upload(*tex4, 0, 0, lf.data);
    const HostTexture h3 = hostParaboloidMap(map), h4 = hostLightField4D(lf);
    const SoftwareLookup sw3(h3, true), sw4(h4, false);
    for (Path path : {Path::Reference, Path::Fast}) {
        raster::Device dev(octane, 80, 60, raster::DepthFormat::None, {path, 2});
        pixelTextureLookup(dev, tex3, tex::PixelTexGenMode::Rgb, coords);
        std::vector<Rgba8> sw = coords;
        sw3.apply(sw, 2);
        EXPECT_EQ(dev.readPixels(0, 0, 80, 60), sw) << "3D, path " << int(path);
        pixelTextureLookup(dev, tex4, tex::PixelTexGenMode::Rgba, coords);
        sw = coords;
        sw4.apply(sw, 1);
        EXPECT_EQ(dev.readPixels(0, 0, 80, 60), sw) << "4D, path " << int(path);
    }
    // The O2 has no pixel texture: the route is refused there, naming the profile.
    raster::Device o2(profile(ProfileId::SgiO2), 80, 60, raster::DepthFormat::None);
    try {
        pixelTextureLookup(o2, tex3, tex::PixelTexGenMode::Rgb, coords);
        ADD_FAILURE() << "sgi-o2 ran a pixel-texture lookup";
    } catch (const UnsupportedFeature& e) {
        EXPECT_NE(std::string(e.what()).find("sgi-o2"), std::string::npos);
    }
}

// A light field of few distinct blocks: the codebook holds them all, so VQ is lossless and
// the passes must rebuild what the uncompressed light field renders.
LightField blockyField() {
    LightField lf;
    lf.slab = slab(6, 32);
    lf.data.resize(lf.slab.samples() * 3);
    for (int j = 0; j < 6; ++j)
        for (int i = 0; i < 6; ++i)
            for (int l = 0; l < 32; ++l)
                for (int k = 0; k < 32; ++k) {
                    const int pattern = ((k / 2) * 7 + (l / 2) * 3 + (i / 2) + (j / 2) * 5) % 6;
                    const int parity = (k & 1) + 2 * (l & 1) + 4 * (i & 1) + 8 * (j & 1);
                    uint8_t* p = lf.data.data() + lf.offset(i, j, k, l);
                    p[0] = uint8_t(40 * pattern + 3 * parity);
                    p[1] = uint8_t(255 - 30 * pattern);
                    p[2] = uint8_t(11 * parity + 20);
                }
    return lf;
}

TEST(VqPasses, LosslessCodebookDecodesExactlyAndThePassesMatchTheUncompressedField) {
    const LightField lf = blockyField();
    VqOptions o;
    o.codebookSize = 300;  // > 256: 2-byte indices through the 16-bit colour-table path
    o.iterations = 4;
    o.trainingBlocks = 100000;
    const VqLightField vq = quantize(lf, {2, 2, 2, 2}, o);
    EXPECT_EQ(vq.indexBytes(), 2);
    EXPECT_EQ(decode(vq).data, lf.data);  // 6 distinct blocks, 300 codewords: exact
    const Profile& octane = profile(ProfileId::SgiOctaneMxe);
    auto mem = std::make_shared<tex::TextureMemory>(octane);
    const VqTextures tx(mem, vq);
    raster::Device dev(octane, 96, 96, raster::DepthFormat::None);
    dev.beginFrame();
    const VqStats st = renderVq(dev, tx, vq, camera());
    EXPECT_EQ(st.tableLoads, 16);  // one per parity class
    const std::vector<Rgba8> got = dev.readPixels(0, 0, 96, 96);
    auto mem2 = std::make_shared<tex::TextureMemory>(octane);
    SliceTextures slices(mem2, lf);
    raster::Device ref(octane, 96, 96, raster::DepthFormat::None);
    ref.beginFrame();
    renderGortler(ref, slices, lf, camera());
    const std::vector<Rgba8> want = ref.readPixels(0, 0, 96, 96);
    // Four colour passes per eye point where the uncompressed field draws one.
    EXPECT_EQ(st.colorFragments, 4 * ref.counters().fragmentsGenerated);
    // Each product and basis weight is rounded on its own: the passes agree with the
    // uncompressed rendering within a few LSB (without the ½-sample index offset a quarter
    // of every hat reads the neighbouring block: errors of tens).
    int worst = 0;
    for (size_t i = 0; i < got.size(); ++i)
        for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int((&got[i].r)[c]) - int((&want[i].r)[c])));
    EXPECT_LE(worst, 6);
}

TEST(VqPasses, BadIndicesAndTooLargeCodebooksAreRefused) {
    const LightField lf = blockyField();
    VqOptions o;
    o.codebookSize = 300;
    o.iterations = 1;
    VqLightField vq = quantize(lf, {2, 2, 2, 2}, o);
    // The O2 keeps 256-entry colour tables: a 300-entry codebook is refused naming it.
    try {
        VqTextures tx(std::make_shared<tex::TextureMemory>(profile(ProfileId::SgiO2)), vq);
        ADD_FAILURE() << "sgi-o2 took a 300-entry codebook";
    } catch (const UnsupportedFeature& e) {
        EXPECT_NE(std::string(e.what()).find("sgi-o2"), std::string::npos) << e.what();
    }
    vq.indices[17] = 300;  // one past the codebook
    EXPECT_THROW(decode(vq), Error);
    try {
        VqTextures tx(std::make_shared<tex::TextureMemory>(profile(ProfileId::SgiOctaneMxe)), vq);
        ADD_FAILURE() << "an index outside the codebook was uploaded";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("outside the codebook"), std::string::npos) << e.what();
    }
    VqOptions big;
    big.codebookSize = 70000;
    EXPECT_THROW(quantize(lf, {2, 2, 2, 2}, big), Error);
}

TEST(LightfieldClaims, SmallSettingRunsEndToEndAndTheRoutesAgree) {
    LightfieldSettings s;
    s.imageSize = 64;
    s.truthSpp = 1;
    s.timingSize = 64;
    s.timingFrames = 1;
    s.geoS = 6;
    s.geoU = 32;
    s.radS = 8;
    s.radU = 32;
    s.vqK = 64;
    s.vqTraining = 2048;
    s.vqIterations = 2;
    s.lightGeoS = 4;
    s.lightGeoU = 16;
    s.lightS = 8;
    s.lightU = 16;
    s.envSize = 64;
    s.glossySize = 16;
    demos::ReproduceOptions o;
    o.outDir = test::scratchDir("lightfield");
    const nlohmann::json r = runLightfield(s, o);
    ASSERT_TRUE(r.contains("claims"));
    std::map<std::string, bool> holds;
    for (const auto& c : r["claims"]) holds[c["id"].get<std::string>()] = c["holds"].get<bool>();
    EXPECT_TRUE(holds.at("pixel_texture_equals_software"));
    EXPECT_TRUE(holds.at("gortler_weights_sum_to_one"));
    EXPECT_TRUE(holds.at("vq_colour_passes_cost_4x"));
    EXPECT_TRUE(holds.at("environment_swap_needs_no_recompute"));
    EXPECT_TRUE(std::filesystem::exists(o.outDir / "figure3.png"));
    EXPECT_TRUE(std::filesystem::exists(o.outDir / "figure6.png"));
    // The 4D-texture VQ route ran on the same codebook, its basis a partition of unity.
    const auto& v4 = r["vector_quantization"]["vq_4d"];
    EXPECT_EQ(v4["colour_passes"].get<int>(), 16);
    EXPECT_LE(v4["frame_basis_sums"]["one_hot"]["max_error_lsb"].get<int>(), 8);
    EXPECT_LE(r["figure6"]["4d"]["one_hot"]["max_error_lsb"].get<int>(), 8);
    EXPECT_NE(v4["o2_refused"].get<std::string>().find("sgi-o2"), std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(o.outDir / "geometry_lightfield.json"));
}

}  // namespace
}  // namespace rg::lightfield

namespace rg::lightfield {
namespace {

TEST(LightfieldDemo, VqFrameAfterALookupFrameEqualsAFreshDevicesFrame) {
    // The viewer keeps one device and switches modes on it: a VQ frame drawn after a
    // pixel-texture frame must equal the same VQ frame on a fresh device.
    LightfieldDemo demo(viewer::DemoOptions{});
    const Profile& octane = profile(ProfileId::SgiOctaneMxe);
    raster::Device a(octane, 128, 128, raster::DepthFormat::D24);
    viewer::findParam(demo.params(), "vq_mode").value = 0;
    demo.render(a, demo.rig().start);
    viewer::findParam(demo.params(), "vq_mode").value = 3;
    demo.render(a, demo.rig().start);
    raster::Device b(octane, 128, 128, raster::DepthFormat::D24);
    demo.render(b, demo.rig().start);
    EXPECT_EQ(a.readPixels(0, 0, 128, 128), b.readPixels(0, 0, 128, 128));
    // An opaque image (the last pass sets alpha to one) of the lit field, not a black or
    // saturated frame.
    double sum = 0;
    for (const Rgba8& p : b.readPixels(0, 0, 128, 128)) {
        ASSERT_EQ(p.a, 255);
        sum += p.r + p.g + p.b;
    }
    const double mean = sum / (128.0 * 128.0 * 3.0);
    EXPECT_GT(mean, 20.0);
    EXPECT_LT(mean, 235.0);
}

// The viewer's 4D route is the reproduction's renderVq4D on the same codebook, frame for
// frame, after a frame of the other route on the same device; a profile without 4D
// textures refuses it naming itself, and the next frame of the other route still draws.
TEST(LightfieldDemo, The4DVqRouteIsRenderVq4DAndTheO2RefusesIt) {
    LightfieldDemo demo(viewer::DemoOptions{});
    const Profile& octane = profile(ProfileId::SgiOctaneMxe);
    raster::Device a(octane, 96, 96, raster::DepthFormat::D24);
    viewer::findParam(demo.params(), "vq_mode").value = 3;
    viewer::findParam(demo.params(), "vq_route").value = 0;
    demo.render(a, demo.rig().start);
    const std::vector<Rgba8> route2d = a.readPixels(0, 0, 96, 96);
    viewer::findParam(demo.params(), "vq_route").value = 1;
    demo.render(a, demo.rig().start);
    const std::vector<Rgba8> viewer4d = a.readPixels(0, 0, 96, 96);

    raster::Device b(octane, 96, 96, raster::DepthFormat::D24);
    auto memory = std::make_shared<tex::TextureMemory>(octane);
    b.textureUnits().setTextureMemory(memory);
    VqTextures4D tx(memory, demo.vq(3));
    b.beginFrame();
    renderVq4D(b, tx, demo.vq(3), demo.rig().start);
    b.endFrame();
    EXPECT_EQ(viewer4d, b.readPixels(0, 0, 96, 96));
    EXPECT_NE(viewer4d, route2d) << "the switch did not change the route";

    raster::Device o2(profile(ProfileId::SgiO2), 96, 96, raster::DepthFormat::D24);
    // Still mode 3 and the 4D route: the profile's want of SGIS_texture4D is what it names.
    try {
        demo.render(o2, demo.rig().start);
        ADD_FAILURE() << "sgi-o2 drew the 4D-texture VQ route";
    } catch (const UnsupportedFeature& e) {
        EXPECT_NE(std::string(e.what()).find("sgi-o2"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("4D"), std::string::npos) << e.what();
    }
    viewer::findParam(demo.params(), "vq_mode").value = 0;
    viewer::findParam(demo.params(), "route").value = 1;  // the O2's software lookup
    EXPECT_NO_THROW(demo.render(o2, demo.rig().start));
}

}  // namespace
}  // namespace rg::lightfield
