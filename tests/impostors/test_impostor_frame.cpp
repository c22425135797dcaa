// The impostors frame on the emulated geforce8800: the cube faces render what the sampler
// reads back; the same bytes on both paths and any thread count in every mode; static
// objects see the mover through its refractor map (§5.2); bad input is an error naming it.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "core/error.h"
#include "core/profile.h"
#include "impostor_renderer.h"
#include "scratch_dir.h"
#include "texunit/cube_mapping.h"

namespace rg::impostors {
namespace {

// Five objects of the §8 scene, coarsely tessellated: the board, the mover (the white
// d-pawn), the sphere it is seen through, a queen and a knight (the one piece that is not
// a lathe, turned by its placement).
ImpostorScene smallScene(bool mirrorMover = false) {
    ChessOptions o;
    o.segments = 12;
    o.sphereSlices = 16;
    o.mirrorMover = mirrorMover;
    o.keep = {"white_queen3", "white_knight6"};
    return makeChessScene(o);
}

std::vector<uint8_t> frameBytes(const ImpostorRenderer& r) {
    const ray::Image im = r.frame();
    std::vector<uint8_t> out;
    for (float v : im.pixels) out.push_back(uint8_t(std::lround(v * 255.0f)));
    return out;
}

// The cube faces' view and projection put each direction's surface on the texel
// tex::selectCubeFace reads for it: a box around the centre rendered into a refractor
// map holds, at every texel, the box's distance along the texel centre's direction.
TEST(ImpostorCube, FacesRenderWhatTheSamplerReadsBack) {
    tex::TextureMemory memory(profile(ProfileId::GeForce8800));
    raster::ProgrammableDevice dev(profile(ProfileId::GeForce8800), raster::DeviceOptions{Path::Fast, 2});
    const int n = 32;
    tex::TextureDesc d;
    d.target = tex::TextureTarget::CubeMap;
    d.format = tex::TexelFormat::RGBA32F;
    d.width = d.height = n;
    auto cube = memory.createRenderTarget(d);
    tex::TextureDesc dd;
    dd.format = tex::TexelFormat::Depth24;
    dd.width = dd.height = n;
    auto depth = memory.createRenderTarget(dd);
    // A box [lo, hi] around the centre c: 12 triangles, normals outward.
    const glm::vec3 c(0.3f, 1.0f, -0.2f), lo = c + glm::vec3(-1.0f, -0.5f, -2.0f), hi = c + glm::vec3(1.5f, 0.7f, 1.0f);
    std::vector<ImpostorVertex> v;
    std::vector<uint32_t> idx;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side) {
            const int a = (axis + 1) % 3, b = (axis + 2) % 3;
            glm::vec3 corner[4];
            for (int k = 0; k < 4; ++k) {
                glm::vec3 p;
                p[axis] = side ? hi[axis] : lo[axis];
                p[a] = (k & 1) ? hi[a] : lo[a];
                p[b] = (k & 2) ? hi[b] : lo[b];
                corner[k] = p;
            }
            glm::vec3 nrm(0.0f);
            nrm[axis] = side ? 1.0f : -1.0f;
            const uint32_t base = uint32_t(v.size());
            for (const glm::vec3& p : corner) v.push_back({p, nrm, {}});
            for (uint32_t i : {0u, 1u, 2u, 1u, 3u, 2u}) idx.push_back(base + i);
        }
    for (int f = 0; f < 6; ++f) {
        raster::ColorTarget ct{cube, 0, f};
        dev.setRenderTargets({&ct, 1}, raster::DepthTarget{depth});
        dev.clearColor(0, glm::vec4(0.0f));
        dev.clearDepth(1.0f);
        raster::ProgramState st;
        st.depthTest = st.depthWrite = 1;
        dev.setState(st);
        WorldVP vp;
        vp.viewProj = cubeFaceProjection(0.01f, 10.0f) * cubeFaceView(f, c);
        NormalDistanceFP fp;
        fp.centre[0] = c.x, fp.centre[1] = c.y, fp.centre[2] = c.z;
        drawTriangles(dev, vp, fp, std::span<const ImpostorVertex>(v), std::span<const uint32_t>(idx));
    }
    int checked = 0;
    for (int f = 0; f < 6; ++f)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::vec3 dir = glm::normalize(
                    tex::cubeFaceDirection(tex::CubeFace(f), (float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n)));
                float t = 1e30f;
                for (int a = 0; a < 3; ++a) {
                    if (dir[a] > 0) t = std::min(t, (hi[a] - c[a]) / dir[a]);
                    if (dir[a] < 0) t = std::min(t, (lo[a] - c[a]) / dir[a]);
                }
                const glm::vec4 texel = cube->renderDataF(0, f)[size_t(y) * size_t(n) + size_t(x)];
                ASSERT_NEAR(texel.w, t, 1e-3f * t) << "face " << f << " texel (" << x << ", " << y << ")";
                // And the sampler reads that texel for that direction.
                const tex::CubeCoord cc = tex::selectCubeFace(dir);
                ASSERT_EQ(int(cc.face), f);
                ASSERT_EQ(int(cc.s * float(n)), x);
                ASSERT_EQ(int(cc.t * float(n)), y);
                ++checked;
            }
    EXPECT_EQ(checked, 6 * n * n);
}

// Every mode's frame (and the maps behind it) gives the same bytes on the reference path
// and on the fast path with 1, 2 and 3 threads.
TEST(ImpostorFrame, SameBytesOnBothPathsAndAnyThreadCount) {
    const ImpostorScene scene = smallScene();
    for (Mode mode : {Mode::Static, Mode::Classical, Mode::Separated}) {
        ImpostorSettings s;
        s.width = 40;
        s.height = 32;
        s.envSize = 8;
        s.refractorSize = 8;
        s.lightMapSize = 32;
        s.shadowMapSize = 64;
        s.mode = mode;
        s.moverU = 0.5f;
        std::vector<uint8_t> first;
        for (auto [path, threads] : {std::pair{Path::Fast, 1}, {Path::Fast, 2}, {Path::Fast, 3}, {Path::Reference, 1}}) {
            ImpostorRenderer r(scene, threads, path);
            const ImpostorFrame f = r.render(scene.closeUp, s);
            EXPECT_GT(f.glassFragments, 50);
            if (first.empty()) first = frameBytes(r);
            else EXPECT_EQ(frameBytes(r), first) << modeName(mode) << " threads " << threads;
        }
    }
}

// §5.2, Figure 5: in the separated mode the sphere's rays find the mirror pawn behind it in
// the pawn's refractor map (they are flagged, take more searches), and the image matches
// the classical mode's — where every map holds the pawn — far better than with the pawn
// left out of the sphere's view.
TEST(ImpostorFrame, StaticObjectsSeeTheMoverThroughItsRefractorMap) {
    const ImpostorScene scene = smallScene(true);
    ImpostorRenderer r(scene, 2, Path::Fast);
    ImpostorSettings s;
    s.width = s.height = 96;
    s.envSize = 32;
    s.refractorSize = 32;
    s.moverU = 0.5f;
    s.mode = Mode::Separated;
    s.diagnostics = true;
    r.render(scene.closeUp, s);
    const ImpostorRenderer::Diagnostics d = r.readDiagnostics();
    int flagged = 0, moreSearches = 0;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            flagged += d.flags.at(x, y, 0) > 0;
            moreSearches += d.searches.at(x, y, 0) > 3;
        }
    EXPECT_GT(flagged, 20) << "no static glass pixel's ray met the mover";
    EXPECT_GE(moreSearches, flagged);
}

TEST(ImpostorErrors, BadSettingsNameTheValueAndTheLimit) {
    auto message = [](const ImpostorSettings& s) {
        try {
            validate(s);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    ImpostorSettings s;
    s.depth = 0;
    EXPECT_NE(message(s).find("DEPTH 0 outside 1–8"), std::string::npos) << message(s);
    s.depth = 1000;
    EXPECT_NE(message(s).find("DEPTH 1000"), std::string::npos);
    s = {};
    s.envSize = 16384;
    EXPECT_NE(message(s).find("largest cube-map face"), std::string::npos) << message(s);
    s = {};
    s.refractorSize = 0;
    EXPECT_NE(message(s).find("refractor distance map 0"), std::string::npos) << message(s);
    s = {};
    s.iterations = -1;
    EXPECT_NE(message(s).find("iterations -1"), std::string::npos) << message(s);
    s = {};
    s.moverU = 2.0f;
    EXPECT_NE(message(s).find("mover position"), std::string::npos) << message(s);
    // Mode A has no height-map search: refused, not drawn with distance maps.
    s = {};
    s.mode = Mode::RefractorMapsOnly;
    s.exit = Exit::HeightMap;
    EXPECT_NE(message(s).find("mode A"), std::string::npos) << message(s);
    s.exit = Exit::DistanceMap;
    EXPECT_EQ(message(s), "");
    // Maps the profile's texture memory cannot hold: the limit named.
    const ImpostorScene scene = smallScene();
    ImpostorRenderer r(scene, 1, Path::Fast);
    s = {};
    s.envSize = 4096;
    try {
        r.render(scene.camera, s);
        FAIL() << "4096² impostors fit";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("MiB of texture memory"), std::string::npos) << e.what();
    }
}

TEST(ImpostorErrors, ScenesWithoutGlassAndUnknownMoversAreRefused) {
    ImpostorScene s = smallScene();
    ChessOptions keep;
    keep.segments = 12;
    keep.keep = {"white_queen3", "white_queen9"};
    try {
        makeChessScene(keep);
        FAIL() << "a kept object that does not exist";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no object 'white_queen9'"), std::string::npos) << e.what();
    }
    try {
        setMover(s, "white_pawn9");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("no object 'white_pawn9'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("glass_sphere"), std::string::npos) << e.what();
    }
    try {
        setMover(s, "board");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("neither glass nor a mirror"), std::string::npos) << e.what();
    }
    const std::filesystem::path dir = test::scratchDir("no_glass");
    {
        std::ofstream f(dir / "diffuse.json");
        f << R"({"materials": [{"name": "clay", "type": "diffuse"}],
                 "objects": [{"name": "ball", "shape": "sphere", "material": "clay"}],
                 "cameras": [{"name": "c", "eye": [0, 0, 5], "target": [0, 0, 0]}]})";
    }
    try {
        impostorSceneFromFile((dir / "diffuse.json").string());
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("has no glass or mirror object"), std::string::npos) << e.what();
    }
    EXPECT_THROW(impostorSceneFromFile(RETROGLASS_SOURCE_DIR "/data/scenes/example.json", "nothing"), Error);
    const ImpostorScene ex = impostorSceneFromFile(RETROGLASS_SOURCE_DIR "/data/scenes/example.json", "ball");
    EXPECT_EQ(ex.scene.objects[size_t(ex.mover)].name, "ball");
    EXPECT_EQ(ex.glass.size(), 2u);  // the chrome teapot and the glass ball
}

}  // namespace
}  // namespace rg::impostors
