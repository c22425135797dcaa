// Spec oracles (issue 24 item 1): values computed here from the rules docs/hardware.md
// writes down — in double or by hand, never by calling the code under test — at points
// where a plausible misreading gives another answer: λ where the floor of ½·log2 ρ² and its
// rounding differ, LOD bias/min/max not exact in the 8 fraction bits, every texgen mode at
// points with r_z ≠ 0 and all of s, t, r, q, paraboloid maps front and back over many
// directions.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "texunit/paraboloid_mapping.h"
#include "texunit/sampler.h"
#include "texunit/texgen.h"
#include "texunit/texture_units.h"

namespace rg::tex {
namespace {

// ---- level of detail ("Level of detail", steps 1–3) -------------------------------------

// The quad whose pixel 1 is (du, dv) texels from pixel 0 and whose pixel 2 is (eu, ev).
std::array<glm::vec4, 4> quad(float du, float dv, float eu, float ev, int size) {
    const float n = float(size);
    return {glm::vec4(0.25f, 0.25f, 0, 1), glm::vec4(0.25f + du / n, 0.25f + dv / n, 0, 1),
            glm::vec4(0.25f + eu / n, 0.25f + ev / n, 0, 1), glm::vec4(0.25f, 0.25f, 0, 1)};
}

// log2approx(x) for x = 2^e·(1 + f), 0 ≤ f < 1: e + f (the doc's "float bits read as fixed
// point"), here from frexp, then λ = ⌊⌊256·log2approx(ρ²)⌋ / 2⌋.
int32_t lambdaOracle(double rho2) {
    int e2 = 0;
    const double m = std::frexp(rho2, &e2);  // rho2 = m·2^e2, m in [0.5, 1)
    const double log2approx = double(e2 - 1) + (2.0 * m - 1.0);
    const int64_t l = int64_t(std::floor(256.0 * log2approx));
    return int32_t(l >= 0 ? l / 2 : -((-l + 1) / 2));  // floor(l / 2)
}

TEST(SpecOracleLod, LambdaFloorsOddFixedPointLogsAndNonPowerOfTwoDerivatives) {
    const std::array<int, 4> size{64, 64, 1, 1};
    struct Case {
        float du, dv, eu, ev;
        double rho2;      // by hand
        int32_t lambda;   // by hand: ⌊128·(e + f)⌋
    } cases[] = {
        // ρ² = 1 + 1/256: log2approx·256 = 1, odd; ½ of it floors to 0 (rounding gives 1).
        {1.0f, 1.0f / 16, 0, 0, 1.00390625, 0},
        // ρ² = 2: e = 1, f = 0 → 256 → 128.
        {1.0f, 1.0f, 0, 0, 2.0, 128},
        // 3 texels: ρ² = 9 = 2³·1.125 → 256·3.125 = 800 → 400 (true log2 3 = 1.585 → 405.7).
        {3.0f, 0, 0, 0, 9.0, 400},
        // 5 texels along y: ρ² = 25 = 2⁴·1.5625 → 256·4.5625 = 1168 → 584.
        {0, 0, 5.0f, 0, 25.0, 584},
        // (3, 4) along x gives 25, (6, 0) along y 36: the larger, 36 = 2⁵·1.125 → 1312 → 656.
        {3.0f, 4.0f, 6.0f, 0, 36.0, 656},
        // Minification past one texel per pixel: ρ² = 2⁻⁴ → −1024 → −512.
        {0.25f, 0.0f, 0.125f, 0.0f, 0.0625, -512},
    };
    for (const Case& c : cases) {
        const double dx2 = double(c.du) * c.du + double(c.dv) * c.dv, dy2 = double(c.eu) * c.eu + double(c.ev) * c.ev;
        ASSERT_EQ(std::max(dx2, dy2), c.rho2) << "the case's hand ρ² is wrong";
        EXPECT_EQ(lambdaOracle(c.rho2), c.lambda) << "the oracle disagrees with the hand value at ρ² = " << c.rho2;
        EXPECT_EQ(quadLambda(quad(c.du, c.dv, c.eu, c.ev, 64), size, 2), c.lambda) << "ρ² = " << c.rho2;
    }
    // Many exact ρ² with odd fixed-point logs: the floor, never the round.
    int odd = 0;
    for (int k = 1; k < 200; ++k) {
        const float du = 1.0f, dv = float(k) / 64.0f;  // ρ² = 1 + k²/4096, exact in float
        const double rho2 = 1.0 + double(k) * k / 4096.0;
        const int32_t want = lambdaOracle(rho2);
        odd += (int64_t(std::floor(256.0 * (rho2 < 2 ? rho2 - 1 : 0))) & 1) ? 1 : 0;
        EXPECT_EQ(quadLambda(quad(du, dv, 0, 0, 64), size, 2), want) << "k = " << k;
    }
    EXPECT_GT(odd, 20);  // the sweep does cross odd fixed-point logs
}

// λ' = clamp(λ + round(bias·256), round(MIN_LOD·256), round(MAX_LOD·256)), rounding halves
// up (⌊x·256 + ½⌋), at values whose ·256 has a fraction ≥ ½ (where floor differs).
TEST(SpecOracleLod, BiasMinAndMaxRoundToTheNearestFixedPointStep) {
    SamplerState s;
    s.lodBias = 0.3f;  // 76.8000003 → 77 (floor: 76)
    s.minLod = -1000.0f;
    s.maxLod = 1000.0f;
    EXPECT_EQ(biasAndClampLambda(100, s), 177);
    s.lodBias = -0.3f;  // −76.8 → ⌊−76.3⌋ = −77
    EXPECT_EQ(biasAndClampLambda(100, s), 23);
    s.lodBias = 0.0f;
    s.minLod = 1.3f;  // 332.8000061 → 333
    EXPECT_EQ(biasAndClampLambda(0, s), 333);
    s.minLod = -1000.0f;
    s.maxLod = 2.71f;  // 693.76 → 694
    EXPECT_EQ(biasAndClampLambda(5000, s), 694);
    // Bias then clamp, in that order: 300 + 77 = 377 clamps to MAX_LOD 1.25 → 320.
    s.lodBias = 0.3f;
    s.maxLod = 1.25f;
    EXPECT_EQ(biasAndClampLambda(300, s), 320);
}

// ---- coordinate generation ("Coordinate generation") ----------------------------------

struct Point {
    glm::dvec4 object, eye;
    glm::dvec3 normal;  // unit, eye space
};

TEST(SpecOracleTexgen, EveryModeAtPointsWithRzNonZeroAndAllFourComponents) {
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const std::array<glm::vec4, 4> planes{glm::vec4(0.5f, -0.25f, 2.0f, 1.5f), glm::vec4(-1.0f, 0.75f, 0.125f, -0.5f),
                                          glm::vec4(0.25f, 0.25f, -1.0f, 3.0f), glm::vec4(1.0f, 2.0f, 0.5f, -1.0f)};
    for (int i = 0; i < 200; ++i) {
        Point p;
        p.object = {u(rng) * 3, u(rng) * 3, u(rng) * 3, 1.0};
        p.eye = {u(rng) * 2, u(rng) * 2, -2.0 - std::abs(u(rng)) * 5, 1.0};
        glm::dvec3 n(u(rng), u(rng), u(rng) + 1.5);  // mostly facing the eye, r_z ≠ 0
        p.normal = n / std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
        VertexEye v;
        v.objectPosition = glm::vec4(p.object);
        v.eyePosition = glm::vec4(p.eye);
        v.eyeNormal = glm::vec3(p.normal);
        // The same inputs as floats, for the oracle's double arithmetic.
        const glm::dvec4 po(v.objectPosition), pe(v.eyePosition);
        const glm::dvec3 nn(v.eyeNormal);
        // u = p_eye/|p_eye|, r = u − 2(n·u)n.
        const glm::dvec3 pe3(pe);
        const glm::dvec3 unit = pe3 / std::sqrt(pe3.x * pe3.x + pe3.y * pe3.y + pe3.z * pe3.z);
        const double nu = nn.x * unit.x + nn.y * unit.y + nn.z * unit.z;
        const glm::dvec3 r = unit - 2.0 * nu * nn;
        ASSERT_GT(std::abs(r.z), 1e-3);
        const glm::vec4 in(9, 8, 7, 6);
        auto gen = [&](TexGenMode mode) {
            TexGenState g;
            g.mode = mode;
            g.planes = planes;
            return glm::dvec4(generateTexCoord(g, v, in));
        };
        auto expectNear = [&](glm::dvec4 got, glm::dvec4 want, double tol, const char* what) {
            for (int c = 0; c < 4; ++c) EXPECT_NEAR(got[c], want[c], tol) << what << " component " << c << " point " << i;
        };
        expectNear(gen(TexGenMode::PassThru), glm::dvec4(in), 0, "pass-through");
        expectNear(gen(TexGenMode::CameraSpaceNormal), glm::dvec4(nn, 1), 0, "camera-space normal");
        expectNear(gen(TexGenMode::NormalMap), glm::dvec4(nn, 1), 0, "normal map");
        expectNear(gen(TexGenMode::CameraSpacePosition), glm::dvec4(pe3, 1), 0, "camera-space position");
        expectNear(gen(TexGenMode::CameraSpaceReflectionVector), glm::dvec4(r, 1), 2e-6, "reflection vector");
        expectNear(gen(TexGenMode::ReflectionMap), glm::dvec4(r, 1), 2e-6, "reflection map");
        glm::dvec4 obj, eyeLin;
        for (int k = 0; k < 4; ++k) {
            const glm::dvec4 pl(planes[size_t(k)]);
            obj[k] = pl.x * po.x + pl.y * po.y + pl.z * po.z + pl.w * po.w;  // w as submitted
            eyeLin[k] = pl.x * pe.x + pl.y * pe.y + pl.z * pe.z + pl.w * pe.w;
        }
        expectNear(gen(TexGenMode::ObjectLinear), obj, 2e-5, "object linear");
        expectNear(gen(TexGenMode::EyeLinear), eyeLin, 2e-5, "eye linear");
        // Sphere map: m = 2√(rx² + ry² + (rz + 1)²), s = rx/m + ½, t = ry/m + ½; r = 0, q = 1.
        const double m = 2.0 * std::sqrt(r.x * r.x + r.y * r.y + (r.z + 1.0) * (r.z + 1.0));
        expectNear(gen(TexGenMode::SphereMap), glm::dvec4(r.x / m + 0.5, r.y / m + 0.5, 0, 1), 2e-6, "sphere map");
        // The texture matrix after generation: M·(s, t, r, q).
        TexGenState g;
        g.mode = TexGenMode::EyeLinear;
        g.planes = planes;
        g.matrixEnabled = true;
        g.matrix = glm::mat4(glm::vec4(1, 0.5f, 0, 0), glm::vec4(0, 2, 0, 0.25f), glm::vec4(0.5f, 0, 1, 0),
                             glm::vec4(0, 0, 0.75f, 1));  // columns
        const glm::dvec4 viaMatrix(generateTexCoord(g, v, in));
        glm::dvec4 want(0.0);
        for (int row = 0; row < 4; ++row)
            for (int col = 0; col < 4; ++col) want[row] += double(g.matrix[col][row]) * eyeLin[col];
        expectNear(viaMatrix, want, 1e-4, "texture matrix");
    }
}

// ---- paraboloid maps ("Paraboloid mapping") --------------------------------------------

TEST(SpecOracleParaboloid, FrontAndBackOverManyDirectionsAgainstTheClosedForm) {
    std::mt19937 rng(5);
    std::normal_distribution<double> g(0.0, 1.0);
    int front = 0, back = 0;
    for (int i = 0; i < 5000; ++i) {
        glm::dvec3 v(g(rng), g(rng), g(rng));
        v /= std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
        const glm::vec3 vf(v);
        const glm::dvec3 w(vf);  // the float direction, renormalised in double
        const glm::dvec3 un = w / std::sqrt(w.x * w.x + w.y * w.y + w.z * w.z);
        const bool isFront = vf.z >= 0.0f;
        const double denom = isFront ? 1.0 + un.z : 1.0 - un.z;
        const double s = (un.x / denom + 1.0) / 2.0, t = (un.y / denom + 1.0) / 2.0;
        const ParaboloidCoord c = directionToParaboloid(vf);
        EXPECT_EQ(c.side, isFront ? ParaboloidSide::Front : ParaboloidSide::Back) << i;
        EXPECT_NEAR(c.s, s, 2e-6) << "direction " << i;
        EXPECT_NEAR(c.t, t, 2e-6) << "direction " << i;
        // The hardware way: the texture matrix on (r, 1), then the q divide.
        const glm::vec4 h = paraboloidTextureMatrix(c.side) * glm::vec4(glm::vec3(un), 1.0f);
        EXPECT_NEAR(h.x / h.w, s, 5e-6) << i;
        EXPECT_NEAR(h.y / h.w, t, 5e-6) << i;
        // The inverse: v = (2x, 2y, ±(1 − x² − y²))/(1 + x² + y²) with x = 2s − 1, y = 2t − 1.
        const double x = 2 * s - 1, y = 2 * t - 1, q = 1 + x * x + y * y;
        const glm::dvec3 back3(2 * x / q, 2 * y / q, (isFront ? 1 : -1) * (1 - x * x - y * y) / q);
        const glm::vec3 inv = paraboloidToDirection(c.side, float(s), float(t));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(inv[k], back3[k], 3e-6) << i;
        (isFront ? front : back)++;
    }
    EXPECT_GT(front, 2000);
    EXPECT_GT(back, 2000);
}

}  // namespace
}  // namespace rg::tex
