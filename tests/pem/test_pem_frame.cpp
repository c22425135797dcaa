// The PEM frame is a deterministic function of its inputs: the same bytes on the
// reference and fast rasterizer paths and any thread count, and the same bytes after the
// maps went through an EXR asset and back (issue: "loading it renders the same frame bit
// for bit").
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "pem_assets.h"
#include "pem_renderer.h"
#include "raycore/builtin_scenes.h"
#include "scratch_dir.h"

namespace fs = std::filesystem;

namespace rg::pem {
namespace {

struct Small {
    PemScene scene;
    ViewSample sample;
    Small() {
        ray::BuiltinOptions bo;
        bo.teapotLevel = 5;
        scene = makePemScene(ray::makeBuiltinScene("teapot-in-room", bo), PemSceneOptions{});
        std::mt19937 rng(3);
        for (size_t p = 0; p < scene.parts.size(); ++p) {
            PartMaps m;
            for (MapTexels* t : {&m.local, &m.distant}) {
                t->layout = TexelLayout{16, 6};
                t->texels.resize(size_t(t->layout.count()));
                for (auto& x : t->texels)
                    x = {uint8_t(rng()), uint8_t(rng()), uint8_t(rng()), uint8_t(rng())};
            }
            sample.parts.push_back(std::move(m));
        }
    }
};

std::vector<Rgba8> frame(const Small& s, const ViewSample& maps, Path path, int threads,
                         bool blended) {
    raster::Device device(profileByName("geforce256"), 96, 72, raster::DepthFormat::D24,
                          {path, threads});
    PemRenderer r(device, s.scene);
    PemSample a = uploadSample(r, maps, EmMode::Layered);
    ray::Camera cam = s.scene.scene.viewpointPaths.at(0).at(3);
    if (blended)
        r.render(cam, EmMode::Layered, a, &a, 0.25f);
    else
        r.render(cam, EmMode::Layered, a);
    auto c = device.framebuffer().color();
    return {c.begin(), c.end()};
}

TEST(PemFrame, SameBytesOnBothPathsAndAnyThreadCount) {
    Small s;
    for (bool blended : {false, true}) {
        std::vector<Rgba8> ref = frame(s, s.sample, Path::Reference, 1, blended);
        int lit = 0;
        for (const Rgba8& c : ref) lit += c.a != 0;
        EXPECT_GT(lit, 300) << "the teapot should cover part of the frame";
        for (int threads : {1, 2, 3})
            EXPECT_EQ(frame(s, s.sample, Path::Fast, threads, blended), ref)
                << "fast path, " << threads << " threads, blended=" << blended;
    }
}

TEST(PemFrame, LoadedAssetsRenderTheSameFrame) {
    Small s;
    fs::path dir = test::scratchDir("pem-frame-assets");
    ViewSample loaded;
    for (size_t p = 0; p < s.sample.parts.size(); ++p) {
        PartMaps m;
        saveMap(dir / ("local" + std::to_string(p) + ".exr"), s.sample.parts[p].local);
        saveMap(dir / ("distant" + std::to_string(p) + ".exr"), s.sample.parts[p].distant);
        m.local = loadMap(dir / ("local" + std::to_string(p) + ".exr"), TexelLayout{16, 6});
        m.distant = loadMap(dir / ("distant" + std::to_string(p) + ".exr"), TexelLayout{16, 6});
        loaded.parts.push_back(std::move(m));
    }
    EXPECT_EQ(frame(s, loaded, Path::Fast, 2, true), frame(s, s.sample, Path::Fast, 2, true));
}

}  // namespace
}  // namespace rg::pem
