// The image-space search (demos/tir/tir_search.h) against closed forms: the frustum exit,
// the map coordinates and their inverse, the bisection on an analytic plane converging as
// 004 §3 says (log₂ of the map size), the critical angle; and the scalar twin against the
// SSE lanes bit for bit.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <bit>
#include <cmath>
#include <random>
#include <vector>

#include "raycore/fresnel.h"
#include "tir_search.h"

namespace rg::tir {
namespace {

using raster::Float4;
using raster::Mask4;
using V3 = Vec3L<float>;
using V4 = Vec4L<float>;

// A symmetric 45° frustum, near 0.1, far 10 (glm::perspectiveRH_ZO's terms).
SearchConstants frustum() {
    SearchConstants k;
    const glm::mat4 p = glm::perspectiveRH_ZO(glm::radians(45.0f), 1.0f, 0.1f, 10.0f);
    k.px = p[0][0], k.py = p[1][1], k.pz = p[2][2], k.pw = p[3][2];
    k.invPx = 1.0f / k.px;
    k.invPy = 1.0f / k.py;
    k.far = 10.0f;
    k.invFar = 0.1f;
    return k;
}

// A map of `n`×`n` texels read as the device's point sampling reads it (NEAREST,
// CLAMP_TO_EDGE: texel ⌊c·n⌋ clamped).
struct Map {
    int n = 0;
    std::vector<glm::vec4> texels;
    glm::vec4 at(float u, float v) const {
        auto idx = [this](float c) { return std::clamp(int(std::floor(c * float(n))), 0, n - 1); };
        return texels[size_t(idx(v)) * size_t(n) + size_t(idx(u))];
    }
};

// The plane z = −depth rendered into a map: every texel holds the plane's linear depth and
// its normal (0, 0, 1).
Map planeMap(const SearchConstants& k, int n, float depth) {
    Map m;
    m.n = n;
    m.texels.assign(size_t(n) * size_t(n), glm::vec4(0.0f, 0.0f, 1.0f, depth * k.invFar));
    return m;
}

TEST(TirSearch, FrustumExitIsWhereTheRayLeaves) {
    const SearchConstants k = frustum();
    // Along −z from the eye: the far plane at distance 10.
    const V3 o(0, 0, -1), d(0, 0, -1);
    const Clip<float> s = toClip(k, o), dc = toClipDirection(k, d);
    EXPECT_NEAR(frustumExit(s, dc), 9.0f, 1e-4f);
    // Sideways along +x from (0, 0, −2): the right plane x = z·tan(22.5°) at x = 2·tan 22.5°.
    const V3 o2(0, 0, -2), d2(1, 0, 0);
    const float t = frustumExit(toClip(k, o2), toClipDirection(k, d2));
    EXPECT_NEAR(t, 2.0f * std::tan(glm::radians(22.5f)), 1e-5f);
    // Towards the eye: the near plane at z = −0.1.
    EXPECT_NEAR(frustumExit(toClip(k, V3(0, 0, -3)), toClipDirection(k, V3(0, 0, 1))), 2.9f, 1e-4f);
}

TEST(TirSearch, MapCoordinatesAndUnprojectionAreInverses) {
    const SearchConstants k = frustum();
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> xy(-0.3f, 0.3f), z(-9.0f, -0.5f);
    for (int i = 0; i < 1000; ++i) {
        const V3 p(xy(rng), xy(rng), z(rng));
        const Clip<float> c = toClip(k, p);
        float u, v;
        mapCoords(c.x, c.y, c.w, u, v);
        const V3 back = unproject(k, u, v, c.w * k.invFar);
        EXPECT_NEAR(back.x, p.x, 1e-5f * std::abs(p.z));
        EXPECT_NEAR(back.y, p.y, 1e-5f * std::abs(p.z));
        EXPECT_NEAR(back.z, p.z, 1e-5f * std::abs(p.z));
    }
    // Row 0 is the top of the image: a point above the axis has v < ½.
    float u, v;
    const Clip<float> up = toClip(k, V3(0, 1, -5));
    mapCoords(up.x, up.y, up.w, u, v);
    EXPECT_LT(v, 0.5f);
    EXPECT_FLOAT_EQ(u, 0.5f);
}

// 004 §3: "The binary search converges on an intersection between the ray and a depth map
// value in no more than log₂ dim steps". On a plane the candidate lies on the plane, and
// after i steps the ray parameter is known to 2⁻ⁱ of the segment.
TEST(TirSearch, BisectionOnAPlaneConvergesWithEachStep) {
    const SearchConstants k = frustum();
    const float planeDepth = 6.0f;
    const Map map = planeMap(k, 512, planeDepth);
    auto fetch = [&](float u, float v, bool) {
        const glm::vec4 t = map.at(u, v);
        return V4(t.x, t.y, t.z, t.w);
    };
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> jitter(-0.3f, 0.3f);
    for (int trial = 0; trial < 200; ++trial) {
        const V3 o(jitter(rng), jitter(rng), -2.0f);
        const V3 d = normalize3(V3(jitter(rng) * 0.5f, jitter(rng) * 0.5f, -1.0f));
        const Clip<float> s = toClip(k, o), dc = toClipDirection(k, d);
        const float tEnd = frustumExit(s, dc);
        const Clip<float> e{s.x + dc.x * tEnd, s.y + dc.y * tEnd, s.z + dc.z * tEnd, s.w + dc.w * tEnd};
        // The exact crossing of the ray with z = −planeDepth.
        const float tTrue = (planeDepth - 2.0f) / -d.z;
        const V3 truth = o + d * tTrue;
        float previous = 1e30f;
        for (int iterations : {2, 4, 6, 8, 10}) {
            const Probe<float> p = binarySearch(k, s, e, iterations, true, fetch);
            const V3 c = unproject(k, p.u, p.v, p.texel.w);
            EXPECT_NEAR(c.z, -planeDepth, 1e-4f);  // the candidate lies on the stored surface
            // The last midpoint is within 2⁻ⁱ of the segment of the crossing, so its
            // projection onto the plane is too (the plane is a level set of w).
            const float segment = glm::length(glm::vec3(d.x, d.y, d.z)) * tEnd;
            const float err = std::hypot(c.x - truth.x, c.y - truth.y);
            EXPECT_LE(err, segment * std::ldexp(1.0f, -iterations) + 1e-3f)
                << "trial " << trial << " iterations " << iterations;
            if (iterations >= 4) EXPECT_LE(err, previous + 1e-3f);
            previous = err;
        }
    }
}

// Figure 4: total internal reflection exactly when sin θ_i > η_t/η_i, and otherwise the
// direction raycore's refractDir gives.
TEST(TirOptics, CriticalAngleAndSnell) {
    const float eta = 1.5f;
    const double critical = std::asin(1.0 / eta);  // 41.81°
    EXPECT_NEAR(critical * 180.0 / 3.14159265358979323846, 41.81, 0.01);
    const V3 n(0, 0, 1);
    for (int i = 0; i <= 900; ++i) {
        const double theta = (double(i) / 10.0) * 3.14159265358979323846 / 180.0;
        const V3 d(float(std::sin(theta)), 0.0f, -float(std::cos(theta)));
        bool tir = false;
        const V3 t = refractOrReflect(d, n, eta, tir);
        const double s = std::sin(theta) * eta;
        if (std::abs(s - 1.0) > 1e-5) EXPECT_EQ(tir, s > 1.0) << "θ = " << i / 10.0 << "°";
        glm::vec3 ref;
        const bool refracts = ray::refractDir({d.x, d.y, d.z}, {n.x, n.y, n.z}, eta, &ref);
        EXPECT_EQ(refracts, !tir);
        if (refracts) {
            EXPECT_NEAR(t.x, ref.x, 1e-6f);
            EXPECT_NEAR(t.z, ref.z, 1e-6f);
        } else {
            EXPECT_FLOAT_EQ(t.x, d.x);  // the mirror direction keeps the tangent part…
            EXPECT_NEAR(t.z, -d.z, 1e-6f);  // … and turns the normal part
        }
    }
}

// The scalar twin and the SSE lanes: the same search, bit for bit, over random rays
// through random maps (random normals and depths, empty texels among them).
TEST(TirSearch, ScalarTwinEqualsLanesBitForBit) {
    SearchConstants k = frustum();
    k.eta = 1.5f;
    k.epsilon = 1e-3f;
    k.cosMiss = 0.9f;
    k.minDistance2 = 4e-6f;
    k.bounces = 4;
    k.frontAndBack = 1;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> unit(-1.0f, 1.0f), depth(0.3f, 0.7f);
    auto randomMap = [&](int n) {
        Map m;
        m.n = n;
        for (int i = 0; i < n * n; ++i) {
            const glm::vec3 nn = glm::normalize(glm::vec3(unit(rng), unit(rng), unit(rng)) + glm::vec3(0, 0, 0.01f));
            const float d = (rng() % 7 == 0) ? 1.0f : depth(rng);
            m.texels.push_back(glm::vec4(nn, d));
        }
        return m;
    };
    const Map back = randomMap(64), front = randomMap(64);
    auto scalarFetch = [](const Map& m) {
        return [&m](float u, float v, bool live) {
            const glm::vec4 t = live ? m.at(u, v) : glm::vec4(0.0f);
            return V4(t.x, t.y, t.z, t.w);
        };
    };
    auto laneFetch = [](const Map& m) {
        return [&m](const Float4& u, const Float4& v, const Mask4& live) {
            std::array<glm::vec4, 4> t{};
            for (int i = 0; i < 4; ++i)
                if ((live.bits() >> i) & 1u) t[size_t(i)] = m.at(u[i], v[i]);
            return Vec4L<Float4>::fromLanes(t);
        };
    };
    auto bits = [](float f) { return std::bit_cast<uint32_t>(f); };
    int differing = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        std::array<V3, 4> p, n;
        for (int i = 0; i < 4; ++i) {
            p[size_t(i)] = V3(unit(rng) * 0.5f, unit(rng) * 0.5f, -3.0f + unit(rng));
            n[size_t(i)] = V3(unit(rng), unit(rng), 1.0f);
        }
        const uint32_t liveBits = 1u + rng() % 15u;
        auto lanes = [&](auto get) { return Float4::lanes(get(0), get(1), get(2), get(3)); };
        const Vec3L<Float4> pl(lanes([&](int i) { return p[size_t(i)].x; }), lanes([&](int i) { return p[size_t(i)].y; }),
                               lanes([&](int i) { return p[size_t(i)].z; }));
        const Vec3L<Float4> nl(lanes([&](int i) { return n[size_t(i)].x; }), lanes([&](int i) { return n[size_t(i)].y; }),
                               lanes([&](int i) { return n[size_t(i)].z; }));
        const PathState<Float4, Mask4> st =
            traceInside<Float4, Mask4>(k, pl, nl, Mask4::fromBits(liveBits), laneFetch(back), laneFetch(front));
        for (int i = 0; i < 4; ++i) {
            if (!((liveBits >> i) & 1u)) continue;
            const PathState<float, bool> ss =
                traceInside<float, bool>(k, p[size_t(i)], n[size_t(i)], true, scalarFetch(back), scalarFetch(front));
            const bool same = bits(ss.origin.x) == bits(st.origin.x[i]) && bits(ss.origin.y) == bits(st.origin.y[i]) &&
                              bits(ss.origin.z) == bits(st.origin.z[i]) && bits(ss.dir.x) == bits(st.dir.x[i]) &&
                              bits(ss.dir.y) == bits(st.dir.y[i]) && bits(ss.dir.z) == bits(st.dir.z[i]) &&
                              ss.segments == st.segments[i] && ss.reflections == st.reflections[i];
            differing += same ? 0 : 1;
        }
    }
    EXPECT_EQ(differing, 0);
}

TEST(TirSearch, CgArcCosineIsWithinItsPublishedError) {
    for (int i = -1000; i <= 1000; ++i) {
        const float x = float(i) / 1000.0f;
        EXPECT_NEAR(acosCg(x), std::acos(double(x)), 7e-5) << x;
    }
}

}  // namespace
}  // namespace rg::tir
