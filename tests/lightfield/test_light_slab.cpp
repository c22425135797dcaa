// Two-plane slabs (Heidrich et al. 1999 §3), their parameter file and the bad input it must
// refuse, the dual-paraboloid encoding of §4, and the Gortler triangulation's weights.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "core/error.h"
#include "gortler_renderer.h"
#include "lf_capture.h"
#include "light_slab.h"
#include "scratch_dir.h"
#include "texunit/paraboloid_mapping.h"

namespace rg::lightfield {
namespace {

namespace fs = std::filesystem;

LightSlab smallSlab() {
    LightSlab s;
    s.stZ = 6.0f;
    s.uvZ = 0.0f;
    s.stMin = glm::vec2(-1.0f);
    s.stMax = glm::vec2(1.0f);
    s.uvMin = glm::vec2(-2.0f);
    s.uvMax = glm::vec2(2.0f);
    s.S = s.T = 4;
    s.U = s.V = 8;
    return s;
}

TEST(LightSlab, SampleRaysCrossTheirEyePointAndTexelCentre) {
    const LightSlab s = smallSlab();
    for (int j = 0; j < s.T; ++j)
        for (int i = 0; i < s.S; ++i)
            for (int l = 0; l < s.V; ++l)
                for (int k = 0; k < s.U; ++k) {
                    const ray::Ray r = s.sampleRay(i, j, k, l);
                    const auto stuv = s.intersect(r.origin, r.dir);
                    ASSERT_TRUE(stuv);
                    const glm::vec3 e = s.eyePoint(i, j);
                    const glm::vec3 w = s.windowPoint((k + 0.5f) / s.U, (l + 0.5f) / s.V);
                    EXPECT_NEAR(stuv->x, e.x, 1e-5f);
                    EXPECT_NEAR(stuv->y, e.y, 1e-5f);
                    EXPECT_NEAR(stuv->z, w.x, 1e-5f);
                    EXPECT_NEAR(stuv->w, w.y, 1e-5f);
                    // The 4D texture coordinates put the sample on its texel centres.
                    const glm::vec4 tc = s.textureCoords(*stuv);
                    EXPECT_NEAR(tc.x, (k + 0.5f) / s.U, 1e-5f);
                    EXPECT_NEAR(tc.z, (i + 0.5f) / s.S, 1e-5f);
                    EXPECT_NEAR(tc.w, (j + 0.5f) / s.T, 1e-5f);
                }
}

LightField smallField() {
    LightField lf;
    lf.slab = smallSlab();
    lf.channels = 3;
    lf.data.resize(lf.slab.samples() * 3);
    for (size_t i = 0; i < lf.data.size(); ++i) lf.data[i] = uint8_t(i * 37 + 11);
    ray::Bounds b;
    b.lo = glm::vec3(-0.5f);
    b.hi = glm::vec3(0.5f);
    lf.objectBounds = b;
    return lf;
}

TEST(LightSlabFile, WrittenAndReadBackEqual) {
    const fs::path dir = test::scratchDir("slab");
    const LightField lf = smallField();
    writeLightField(dir / "lf.json", lf);
    const LightField back = readLightField(dir / "lf.json");
    EXPECT_EQ(back.data, lf.data);
    EXPECT_EQ(back.slab.S, lf.slab.S);
    EXPECT_EQ(back.slab.U, lf.slab.U);
    EXPECT_EQ(back.slab.stZ, lf.slab.stZ);
    EXPECT_EQ(back.slab.uvMax, lf.slab.uvMax);
    EXPECT_EQ(back.content, lf.content);
    ASSERT_TRUE(back.objectBounds);
    EXPECT_EQ(back.objectBounds->hi, lf.objectBounds->hi);
}

// Each bad file must raise rg::Error whose message names the file and says what is wrong.
void expectRefused(const fs::path& path, const std::string& what) {
    try {
        readLightField(path);
        ADD_FAILURE() << "accepted: " << what;
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(path.string()), std::string::npos) << m;
        EXPECT_NE(m.find(what), std::string::npos) << "expected '" << what << "' in: " << m;
    }
}

TEST(LightSlabFile, BadFilesAreRefusedNamingTheFile) {
    const fs::path dir = test::scratchDir("bad");
    const LightField lf = smallField();
    writeLightField(dir / "good.json", lf);
    std::ifstream in(dir / "good.json");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    auto variant = [&](const std::string& name, std::string body) {
        std::ofstream(dir / name) << body;
        fs::copy_file(dir / "good.json.bin", dir / (name + ".bin"), fs::copy_options::overwrite_existing);
        // The data file is named inside: keep pointing at the good one.
        return dir / name;
    };
    auto replace = [&](std::string s, const std::string& a, const std::string& b) {
        const size_t p = s.find(a);
        EXPECT_NE(p, std::string::npos) << a;
        if (p != std::string::npos) s.replace(p, a.size(), b);
        return s;
    };
    expectRefused(variant("truncated.json", text.substr(0, text.size() / 2)), "not valid JSON");
    expectRefused(variant("bytes.json", replace(text, "\"data_bytes\": 3072", "\"data_bytes\": 3071")), "data_bytes");
    expectRefused(variant("texel.json", replace(text, "\"RGB8\"", "\"RGBA8\"")), "does not fit texel");
    expectRefused(variant("npot.json", replace(text, "8,\n      8", "6,\n      8")), "powers of two");
    expectRefused(variant("missing.json", replace(text, "\"uv_plane\"", "\"uv_plan\"")), "missing \"uv_plane\"");
    expectRefused(variant("coincide.json", replace(text, "\"z\": 6.0", "\"z\": 0.0")), "coincide");
    // The planes must bound the object: one that reaches past the eye-point plane, and one
    // whose shadow leaves the window.
    expectRefused(variant("cut.json", replace(text, "0.5,\n      0.5,\n      0.5", "0.5,\n      0.5,\n      7.0")),
                  "do not bound the object");
    expectRefused(variant("wide.json", replace(text, "0.5,\n      0.5,\n      0.5", "3.5,\n      0.5,\n      0.5")),
                  "do not bound the object");
    // A data file shorter than the slab (truncated).
    fs::resize_file(dir / "good.json.bin", 1000);
    expectRefused(dir / "good.json", "truncated");
}

TEST(ParaboloidEncoding, MatchesTheTextureUnitsMappingAndRoundTrips) {
    std::mt19937 rng(5);
    std::normal_distribution<float> g;
    for (int n = 0; n < 100000; ++n) {
        const glm::vec3 d = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        const ParaboloidCoord c = toParaboloid(d);
        const tex::ParaboloidCoord t = tex::directionToParaboloid(d);
        ASSERT_EQ(c.side, t.side == tex::ParaboloidSide::Front ? 0 : 1);
        ASSERT_NEAR(c.s, t.s, 1e-6f);
        ASSERT_NEAR(c.t, t.t, 1e-6f);
        const glm::vec3 back = fromParaboloid(c.s, c.t, c.side);
        ASSERT_NEAR(glm::length(back - d), 0.0f, 2e-6f);
    }
}

// Σ over eye points of their weights at random (s, t) points inside the grid.
double maxWeightSumError(Triangulation tri) {
    const LightSlab s = smallSlab();
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    double worst = 0;
    for (int n = 0; n < 2000; ++n) {
        const glm::vec2 p(u(rng), u(rng));
        double sum = 0;
        for (int j = 0; j < s.T; ++j)
            for (int i = 0; i < s.S; ++i) sum += hatWeight(s, i, j, p, tri);
        worst = std::max(worst, std::abs(sum - 1.0));
    }
    return worst;
}

TEST(GortlerWeights, OneFixedDiagonalSumsToOneAndPerEyePointDiagonalsDoNot) {
    EXPECT_LT(maxWeightSumError(Triangulation::FixedDiagonal), 1e-9);
    // The trap the test guards against: each eye point's own diagonals overlap.
    EXPECT_GT(maxWeightSumError(Triangulation::PerEyePointDiagonals), 0.1);
    // The hexagon: 6 triangles around an interior eye point, 3 at an edge-corner pair.
    EXPECT_EQ(eyePointTriangles(smallSlab(), 1, 1, Triangulation::FixedDiagonal).size(), 6u);
    EXPECT_EQ(eyePointTriangles(smallSlab(), 0, 0, Triangulation::FixedDiagonal).size(), 2u);
    EXPECT_EQ(eyePointTriangles(smallSlab(), 3, 0, Triangulation::FixedDiagonal).size(), 1u);
}

}  // namespace
}  // namespace rg::lightfield
