// Fresnel oracles: normal incidence, grazing, total internal reflection, Snell's law, and
// Schlick against the exact equations.
#include <gtest/gtest.h>

#include <cmath>

#include "raycore/fresnel.h"
#include "raycore/material.h"

namespace rg::ray {
namespace {

TEST(Fresnel, ExactAtNormalIncidenceIsSquaredRatio) {
    for (float n : {1.33f, 1.5f, 1.7f, 2.4f}) {
        const float expected = ((n - 1) / (n + 1)) * ((n - 1) / (n + 1));
        EXPECT_NEAR(FresnelDielectric(1.0f, 1.0f, n), expected, 1e-6f) << "n=" << n;
        // The same from inside the glass: reciprocity.
        EXPECT_NEAR(FresnelDielectric(1.0f, n, 1.0f), expected, 1e-6f) << "n=" << n;
        EXPECT_FLOAT_EQ(FresnelNormalIncidence(n), expected);
    }
    EXPECT_NEAR(FresnelDielectric(1.0f, 1.0f, 1.5f), 0.04f, 1e-6f);
}

// The exact unpolarized reflectance against the Fresnel equations (Hecht, Optics §4.6) at
// tabulated points — glass n = 1.5 from air: 45° gives R_s = 0.0920, R_p = 0.00846, R =
// 0.0502; Brewster's angle atan 1.5 = 56.31° gives R_p = 0, R = R_s/2 = 0.0740; water n =
// 1.333 at 60°: sin θt = 0.6497, r_s = −0.3392, r_p = 0.0657, R = 0.0597 — and at every degree against the equations in double.
TEST(Fresnel, ExactReflectanceAtTabulatedAnglesAndIndices) {
    auto fresnel = [](double cosI, double n1, double n2) {
        const double sinT = n1 / n2 * std::sqrt(std::max(0.0, 1 - cosI * cosI));
        if (sinT >= 1) return 1.0;
        const double cosT = std::sqrt(1 - sinT * sinT);
        const double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
        const double rp = (n1 * cosT - n2 * cosI) / (n1 * cosT + n2 * cosI);
        return 0.5 * (rs * rs + rp * rp);
    };
    const double deg = 3.14159265358979323846 / 180.0;
    EXPECT_NEAR(FresnelDielectric(float(std::cos(45 * deg)), 1.0f, 1.5f), 0.0502, 1e-4);
    EXPECT_NEAR(FresnelDielectric(float(std::cos(std::atan(1.5))), 1.0f, 1.5f), 0.0740, 1e-4);
    EXPECT_NEAR(FresnelDielectric(float(std::cos(60 * deg)), 1.0f, 1.333f), 0.0597, 1e-4);
    for (double n : {1.2, 1.333, 1.5, 1.7, 2.42})
        for (int a = 0; a <= 90; ++a) {
            const float cosI = float(std::cos(a * deg));
            EXPECT_NEAR(FresnelDielectric(cosI, 1.0f, float(n)), fresnel(cosI, 1.0, float(n)), 2e-6)
                << "n " << n << " at " << a << "° from air";
            EXPECT_NEAR(FresnelDielectric(cosI, float(n), 1.0f), fresnel(cosI, float(n), 1.0), 2e-6)
                << "n " << n << " at " << a << "° from inside";
        }
}

TEST(Fresnel, GrazingIncidenceReflectsEverything) {
    EXPECT_NEAR(FresnelDielectric(0.0f, 1.0f, 1.5f), 1.0f, 1e-6f);
    EXPECT_FLOAT_EQ(FresnelSchlick(0.0f, 0.04f), 1.0f);
}

TEST(Fresnel, TotalInternalReflectionPastTheCriticalAngle) {
    const float critical = std::asin(1.0f / 1.5f);  // 41.8°
    for (float deg : {42.5f, 45.0f, 60.0f, 89.0f}) {
        float theta = deg * 3.14159265f / 180.0f;
        ASSERT_GT(theta, critical);
        EXPECT_EQ(FresnelDielectric(std::cos(theta), 1.5f, 1.0f), 1.0f) << deg << "°";
        glm::vec3 d(std::sin(theta), -std::cos(theta), 0.0f), t;
        EXPECT_FALSE(refractDir(d, {0, 1, 0}, 1.5f, &t)) << deg << "°";
    }
    // Just inside the critical angle light still leaves, but the reflectance has risen
    // far above its normal-incidence 4%.
    float theta = critical - 0.01f;
    float F = FresnelDielectric(std::cos(theta), 1.5f, 1.0f);
    EXPECT_LT(F, 1.0f);
    EXPECT_GT(F, 0.3f);
}

TEST(Fresnel, RefractionObeysSnell) {
    for (float deg : {0.0f, 10.0f, 30.0f, 60.0f, 85.0f}) {
        float theta = deg * 3.14159265f / 180.0f;
        glm::vec3 d(std::sin(theta), -std::cos(theta), 0.0f), t;
        ASSERT_TRUE(refractDir(d, {0, 1, 0}, 1.0f / 1.5f, &t));
        EXPECT_NEAR(glm::length(t), 1.0f, 1e-6f);
        EXPECT_NEAR(1.0f * std::sin(theta), 1.5f * t.x, 1e-5f) << deg << "°";
        EXPECT_LT(t.y, 0.0f);
    }
}

TEST(Fresnel, SchlickAgreesWithExactAtTheEndsAndStaysClose) {
    const float n = 1.5f, F0 = FresnelNormalIncidence(n);
    EXPECT_NEAR(FresnelSchlick(1.0f, F0), FresnelDielectric(1.0f, 1.0f, n), 1e-6f);
    EXPECT_NEAR(FresnelSchlick(0.0f, F0), FresnelDielectric(0.0f, 1.0f, n), 1e-6f);
    float worst = 0.0f;
    for (int i = 0; i <= 1000; ++i) {
        float c = float(i) / 1000.0f;
        worst = std::max(worst, std::abs(FresnelSchlick(c, F0) - FresnelDielectric(c, 1.0f, n)));
        // Both increase towards grazing.
        if (i > 0) {
            EXPECT_LE(FresnelSchlick(c, F0), FresnelSchlick(c - 0.001f, F0) + 1e-6f);
        }
    }
    // Schlick's approximation for glass is known to stay within a few percent of the exact
    // reflectance (its largest gap is near 80° incidence).
    EXPECT_LT(worst, 0.05f);
    EXPECT_GT(worst, 0.0f);
}

TEST(Fresnel, ReflectionIsAMirror) {
    glm::vec3 d = glm::normalize(glm::vec3(1, -1, 0));
    glm::vec3 r = reflectDir(d, {0, 1, 0});
    EXPECT_NEAR(r.x, d.x, 1e-7f);
    EXPECT_NEAR(r.y, -d.y, 1e-7f);
}

TEST(Material, TransparencyAttenuationIsPowerOfThickness) {
    glm::vec3 g = transparencyAttenuation({0.5f, 0.9f, 1.0f}, 2.0f);
    EXPECT_NEAR(g.x, 0.25f, 1e-6f);
    EXPECT_NEAR(g.y, 0.81f, 1e-6f);
    EXPECT_NEAR(g.z, 1.0f, 1e-6f);
    Material m;
    m.type = MaterialType::Mirror;
    m.reflectance = glm::vec3(0.3f);
    m.fresnel = MirrorFresnel::Constant;
    EXPECT_EQ(mirrorReflectance(m, 0.2f), glm::vec3(0.3f));
    m.fresnel = MirrorFresnel::Schlick;
    EXPECT_NEAR(mirrorReflectance(m, 1.0f).x, 0.3f, 1e-6f);
    EXPECT_GT(mirrorReflectance(m, 0.2f).x, 0.3f);
}

}  // namespace
}  // namespace rg::ray
