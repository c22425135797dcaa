// Mappings: cube-map face selection (ARB_texture_cube_map §3.8.6), dual paraboloids
// (Heidrich & Seidel 1998) and texture-coordinate generation
// (docs/hardware.md, "Cube mapping", "Paraboloid mapping", "Coordinate generation").
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>

#include "tex_test_util.h"
#include "texunit/cube_mapping.h"
#include "texunit/paraboloid_mapping.h"
#include "texunit/texgen.h"
#include "texunit/texture_units.h"

namespace rg::tex {
namespace {

using testing::Rng;

void expectFace(glm::vec3 r, CubeFace face, float s, float t) {
    CubeCoord c = selectCubeFace(r);
    EXPECT_EQ(c.face, face) << "r = (" << r.x << ", " << r.y << ", " << r.z << ")";
    EXPECT_EQ(c.s, s) << "r = (" << r.x << ", " << r.y << ", " << r.z << ")";
    EXPECT_EQ(c.t, t) << "r = (" << r.x << ", " << r.y << ", " << r.z << ")";
}

TEST(CubeMapping, EachAxisPerTheSpecTable) {
    // Worked by hand from the table: s = (sc/|ma| + 1)/2, t = (tc/|ma| + 1)/2.
    expectFace({2.0f, 0.5f, -1.0f}, CubeFace::PositiveX, 0.75f, 0.375f);   // sc=−rz, tc=−ry
    expectFace({-4.0f, 2.0f, 2.0f}, CubeFace::NegativeX, 0.75f, 0.25f);    // sc=+rz, tc=−ry
    expectFace({0.5f, 4.0f, -2.0f}, CubeFace::PositiveY, 0.5625f, 0.25f);  // sc=+rx, tc=+rz
    expectFace({1.0f, -2.0f, 1.0f}, CubeFace::NegativeY, 0.75f, 0.25f);    // sc=+rx, tc=−rz
    expectFace({1.0f, 1.0f, 4.0f}, CubeFace::PositiveZ, 0.625f, 0.375f);   // sc=+rx, tc=−ry
    expectFace({1.0f, 1.0f, -4.0f}, CubeFace::NegativeZ, 0.375f, 0.375f);  // sc=−rx, tc=−ry
}

TEST(CubeMapping, LengthNeverEnters) {
    for (float k : {1e-3f, 0.5f, 1.0f, 3.0f, 1e4f}) {
        CubeCoord a = selectCubeFace(glm::vec3(0.25f, -0.5f, 1.0f) * k);
        EXPECT_EQ(a.face, CubeFace::PositiveZ);
        EXPECT_FLOAT_EQ(a.s, 0.625f);
        EXPECT_FLOAT_EQ(a.t, 0.75f);
    }
}

TEST(CubeMapping, TiesGoXThenYThenZAndZeroIsPositive) {
    expectFace({1, 1, 0}, CubeFace::PositiveX, 0.5f, 0.0f);
    expectFace({1, 0, 1}, CubeFace::PositiveX, 0.0f, 0.5f);
    expectFace({1, 1, 1}, CubeFace::PositiveX, 0.0f, 0.0f);
    expectFace({-1, 1, 0}, CubeFace::NegativeX, 0.5f, 0.0f);
    expectFace({0, 1, 1}, CubeFace::PositiveY, 0.5f, 1.0f);
    expectFace({0, -1, -1}, CubeFace::NegativeY, 0.5f, 1.0f);
    expectFace({0, 0, 0}, CubeFace::PositiveX, 0.5f, 0.5f);
    expectFace({-0.0f, 0, 0}, CubeFace::PositiveX, 0.5f, 0.5f);
    expectFace({0, 0, -0.0f}, CubeFace::PositiveX, 0.5f, 0.5f);
    expectFace({0, -0.0f, 2}, CubeFace::PositiveZ, 0.5f, 0.5f);
}

TEST(CubeMapping, RoundTripWithin2e6Radians) {
    Rng rng(7);
    double worst = 0;
    for (int i = 0; i < 200000; ++i) {
        glm::vec3 r(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        if (glm::length(r) < 1e-3f) continue;
        r *= rng.uniform(0.01f, 100.0f);
        CubeCoord c = selectCubeFace(r);
        ASSERT_GE(c.s, 0.0f);
        ASSERT_LE(c.s, 1.0f);
        ASSERT_GE(c.t, 0.0f);
        ASSERT_LE(c.t, 1.0f);
        glm::dvec3 a = glm::normalize(glm::dvec3(r)), b = glm::normalize(glm::dvec3(cubeFaceDirection(c.face, c.s, c.t)));
        worst = std::max(worst, glm::length(a - b));
    }
    EXPECT_LT(worst, 2e-6) << "direction → (face, s, t) → direction";
}

TEST(ParaboloidMapping, RoundTripWithin2e6Radians) {
    Rng rng(11);
    double worst = 0;
    for (int i = 0; i < 200000; ++i) {
        glm::vec3 r(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        if (glm::length(r) < 1e-3f) continue;
        ParaboloidCoord c = directionToParaboloid(r);
        EXPECT_EQ(c.side, r.z >= 0 ? ParaboloidSide::Front : ParaboloidSide::Back);
        glm::dvec3 a = glm::normalize(glm::dvec3(r));
        glm::dvec3 b = glm::dvec3(paraboloidToDirection(c.side, c.s, c.t));
        worst = std::max(worst, glm::length(a - b));
    }
    EXPECT_LT(worst, 2e-6) << "direction → paraboloid → direction";
}

TEST(ParaboloidMapping, KnownPointsAndRim) {
    ParaboloidCoord f = directionToParaboloid({0, 0, 1});
    EXPECT_EQ(f.side, ParaboloidSide::Front);
    EXPECT_EQ(f.s, 0.5f);
    EXPECT_EQ(f.t, 0.5f);
    ParaboloidCoord b = directionToParaboloid({0, 0, -5});
    EXPECT_EQ(b.side, ParaboloidSide::Back);
    EXPECT_EQ(b.s, 0.5f);
    // The rz = 0 rim belongs to the front, at the circle's edge; the back map (not
    // mirrored) would put it at the same (s, t).
    ParaboloidCoord rim = directionToParaboloid({1, 0, 0});
    EXPECT_EQ(rim.side, ParaboloidSide::Front);
    EXPECT_EQ(rim.s, 1.0f);
    EXPECT_EQ(rim.t, 0.5f);
    ParaboloidCoord rimNeg0 = directionToParaboloid({0, -1, -0.0f});
    EXPECT_EQ(rimNeg0.side, ParaboloidSide::Front);
    EXPECT_EQ(rimNeg0.t, 0.0f);
    // 45° off the front axis: x = sin/(1 + cos) = tan(22.5°).
    ParaboloidCoord d = directionToParaboloid({1, 0, 1});
    EXPECT_NEAR(d.s, (std::tan(M_PI / 8) + 1) / 2, 1e-7);
}

TEST(ParaboloidMapping, TextureMatrixAndProjectiveDivideAgreeWithDirectMapping) {
    // The hardware way: unit reflection vector → texture matrix → s/q, t/q.
    Rng rng(5);
    for (int i = 0; i < 100000; ++i) {
        glm::vec3 r(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
        if (glm::length(r) < 1e-2f) continue;
        r = glm::normalize(r);
        ParaboloidCoord direct = directionToParaboloid(r);
        glm::vec4 h = paraboloidTextureMatrix(paraboloidSide(r)) * glm::vec4(r, 1.0f);
        ASSERT_GE(h.w, 1.0f - 1e-6f);  // q ≥ 1 on the chosen side: no blow-up
        EXPECT_NEAR(h.x / h.w, direct.s, 2e-7);
        EXPECT_NEAR(h.y / h.w, direct.t, 2e-7);
    }
}

TEST(ParaboloidMapping, DirectSamplerMatchesTheTwoPassHardwareWay) {
    TextureMemory mem(profile(ProfileId::SgiOctaneMxe));
    auto mk = [&](int side) {
        return testing::makeRgba8(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 32, 32, 1, 1, 1},
                                  [&](int, int, int x, int y, int, int) {
                                      return Rgba8{uint8_t(x * 8), uint8_t(y * 8), uint8_t(side * 255), 255};
                                  });
    };
    auto front = mk(0), back = mk(1);
    SamplerState s;
    s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge,
                 AddressMode::ClampToEdge};
    // Through the texture units: texture matrix on set 0, projective divide at the pixel.
    Rng rng(3);
    int compared = 0;
    for (int i = 0; i < 2000; ++i) {
        glm::vec3 r = glm::normalize(glm::vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)));
        ParaboloidSide side = paraboloidSide(r);
        TextureUnits tu;
        tu.setTexture(0, side == ParaboloidSide::Front ? front : back);
        tu.setSampler(0, s);
        StageState st;
        st.colorOp = TextureOp::SelectArg1;
        st.alphaOp = TextureOp::SelectArg1;
        tu.setStage(0, st);
        TexGenState g;
        g.matrixEnabled = true;
        g.matrix = paraboloidTextureMatrix(side);
        g.projected = true;
        tu.setTexGen(0, g);
        VertexEye v{};
        glm::vec4 tc = tu.processVertexTexCoord(0, v, glm::vec4(r, 1.0f));
        FragmentQuad q;
        for (int p = 0; p < 4; ++p) q.texCoord[0][size_t(p)] = tc;  // λ: magnification
        std::array<Rgba8, 4> out;
        tu.shadeQuad(q, out, Path::Reference);
        Rgba8 direct = sampleDualParaboloid(*front, *back, s, r, -(1 << 20));
        // Float rounding of s/q against the direct form can differ by ~1e-7 and flip a
        // sub-texel step; allow one 8-bit step on R and G, exact side (B).
        EXPECT_NEAR(out[0].r, direct.r, 1) << i;
        EXPECT_NEAR(out[0].g, direct.g, 1) << i;
        EXPECT_EQ(out[0].b, direct.b) << i;
        ++compared;
    }
    EXPECT_EQ(compared, 2000);
}

TEST(TexGen, Direct3D7AndOpenGLModes) {
    VertexEye v{};
    v.objectPosition = {1, 2, 3, 1};
    v.eyePosition = {0, 0, -2, 1};
    v.eyeNormal = glm::normalize(glm::vec3(0, 1, 1));
    v.objectNormal = {0, 0, 1};
    TexGenState g;
    glm::vec4 in(0.25f, 0.5f, 0, 1);
    EXPECT_EQ(generateTexCoord(g, v, in), in);
    g.mode = TexGenMode::CameraSpaceNormal;
    EXPECT_EQ(generateTexCoord(g, v, in), glm::vec4(v.eyeNormal, 1));
    g.mode = TexGenMode::CameraSpacePosition;
    EXPECT_EQ(generateTexCoord(g, v, in), glm::vec4(0, 0, -2, 1));
    // u = (0,0,−1), n = (0,1,1)/√2: n·u = −1/√2, r = u + √2·n = (0, 1, 0).
    g.mode = TexGenMode::CameraSpaceReflectionVector;
    glm::vec4 r = generateTexCoord(g, v, in);
    EXPECT_NEAR(r.x, 0, 1e-6);
    EXPECT_NEAR(r.y, 1, 1e-6);
    EXPECT_NEAR(r.z, 0, 1e-6);
    g.mode = TexGenMode::ReflectionMap;
    EXPECT_EQ(generateTexCoord(g, v, in), r);
    // Sphere map of r = (0,1,0): m = 2√2, s = ½, t = 1/(2√2) + ½.
    g.mode = TexGenMode::SphereMap;
    glm::vec4 sm = generateTexCoord(g, v, in);
    EXPECT_NEAR(sm.x, 0.5, 1e-6);
    EXPECT_NEAR(sm.y, 0.5 + 1 / (2 * std::sqrt(2.0)), 1e-6);
    g.mode = TexGenMode::ObjectLinear;
    g.planes[0] = {1, 1, 1, 0};
    EXPECT_EQ(generateTexCoord(g, v, in).x, 6.0f);
    g.mode = TexGenMode::EyeLinear;
    g.planes[0] = {0, 0, -0.5f, 1};
    EXPECT_EQ(generateTexCoord(g, v, in).x, 2.0f);
    // Texture matrix after generation: a projective scale in q.
    g.mode = TexGenMode::PassThru;
    g.matrixEnabled = true;
    g.matrix = glm::mat4(1.0f);
    g.matrix[3][3] = 2.0f;
    EXPECT_EQ(generateTexCoord(g, v, in), glm::vec4(0.25f, 0.5f, 0, 2));
}

}  // namespace
}  // namespace rg::tex
