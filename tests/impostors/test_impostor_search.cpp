// The searches of demos/impostors/impostor_search.h against closed forms: Figure 1's ratio,
// the secant search converging on an analytic sphere's distance map, the search from outside
// with its validity test (Figure 4), the refraction against raycore's; and the scalar twin
// against the SSE lanes and the quad groups bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "impostor_search_linear.h"
#include "impostor_shading.h"
#include "raycore/fresnel.h"
#include "reproduce_impostors.h"
#include "texunit/cube_mapping.h"

namespace rg::impostors {
namespace {

using raster::Float4;
using raster::FloatQ;
using raster::Mask4;
using raster::MaskQ;
using V3 = Vec3L<float>;
using V4 = Vec4L<float>;

// A sphere of radius `radius` centred at `centre`, seen from the origin (inside it), as a
// point-sampled distance cube map of n² texels a face: each texel the distance to the
// sphere along its centre's direction, and the sphere's outward normal there.
struct SphereMap {
    glm::vec3 centre;
    float radius;
    int n;
    std::vector<glm::vec4> texels;
    // Distance from o along unit d to the sphere (from inside: the far root).
    float hit(glm::vec3 o, glm::vec3 d) const {
        const glm::vec3 oc = o - centre;
        const float b = glm::dot(oc, d), c = glm::dot(oc, oc) - radius * radius;
        const float disc = b * b - c;
        if (disc < 0) return -1.0f;
        const float s = std::sqrt(disc);
        return -b - s > 1e-6f ? -b - s : -b + s;
    }
    SphereMap(glm::vec3 c, float r, int size) : centre(c), radius(r), n(size), texels(size_t(6) * size_t(size) * size_t(size)) {
        for (int f = 0; f < 6; ++f)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const glm::vec3 d = glm::normalize(
                        tex::cubeFaceDirection(tex::CubeFace(f), (float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n)));
                    const float t = hit(glm::vec3(0.0f), d);
                    const glm::vec3 nrm = glm::normalize(d * t - centre);
                    texels[(size_t(f) * size_t(n) + size_t(y)) * size_t(n) + size_t(x)] = glm::vec4(nrm, t);
                }
    }
    // The device's point sampling (NearestFloat2D::fetchCube).
    glm::vec4 fetch(glm::vec3 d) const {
        const tex::CubeCoord c = tex::selectCubeFace(d);
        auto texel = [&](float v) {
            float u = v * float(n);
            if (!(u == u)) u = 0.0f;
            return std::clamp(int(std::floor(std::clamp(u, -4194304.0f, 4194304.0f))), 0, n - 1);
        };
        return texels[(size_t(int(c.face)) * size_t(n) + size_t(texel(c.t))) * size_t(n) + size_t(texel(c.s))] + glm::vec4(0.0f);
    }
};

// The fetch as each lane type calls it: lanes outside `live` read zero.
struct Fetch {
    const SphereMap* map;
    int* count;
    V4 operator()(const V3& d, bool live) const {
        if (!live) return V4(0.0f, 0.0f, 0.0f, 0.0f);
        ++*count;
        const glm::vec4 t = map->fetch(glm::vec3(d.x, d.y, d.z));
        return V4(t.x, t.y, t.z, t.w);
    }
    Vec4L<Float4> operator()(const Vec3L<Float4>& d, const Mask4& live) const {
        std::array<glm::vec4, 4> t{};
        for (int i = 0; i < 4; ++i)
            if ((live.bits() >> i) & 1u) {
                ++*count;
                t[size_t(i)] = map->fetch(glm::vec3(d.x[i], d.y[i], d.z[i]));
            }
        return Vec4L<Float4>::fromLanes(t);
    }
    template <int N>
    Vec4L<FloatQ<N>> operator()(const Vec3L<FloatQ<N>>& d, const MaskQ<N>& live) const {
        Vec4L<FloatQ<N>> r;
        for (int q = 0; q < N; ++q)
            r.setQuad(q, (*this)(Vec3L<Float4>(d.x.quad(q), d.y.quad(q), d.z.quad(q)), live.quad(q)));
        return r;
    }
};

bool sameBits(float a, float b) { return std::memcmp(&a, &b, 4) == 0; }

// Figure 1: |y|/|y'| is 1 at the hit, below 1 in front of the surface (an undershoot),
// above behind it (an overshoot).
TEST(ImpostorSearch, Figure1RatioTellsUndershootFromOvershoot) {
    const SphereMap m({0.3f, -0.2f, 0.1f}, 2.0f, 256);
    std::mt19937 rng(1);
    std::normal_distribution<float> g;
    for (int i = 0; i < 200; ++i) {
        const glm::vec3 d = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        const float stored = m.fetch(d).w;
        const V3 at(d.x * stored, d.y * stored, d.z * stored);
        EXPECT_FLOAT_EQ(distanceRatio(at, stored), 1.0f);
        EXPECT_LT(distanceRatio(at * 0.9f, stored), 1.0f);  // undershoot
        EXPECT_GT(distanceRatio(at * 1.1f, stored), 1.0f);  // overshoot
    }
}

// Figure 2: from points near the reference point, the search converges to the sphere's hit:
// after p and l within a few % of the distance, after 8 iterations within the map's texel
// (the point-sampled map is a staircase of ½ texel), and the error falls.
TEST(ImpostorSearch, SecantSearchConvergesOnAnAnalyticSphere) {
    const int n = 512;
    const SphereMap m({0.4f, 0.1f, -0.3f}, 2.5f, n);
    std::mt19937 rng(2);
    std::normal_distribution<float> g;
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    double err0 = 0, err8 = 0, worst8 = 0;
    const int rays = 500;
    int count = 0;
    const Fetch fetch{&m, &count};
    for (int i = 0; i < rays; ++i) {
        const glm::vec3 o = glm::normalize(glm::vec3(g(rng), g(rng), g(rng))) * (0.8f * u(rng));
        const glm::vec3 d = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        const float truth = m.hit(o, d);
        const V3 x(o.x, o.y, o.z), R(d.x, d.y, d.z);
        const SearchResult<float, bool> s0 = secantSearch(x, R, 0, true, fetch);
        const SearchResult<float, bool> s8 = secantSearch(x, R, 8, true, fetch);
        err0 += std::fabs(s0.d - truth);
        err8 += std::fabs(s8.d - truth);
        worst8 = std::max(worst8, double(std::fabs(s8.d - truth)));
    }
    err0 /= rays;
    err8 /= rays;
    const double texel = 2.5 * 2.0 / n;  // a texel at the sphere's distance, roughly
    EXPECT_LT(err8, 0.5 * err0) << "iterations must refine the first guesses";
    EXPECT_LT(err8, texel) << "mean error after 8 iterations";
    EXPECT_LT(worst8, 8 * texel);
    EXPECT_LT(err0, 0.05 * 2.5);
}

// A refracted ray starts on the refractor's surface (Figure 3): x is a root itself (ratio 1),
// so an unseeded search that "uses x" stops at d ≈ 0; seeded with the ray's point nearest
// the centre, it finds the far side, the exit, within a texel.
TEST(ImpostorSearch, ARayFromTheSurfaceFindsItsExitOnlySeeded) {
    const int n = 128;
    const float radius = 1.0f;
    const SphereMap m({0.0f, 0.0f, 0.0f}, radius, n);
    std::mt19937 rng(5);
    std::normal_distribution<float> g;
    const double texel = 2.0 * radius / n;
    double seededErr = 0, plainErr = 0;
    const int rays = 400;
    int count = 0;
    const Fetch fetch{&m, &count};
    for (int i = 0; i < rays; ++i) {
        const glm::vec3 nrm = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        glm::vec3 d = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        if (glm::dot(d, nrm) > -0.2f) d = glm::normalize(d - nrm * (glm::dot(d, nrm) + 0.6f));  // inwards
        const glm::vec3 o = nrm * radius;
        const float truth = -2.0f * glm::dot(o, d);  // the chord
        const V3 x(o.x, o.y, o.z), R(d.x, d.y, d.z);
        seededErr += std::fabs(secantSearch(x, R, 8, true, fetch, /*seeded=*/true).d - truth);
        plainErr += std::fabs(secantSearch(x, R, 8, true, fetch).d - truth);
    }
    seededErr /= rays;
    plainErr /= rays;
    EXPECT_LT(seededErr, texel) << "seeded: mean error of the exit";
    EXPECT_GT(plainErr, 0.25 * radius) << "unseeded: the entry itself is taken for the root";
}

// The fetch count: r, p, l and one per iteration (plus x's own ratio, once, where no
// undershoot was seen by the first iteration); from outside, one more (the seed).
TEST(ImpostorSearch, ReadsThreeTexelsPlusOnePerIteration) {
    const SphereMap m({0.0f, 0.0f, 0.0f}, 2.0f, 64);
    std::mt19937 rng(9);
    std::normal_distribution<float> g;
    for (int i = 0; i < 50; ++i) {
        const glm::vec3 o = glm::normalize(glm::vec3(g(rng), g(rng), g(rng))) * 0.5f;
        const glm::vec3 d = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        const V3 x(o.x, o.y, o.z), R(d.x, d.y, d.z);
        int counts[3] = {0, 0, 0};
        for (int it = 0; it < 3; ++it) {
            const Fetch fetch{&m, &counts[it]};
            secantSearch(x, R, it == 0 ? 0 : it + 3, true, fetch);
        }
        EXPECT_EQ(counts[0], 3);
        EXPECT_EQ(counts[2] - counts[1], 1) << "iteration 5 reads one texel";
        EXPECT_GE(counts[1], 3 + 4);
        EXPECT_LE(counts[1], 3 + 4 + 1);
        int outside = 0;
        const Fetch fo{&m, &outside};
        secantSearch(x, R, 0, true, fo, true);
        EXPECT_EQ(outside, 4);
    }
}

// Rays from a sphere of radius 2 about the origin, aimed into a box of half size `spread`
// (seeded): the ray, its analytic entry into the sphere of `radius` about the origin (the
// entry exists when disc > 0) and its closest approach to the centre.
struct SphereRay {
    glm::vec3 o, d;
    float entry, disc, closest;
};
std::vector<SphereRay> sphereRays(float radius, float spread, unsigned seed, int n) {
    std::mt19937 rng(seed);
    std::normal_distribution<float> g;
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    std::vector<SphereRay> rays;
    for (int i = 0; i < n; ++i) {
        SphereRay r;
        r.o = glm::normalize(glm::vec3(g(rng), g(rng), g(rng))) * 2.0f;
        const glm::vec3 aim(u(rng) * spread, u(rng) * spread, u(rng) * spread);
        r.d = glm::normalize(aim - r.o);
        const float b = glm::dot(r.o, r.d), c = glm::dot(r.o, r.o) - radius * radius;
        r.disc = b * b - c;
        r.entry = -b - std::sqrt(std::max(0.0f, r.disc));
        r.closest = std::sqrt(std::max(0.0f, glm::dot(r.o, r.o) - b * b));
        rays.push_back(r);
    }
    return rays;
}

// Figure 4: from outside, through the bounding box's far point, the reversed ray; hits of a
// sphere found within a texel of the analytic entry, misses rejected by the ε test. Rays
// that pass near the silhouette (within 2ε) are excused.
TEST(ImpostorSearch, OutsideSearchFindsTheEntryAndRejectsMisses) {
    const float radius = 0.5f;
    const SphereMap m({0.0f, 0.0f, 0.0f}, radius, 256);
    const float lo[3] = {-radius, -radius, -radius}, hi[3] = {radius, radius, radius};
    const float eps = 0.015f;
    int count = 0;
    const Fetch fetch{&m, &count};
    int hits = 0, misses = 0, checked = 0, i = 0;
    for (const SphereRay& r : sphereRays(radius, 0.7f, 3, 2000)) {
        ++i;
        if (std::fabs(r.closest - radius) < 2 * eps) continue;
        ++checked;
        const OutsideHit<float, bool> h = outsideSearch(V3(r.o.x, r.o.y, r.o.z), V3(r.d.x, r.d.y, r.d.z), lo, hi, eps, 8, true, fetch);
        if (r.disc > 0) {
            ASSERT_TRUE(h.valid) << "ray " << i << " hits the sphere";
            EXPECT_NEAR(h.t, r.entry, 0.01f) << "ray " << i;
            ++hits;
        } else {
            EXPECT_FALSE(h.valid) << "ray " << i << " misses the sphere by " << r.closest - radius;
            ++misses;
        }
    }
    EXPECT_GT(hits, 300);
    EXPECT_GT(misses, 300);
    EXPECT_GT(checked, 1500);
}

// Figure 4's comparison search ([6]'s linear search, then the secant steps) on the same
// analytic sphere: the entry within 0.01 of the analytic one (the last crossing from inside
// along the reversed ray, never the far side's), misses rejected, and samples + iterations
// texels read (one more when the last sample is inside), none when the box is missed.
TEST(ImpostorSearch, LinearFirstOutsideSearchFindsTheEntryAndRejectsMisses) {
    const float radius = 0.5f;
    const SphereMap m({0.0f, 0.0f, 0.0f}, radius, 256);
    const float lo[3] = {-radius, -radius, -radius}, hi[3] = {radius, radius, radius};
    const float eps = 0.015f;
    int hits = 0, misses = 0, boxMisses = 0, i = 0;
    for (const SphereRay& r : sphereRays(radius, 0.8f, 5, 2000)) {
        ++i;
        // Rays within 2ε of the silhouette are excused, and so are rays whose chord is shorter
        // than the samples' spacing could see (16 samples over the box's span ≥ the chord).
        if (std::fabs(r.closest - radius) < 2 * eps) continue;
        if (r.disc > 0 && 2.0f * std::sqrt(r.disc) < 2.0f * std::sqrt(3.0f) * radius / 16.0f) continue;
        int count = 0;
        const Fetch fetch{&m, &count};
        const OutsideHit<float, bool> h =
            outsideSearchLinearFirst(V3(r.o.x, r.o.y, r.o.z), V3(r.d.x, r.d.y, r.d.z), lo, hi, eps, 16, 8, fetch);
        if (!h.boxHit) {
            EXPECT_EQ(count, 0);
            EXPECT_FALSE(h.valid);
            ++boxMisses;
            continue;
        }
        if (r.disc > 0) {
            ASSERT_TRUE(h.valid) << "ray " << i << " hits the sphere";
            EXPECT_NEAR(h.t, r.entry, 0.01f) << "ray " << i;
            EXPECT_GE(count, 16 + 8);
            EXPECT_LE(count, 16 + 8 + 1);
            ++hits;
        } else {
            EXPECT_FALSE(h.valid) << "ray " << i << " misses the sphere by " << r.closest - radius;
            EXPECT_EQ(count, 16) << "no sample inside: no secant step";
            ++misses;
        }
    }
    EXPECT_GT(hits, 300);
    EXPECT_GT(misses, 100);
    EXPECT_GT(boxMisses, 10);
}

TEST(ImpostorSearch, RefractionIsRaycoresAndTotalInternalReflectionMirrors) {
    std::mt19937 rng(4);
    std::normal_distribution<float> g;
    for (int i = 0; i < 500; ++i) {
        const glm::vec3 n = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        glm::vec3 d = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
        if (glm::dot(d, n) > 0) d = -d;
        for (float eta : {1.0f / 1.5f, 1.5f}) {
            bool tir = false;
            const V3 t = refractOrReflect(V3(d.x, d.y, d.z), V3(n.x, n.y, n.z), eta, tir);
            glm::vec3 want;
            const bool ok = ray::refractDir(d, n, eta, &want);
            EXPECT_EQ(tir, !ok);
            if (!ok) want = ray::reflectDir(d, n);
            EXPECT_NEAR(t.x, want.x, 2e-6f);
            EXPECT_NEAR(t.y, want.y, 2e-6f);
            EXPECT_NEAR(t.z, want.z, 2e-6f);
        }
        EXPECT_NEAR(fresnelSchlick(-glm::dot(d, n), 0.04f), ray::FresnelSchlick(-glm::dot(d, n), 0.04f), 1e-6f);
    }
    EXPECT_NEAR(expNeg(0.0f), 1.0f, 1e-7f);
    for (float z : {0.01f, 0.1f, 0.5f, 1.0f, 2.0f}) EXPECT_NEAR(expNeg(z) / std::exp(-z), 1.0f, 1e-5f) << z;
}

// The scalar twin (float, bool) and the SSE lanes (Float4, Mask4) and the quad groups
// (FloatQ<2>) compute the same bits: the search, the outside search and a whole shading
// with the mover, on random rays, NaN-free and degenerate ones alike.
TEST(ImpostorSearch, ScalarTwinEqualsLanesBitForBit) {
    const SphereMap env({0.5f, 1.0f, -0.5f}, 6.0f, 32), refr({0.0f, 0.0f, 0.0f}, 0.4f, 32);
    int count = 0;
    const Fetch fe{&env, &count}, fr{&refr, &count};
    ObjectFrame self, mover;
    mover.centre[0] = 1.0f;
    mover.boxLo[0] = mover.boxLo[1] = mover.boxLo[2] = -0.4f;
    mover.boxHi[0] = mover.boxHi[1] = mover.boxHi[2] = 0.4f;
    self.boxLo[0] = self.boxLo[1] = self.boxLo[2] = -0.4f;
    self.boxHi[0] = self.boxHi[1] = self.boxHi[2] = 0.4f;
    self.absorption[0] = 0.05f, self.absorption[1] = 0.1f, self.absorption[2] = 0.2f;
    const float c = std::cos(0.7f), s = std::sin(0.7f);
    const float rot[9] = {c, 0, -s, 0, 1, 0, s, 0, c};
    std::memcpy(mover.toLocal, rot, sizeof rot);
    std::mt19937 rng(5);
    std::normal_distribution<float> g;
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    auto check = [](float a, float b, const char* what, int i) {
        ASSERT_TRUE(sameBits(a, b) || (std::isnan(a) && std::isnan(b))) << what << " ray " << i << ": " << a << " vs " << b;
    };
    for (int i = 0; i < 400; ++i) {
        float px[4], py[4], pz[4], dx[4], dy[4], dz[4];
        for (int l = 0; l < 4; ++l) {
            const glm::vec3 n = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)));
            glm::vec3 d = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)) + glm::vec3(1.0f, 0.0f, 0.0f));
            if (i % 17 == 0 && l == 1) d = glm::vec3(1.0f, 0.0f, 0.0f);  // axis-aligned: slab divisions by zero
            const glm::vec3 p = n * 0.4f + glm::vec3(u(rng), u(rng), u(rng)) * 0.01f;
            px[l] = p.x, py[l] = p.y, pz[l] = p.z, dx[l] = d.x, dy[l] = d.y, dz[l] = d.z;
        }
        const Vec3L<Float4> P4(Float4::lanes(px[0], px[1], px[2], px[3]), Float4::lanes(py[0], py[1], py[2], py[3]),
                               Float4::lanes(pz[0], pz[1], pz[2], pz[3]));
        const Vec3L<Float4> D4(Float4::lanes(dx[0], dx[1], dx[2], dx[3]), Float4::lanes(dy[0], dy[1], dy[2], dy[3]),
                               Float4::lanes(dz[0], dz[1], dz[2], dz[3]));
        const Mask4 live = Mask4::fromBits(i % 5 == 0 ? 0b1011u : 0b1111u);
        const SearchResult<Float4, Mask4> s4 = secantSearch(P4 * Float4(0.3f), D4, 8, live, fe);
        const OutsideHit<Float4, Mask4> o4 =
            outsideSearch(P4 * Float4(4.0f), D4 * Float4(-1.0f), mover.boxLo, mover.boxHi, 0.01f, 8, live, fr);
        Shaded<Float4> sh4 = shadeOwn(self, 8, P4, P4, D4, live, fe, fr);
        throughMover(mover, 8, P4, sh4.reflDir, sh4.reflD, live, sh4.reflColour, sh4.searches, sh4.moverFlags, 1.0f, fe, fr);
        // Quad groups of two: quad 0 these lanes, quad 1 the same.
        MaskQ<2> liveQ;
        liveQ.q = {live, live};
        Vec3L<FloatQ<2>> PQ, DQ;
        for (int q = 0; q < 2; ++q) {
            PQ.x.setQuad(q, P4.x), PQ.y.setQuad(q, P4.y), PQ.z.setQuad(q, P4.z);
            DQ.x.setQuad(q, D4.x), DQ.y.setQuad(q, D4.y), DQ.z.setQuad(q, D4.z);
        }
        Shaded<FloatQ<2>> shQ = shadeOwn(self, 8, PQ, PQ, DQ, liveQ, fe, fr);
        throughMover(mover, 8, PQ, shQ.reflDir, shQ.reflD, liveQ, shQ.reflColour, shQ.searches, shQ.moverFlags, 1.0f, fe, fr);
        for (int l = 0; l < 4; ++l) {
            if (!((live.bits() >> l) & 1u)) continue;
            const V3 P(px[l], py[l], pz[l]), D(dx[l], dy[l], dz[l]);
            const SearchResult<float, bool> s1 = secantSearch(P * 0.3f, D, 8, true, fe);
            check(s1.d, s4.d[l], "search d", i);
            check(s1.texel.w, s4.texel.w[l], "search texel", i);
            const OutsideHit<float, bool> o1 = outsideSearch(P * 4.0f, D * -1.0f, mover.boxLo, mover.boxHi, 0.01f, 8, true, fr);
            ASSERT_EQ(o1.valid, bool((o4.valid.bits() >> l) & 1u)) << "outside valid, ray " << i;
            check(o1.t, o4.t[l], "outside t", i);
            Shaded<float> sh1 = shadeOwn(self, 8, P, P, D, true, fe, fr);
            throughMover(mover, 8, P, sh1.reflDir, sh1.reflD, true, sh1.reflColour, sh1.searches, sh1.moverFlags, 1.0f, fe, fr);
            const V3 c1 = combine(self, sh1);
            const Vec3L<Float4> c4 = combine(self, sh4);
            const Vec3L<FloatQ<2>> cQ = combine(self, shQ);
            check(c1.x, c4.x[l], "colour r", i);
            check(c1.y, c4.y[l], "colour g", i);
            check(c1.z, c4.z[l], "colour b", i);
            check(c1.x, cQ.x[4 + l], "group colour r", i);
            check(sh1.searches, sh4.searches[l], "searches", i);
            check(sh1.moverFlags, shQ.moverFlags[l], "group flags", i);
        }
    }
}

// Figure 2's experiment as the reproduction runs it: the error falls with the iterations,
// and classical environment mapping is far worse.
TEST(ImpostorSearch, AnalyticRoomErrorFallsWithIterations) {
    const AnalyticErrors e = analyticSearchErrors(128, 8, 600);
    ASSERT_EQ(e.meanError.size(), 9u);
    EXPECT_LT(e.meanError[8], e.meanError[0]);
    EXPECT_LT(e.meanError[4], e.meanError[1]);
    EXPECT_LT(e.meanError[0], e.classicalError);
    EXPECT_GT(e.bracketed, 0.5);
}

}  // namespace
}  // namespace rg::impostors
