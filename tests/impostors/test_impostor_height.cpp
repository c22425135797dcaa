// 002 §6's refractor height maps (demos/impostors/impostor_height_search.h,
// impostor_height_maps.cpp) against closed forms: the map Embree builds of a sphere and a
// cylinder against their heights over the plane of symmetry, Figure 7's cases 1, 2, 3, 3a → 3b
// and Figure 8's mirrored retry on rays computed by hand against an analytic cylinder's map,
// and the scalar twin against the SSE lanes and the quad groups bit for bit.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <random>

#include "core/error.h"
#include "impostor_height_maps.h"
#include "impostor_height_shading.h"
#include "impostor_renderer.h"
#include "raycore/shapes.h"

namespace rg::impostors {
namespace {

using raster::Float4;
using raster::FloatQ;
using raster::Mask4;
using raster::MaskQ;
using V3 = Vec3L<float>;
using V4 = Vec4L<float>;

// The map Embree takes of a sphere of radius r about its centre: over the plane z = 0, the
// height √(r² − s² − t²) and the normal (s, t, h)/r. The tessellation (a lathe of 256 × 128)
// sits within r(1 − cos(π/128)) of the sphere; heights where the slope is steep (ρ > 0.9r)
// are excused from the height check, as the chord error grows there as r·δ/h.
TEST(ImpostorHeightMap, SphereMapIsTheClosedForm) {
    const float r = 0.5f;
    const ray::Mesh sphere = ray::makeSphere(r, 256, 128);
    const int n = 128;
    const HeightMap m = buildHeightMap(sphere, glm::vec3(0.0f), n);
    const HeightFrame& f = m.frame;
    EXPECT_NEAR(f.axis[0], 0.0f, 1e-6f);
    EXPECT_NEAR(f.axis[1], 0.0f, 1e-6f);
    EXPECT_GT(f.hMax, r);
    const float sag = r * (1.0f - std::cos(3.14159265f / 128.0f));
    int checked = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float s = f.sLo + (float(x) + 0.5f) / float(n) * (f.sHi - f.sLo);
            const float t = f.tHi - (float(y) + 0.5f) / float(n) * (f.tHi - f.tLo);
            const glm::vec4 v = m.texels[size_t(y) * n + size_t(x)];
            const float rho = std::sqrt(s * s + t * t);
            // The texel's own coordinates through the frame the programs use.
            EXPECT_EQ(int(std::floor(heightU(f, s) * float(n))), x);
            EXPECT_EQ(int(std::floor(heightV(f, t) * float(n))), y);
            if (rho > 1.01f * r) {
                EXPECT_EQ(v.w, 0.0f) << "outside the silhouette at texel " << x << ", " << y;
                continue;
            }
            if (rho > 0.9f * r) continue;
            const float h = std::sqrt(r * r - rho * rho);
            EXPECT_NEAR(v.w, h, 3.0f * sag * r / h + 1e-5f) << "texel " << x << ", " << y;
            EXPECT_NEAR(v.x, s / r, 0.02f);
            EXPECT_NEAR(v.y, t / r, 0.02f);
            EXPECT_NEAR(v.z, h / r, 0.02f);
            ++checked;
        }
    EXPECT_GT(checked, int(0.5f * 3.14159f * 0.81f * (n * n / 4)));
}

// A cylinder about a piece's axis, its box centre off the origin (the map's frame is the
// refractor map's, about the box centre): over its side the height is √(r² − s²) whatever t,
// the normal (s, 0, h)/r; the cap is flat.
TEST(ImpostorHeightMap, CylinderMapIsTheClosedForm) {
    const float r = 0.3f, height = 0.8f;
    const ray::Mesh cyl = ray::makeCylinder(r, height, 512);
    const glm::vec3 centre(0.0f, 0.5f * height, 0.0f);
    const int n = 64;
    const HeightMap m = buildHeightMap(cyl, centre, n);
    const HeightFrame& f = m.frame;
    EXPECT_LT(f.tLo, -0.5f * height);
    EXPECT_GT(f.tHi, 0.5f * height);
    int checked = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float s = f.sLo + (float(x) + 0.5f) / float(n) * (f.sHi - f.sLo);
            const float t = f.tHi - (float(y) + 0.5f) / float(n) * (f.tHi - f.tLo);
            const glm::vec4 v = m.texels[size_t(y) * n + size_t(x)];
            if (std::fabs(s) > r || std::fabs(t) > 0.5f * height) {
                EXPECT_EQ(v.w, 0.0f) << "texel " << x << ", " << y;
                continue;
            }
            const float h = std::sqrt(r * r - s * s);
            if (std::fabs(s) > 0.9f * r) continue;
            EXPECT_NEAR(v.w, h, 1e-4f) << "texel " << x << ", " << y;
            EXPECT_NEAR(v.x, s / r, 0.01f);
            EXPECT_NEAR(v.y, 0.0f, 0.01f);
            EXPECT_NEAR(v.z, h / r, 0.01f);
            ++checked;
        }
    EXPECT_GT(checked, n * n / 4);
}

// An analytic height map of a cylinder of radius 1 about the y axis, |t| ≤ 1, point sampled
// at n² texels like the device: the closed form at each texel's centre.
struct CylinderHeights {
    HeightFrame frame;
    int n = 2048;
    CylinderHeights() {
        frame.sLo = -1.1f, frame.sHi = 1.1f, frame.tLo = -1.1f, frame.tHi = 1.1f;
        frame.hMax = 1.05f;
        frame.steps = 20;
    }
    glm::vec4 texel(float u, float v) const {
        auto idx = [&](float c) { return std::clamp(int(std::floor(c * float(n))), 0, n - 1); };
        const float s = frame.sLo + (float(idx(u)) + 0.5f) / float(n) * (frame.sHi - frame.sLo);
        const float t = frame.tHi - (float(idx(v)) + 0.5f) / float(n) * (frame.tHi - frame.tLo);
        if (std::fabs(s) >= 1.0f || std::fabs(t) >= 1.0f) return glm::vec4(0.0f);
        const float h = std::sqrt(1.0f - s * s);
        // The caps' normal within a rim 0.002 deep, the side's elsewhere.
        if (std::fabs(t) > 0.998f) return glm::vec4(0.0f, t > 0 ? 1.0f : -1.0f, 0.0f, h);
        return glm::vec4(s, 0.0f, h, h);
    }
};

struct HFetch {
    const CylinderHeights* map;
    V4 operator()(float u, float v, bool live) const {
        if (!live) return V4(0.0f, 0.0f, 0.0f, 0.0f);
        const glm::vec4 t = map->texel(u, v);
        return V4(t.x, t.y, t.z, t.w);
    }
    Vec4L<Float4> operator()(const Float4& u, const Float4& v, const Mask4& live) const {
        std::array<glm::vec4, 4> t{};
        for (int i = 0; i < 4; ++i)
            if ((live.bits() >> i) & 1u) t[size_t(i)] = map->texel(u[i], v[i]);
        return Vec4L<Float4>::fromLanes(t);
    }
    template <int N>
    Vec4L<FloatQ<N>> operator()(const FloatQ<N>& u, const FloatQ<N>& v, const MaskQ<N>& live) const {
        Vec4L<FloatQ<N>> r;
        for (int q = 0; q < N; ++q) r.setQuad(q, (*this)(u.quad(q), v.quad(q), live.quad(q)));
        return r;
    }
};

HeightHit<float, bool> search(const CylinderHeights& m, glm::vec3 o, glm::vec3 d, bool exit) {
    d = glm::normalize(d);
    return heightSearch(m.frame, V3(o.x, o.y, o.z), V3(d.x, d.y, d.z), exit, true, HFetch{&m});
}
void expectPoint(const HeightHit<float, bool>& h, glm::vec3 want, float tol = 0.01f) {
    EXPECT_NEAR(h.point.x, want.x, tol);
    EXPECT_NEAR(h.point.y, want.y, tol);
    EXPECT_NEAR(h.point.z, want.z, tol);
}

// Figure 7, case 1 (the plane within the box, the front segment [d_near, d_plane]): a ray
// from (0, 0, 3) towards −z and a little +x enters the cylinder's front at s² + h² = 1. With
// d = (0.2, 0, −1)/|·|, the hit solves (0.2k)² + (3 − k)² = 1: k = (3 − √(9 − 1.04·8))/1.04.
TEST(ImpostorHeightSearch, Case1FindsTheFrontEntry) {
    const CylinderHeights m;
    const HeightHit<float, bool> h = search(m, {0, 0, 3}, {0.2f, 0, -1}, false);
    EXPECT_EQ(h.segmentCase, kCase1);
    EXPECT_TRUE(h.found);
    EXPECT_FALSE(h.retried);
    const float k = (3.0f - std::sqrt(9.0f - 1.04f * 8.0f)) / 1.04f;
    expectPoint(h, {0.2f * k, 0.0f, 3.0f - k});
    EXPECT_NEAR(h.normal.x, 0.2f * k, 0.01f);
    EXPECT_NEAR(h.normal.z, 3.0f - k, 0.01f);
}

// Figure 8: a refracted ray from the front surface (0, 0, 1) into the cylinder along
// (0.3, 0, −1) reaches the billboard's plane still inside (case 1, the front search finds no
// exit), so the segment behind the plane is reflected to it and searched again. The exit, by
// hand: (0.3k)² + (1 − k)² = 1, k = 2/1.09, at (0.550, 0, −0.835), and its normal points
// back (−z): the mirrored texel's h component reflected again.
TEST(ImpostorHeightSearch, Case1ExitBehindThePlaneIsFoundByTheMirroredRetry) {
    const CylinderHeights m;
    const HeightHit<float, bool> h = search(m, {0, 0, 1}, {0.3f, 0, -1}, true);
    EXPECT_EQ(h.segmentCase, kCase1);
    EXPECT_TRUE(h.retried);
    EXPECT_TRUE(h.found);
    const float k = 2.0f / 1.09f;
    expectPoint(h, {0.3f * k, 0.0f, 1.0f - k});
    EXPECT_NEAR(h.normal.x, 0.3f * k, 0.01f);
    EXPECT_NEAR(h.normal.z, 1.0f - k, 0.01f);
}

// Case 2 (the ray leaves the box before it reaches the plane): from (0, 0, 1.5) along
// (1, 0, −0.5) the box's s slab ends at k = 1.1 and the plane is at k = 3; s² + h² stays
// above 1 on the way, so there is no hit, and no retry ("the ray leaves the box"). An exit
// from (0, 0, 1) steeply up, (0, 1, −0.2), leaves through the top cap (t = 1) at k = 1 before
// the plane (k = 5): case 2, found, the cap's normal.
TEST(ImpostorHeightSearch, Case2SearchesUpToTheBoxOnly) {
    const CylinderHeights m;
    const HeightHit<float, bool> miss = search(m, {0, 0, 1.5f}, {1, 0, -0.5f}, false);
    EXPECT_EQ(miss.segmentCase, kCase2);
    EXPECT_FALSE(miss.found);
    EXPECT_FALSE(miss.retried);
    const HeightHit<float, bool> up = search(m, {0, 0, 1}, {0, 1, -0.2f}, true);
    EXPECT_EQ(up.segmentCase, kCase2);
    EXPECT_TRUE(up.found);
    expectPoint(up, {0.0f, 1.0f, 0.8f});
    EXPECT_NEAR(up.normal.y, 1.0f, 1e-6f);
}

// Case 3 (d_plane ≤ d_near): an exit from the top cap (0, 1, 0.5) going down and away from
// the plane, (0, −1, 0.3), stays in front and leaves through the side where h = 1: k = 5/3,
// at (0, −2/3, 1).
TEST(ImpostorHeightSearch, Case3InFrontSearchesTheBoxSpan) {
    const CylinderHeights m;
    const HeightHit<float, bool> h = search(m, {0, 1, 0.5f}, {0, -1, 0.3f}, true);
    EXPECT_EQ(h.segmentCase, kCase3);
    EXPECT_TRUE(h.found);
    EXPECT_FALSE(h.retried);
    expectPoint(h, {0.0f, 1.0f - 5.0f / 3.0f, 1.0f});
    EXPECT_NEAR(h.normal.z, 1.0f, 0.01f);
}

// Case 3a → 3b: from above the cylinder, (0, 3, 0.5) along (0, −1, −0.6), the ray crosses the
// billboard's plane at k = 0.83, before the box (t ≤ 1.1 from k = 1.9): the segment within
// the box is behind the plane, reflected to it, and the top cap is met at k = 2, (0, 1, −0.7).
TEST(ImpostorHeightSearch, Case3aBehindThePlaneIsReflected) {
    const CylinderHeights m;
    const HeightHit<float, bool> h = search(m, {0, 3, 0.5f}, {0, -1, -0.6f}, false);
    EXPECT_EQ(h.segmentCase, kCase3a);
    EXPECT_TRUE(h.found);
    EXPECT_FALSE(h.retried);
    expectPoint(h, {0.0f, 1.0f, -0.7f});
    EXPECT_NEAR(h.normal.y, 1.0f, 1e-6f);
}

// The billboard turns to face the ray's origin: the same ray turned about the axis by any
// angle finds the same hit turned by it (a cylinder has axial symmetry: §6's proxy is exact).
TEST(ImpostorHeightSearch, TheBillboardFacesTheOrigin) {
    const CylinderHeights m;
    const HeightHit<float, bool> ref = search(m, {0, 0, 1}, {0.3f, 0.2f, -1}, true);
    ASSERT_TRUE(ref.found);
    for (float a : {0.5f, 1.7f, 3.0f, -2.2f}) {
        const float c = std::cos(a), s = std::sin(a);
        auto turn = [&](glm::vec3 p) { return glm::vec3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z); };
        const HeightHit<float, bool> h = search(m, turn({0, 0, 1}), turn({0.3f, 0.2f, -1}), true);
        ASSERT_TRUE(h.found);
        const glm::vec3 want = turn({ref.point.x, ref.point.y, ref.point.z});
        expectPoint(h, want, 0.005f);
    }
}

// The finite cylinder of CylinderHeights (radius r, |y| ≤ hh): the ray's first hit, or −1.
float cylinderHit(glm::vec3 o, glm::vec3 d, float r, float hh) {
    float best = -1.0f;
    auto take = [&](float k) {
        if (k > 0.0f && (best < 0.0f || k < best)) best = k;
    };
    const float a = d.x * d.x + d.z * d.z, b = o.x * d.x + o.z * d.z, c = o.x * o.x + o.z * o.z - r * r;
    const float disc = b * b - a * c;
    if (a > 0.0f && disc >= 0.0f)
        for (float k : {(-b - std::sqrt(disc)) / a, (-b + std::sqrt(disc)) / a})
            if (std::fabs(o.y + k * d.y) <= hh) take(k);
    if (d.y != 0.0f)
        for (float y : {-hh, hh}) {
            const float k = (y - o.y) / d.y;
            const glm::vec3 p = o + k * d;
            if (p.x * p.x + p.z * p.z <= r * r) take(k);
        }
    return best;
}

// §6 from outside ("Search can be executed from an outer point"): rays from around the
// cylinder aimed into its box, the entry search against the closed-form first hit. Rays
// within 0.03 of grazing (a cylinder 3 % smaller and one 3 % larger disagree) are excused.
// A binary search "will not necessarily return the nearest intersection point": where it
// returns one, it is the entry within 0.02 for nearly every ray, and it tells hits from
// misses for nearly every ray.
TEST(ImpostorHeightSearch, EntryFromOutsideAgreesWithTheAnalyticCylinder) {
    const CylinderHeights m;
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    int checked = 0, agree = 0, hits = 0, close = 0;
    for (int i = 0; i < 3000; ++i) {
        const float a = 3.14159265f * u(rng);
        const glm::vec3 o(3.0f * std::sin(a), 2.0f * u(rng), 3.0f * std::cos(a));
        const glm::vec3 aim(1.3f * u(rng), 1.3f * u(rng), 1.3f * u(rng));
        const glm::vec3 d = glm::normalize(aim - o);
        const float inner = cylinderHit(o, d, 0.97f, 0.97f), outer = cylinderHit(o, d, 1.03f, 1.03f);
        if ((inner > 0.0f) != (outer > 0.0f)) continue;
        ++checked;
        const float truth = cylinderHit(o, d, 1.0f, 1.0f);
        const HeightHit<float, bool> h = search(m, o, d, false);
        agree += h.found == (truth > 0.0f);
        if (h.found && truth > 0.0f) {
            ++hits;
            close += std::fabs(h.d - truth) < 0.02f;
        }
    }
    EXPECT_GT(checked, 2000);
    EXPECT_GT(hits, 500);
    EXPECT_GE(double(agree) / checked, 0.97) << agree << " of " << checked;
    EXPECT_GE(double(close) / hits, 0.97) << close << " of " << hits;
}

// A constant-distance environment (a sphere of radius 5 about the reference point) for every
// lane type: radiance = the direction.
struct SkyFetch {
    template <class F, class M>
    Vec4L<F> operator()(const Vec3L<F>& d, const M&) const {
        return Vec4L<F>(d.x, d.y, d.z, F(5.0f));
    }
};

bool sameBits(float a, float b) { return std::memcmp(&a, &b, 4) == 0 || (std::isnan(a) && std::isnan(b)); }

// The scalar twin and the lane types compute the same bits: the search and a whole shading
// with the height-map exit, on random rays from the cylinder's surface and from outside.
TEST(ImpostorHeightSearch, ScalarTwinEqualsLanesBitForBit) {
    CylinderHeights m;
    m.n = 256;
    m.frame.steps = 8;
    const HFetch fetch{&m};
    ObjectFrame self;
    self.absorption[0] = 0.1f;
    std::mt19937 rng(12);
    int met = 0;
    std::normal_distribution<float> g;
    for (int i = 0; i < 300; ++i) {
        float o[3][4], d[3][4];
        for (int l = 0; l < 4; ++l) {
            const float a = g(rng);
            glm::vec3 p(std::sin(a), 0.8f * std::tanh(g(rng)), std::cos(a));
            if (l == 3) p *= 3.0f;  // from outside
            glm::vec3 dir = glm::normalize(glm::vec3(g(rng), g(rng), g(rng)) - 0.5f * p);
            if (i % 13 == 0 && l == 1) dir = glm::vec3(0.0f, 1.0f, 0.0f);  // parallel to the plane
            for (int k = 0; k < 3; ++k) o[k][l] = p[k], d[k][l] = dir[k];
        }
        const Vec3L<Float4> O4(Float4::lanes(o[0][0], o[0][1], o[0][2], o[0][3]), Float4::lanes(o[1][0], o[1][1], o[1][2], o[1][3]),
                               Float4::lanes(o[2][0], o[2][1], o[2][2], o[2][3]));
        const Vec3L<Float4> D4(Float4::lanes(d[0][0], d[0][1], d[0][2], d[0][3]), Float4::lanes(d[1][0], d[1][1], d[1][2], d[1][3]),
                               Float4::lanes(d[2][0], d[2][1], d[2][2], d[2][3]));
        const Mask4 live = Mask4::fromBits(i % 5 == 0 ? 0b1101u : 0b1111u);
        const HeightHit<Float4, Mask4> h4 = heightSearch(m.frame, O4, D4, true, live, fetch);
        const HeightPaths<Float4, Mask4> p4 = tracePathsHeight(self, m.frame, O4, O4, D4, live, fetch);
        MaskQ<2> liveQ;
        liveQ.q = {live, live};
        Vec3L<FloatQ<2>> OQ, DQ;
        for (int q = 0; q < 2; ++q) {
            OQ.x.setQuad(q, O4.x), OQ.y.setQuad(q, O4.y), OQ.z.setQuad(q, O4.z);
            DQ.x.setQuad(q, D4.x), DQ.y.setQuad(q, D4.y), DQ.z.setQuad(q, D4.z);
        }
        const HeightPaths<FloatQ<2>, MaskQ<2>> pQ = tracePathsHeight(self, m.frame, OQ, OQ, DQ, liveQ, fetch);
        // The static object's rays met by a mover (this cylinder, 2.5 away along x).
        ObjectFrame mover = self;
        mover.centre[0] = 2.5f;
        Vec3L<Float4> c4(Float4(0.0f), Float4(0.0f), Float4(0.0f));
        Float4 s4(3.0f), f4(0.0f);
        throughMoverHeight(mover, m.frame, 4, O4, D4, Float4(100.0f), live, c4, s4, f4, 1.0f, SkyFetch{}, SkyFetch{}, fetch);
        for (int l = 0; l < 4; ++l) {
            if (!((live.bits() >> l) & 1u)) continue;
            const V3 O(o[0][l], o[1][l], o[2][l]), D(d[0][l], d[1][l], d[2][l]);
            const HeightHit<float, bool> h1 = heightSearch(m.frame, O, D, true, true, fetch);
            ASSERT_EQ(h1.found, bool((h4.found.bits() >> l) & 1u)) << "ray " << i << " lane " << l;
            ASSERT_TRUE(sameBits(h1.d, h4.d[l])) << "ray " << i << " lane " << l << ": " << h1.d << " vs " << h4.d[l];
            ASSERT_TRUE(sameBits(h1.normal.x, h4.normal.x[l])) << "ray " << i;
            ASSERT_TRUE(sameBits(h1.segmentCase, h4.segmentCase[l])) << "ray " << i;
            const HeightPaths<float, bool> p1 = tracePathsHeight(self, m.frame, O, O, D, true, fetch);
            ASSERT_TRUE(sameBits(p1.paths.exitDir.x, p4.paths.exitDir.x[l])) << "ray " << i;
            ASSERT_TRUE(sameBits(p1.paths.exitOrigin.z, p4.paths.exitOrigin.z[l])) << "ray " << i;
            ASSERT_TRUE(sameBits(p1.paths.transmit.x, pQ.paths.transmit.x[4 + l])) << "ray " << i;
            ASSERT_TRUE(sameBits(p1.paths.exitDir.y, pQ.paths.exitDir.y[l])) << "ray " << i;
            V3 c1(0.0f, 0.0f, 0.0f);
            float s1 = 3.0f, f1 = 0.0f;
            throughMoverHeight(mover, m.frame, 4, O, D, 100.0f, true, c1, s1, f1, 1.0f, SkyFetch{}, SkyFetch{}, fetch);
            ASSERT_TRUE(sameBits(c1.x, c4.x[l]) && sameBits(c1.z, c4.z[l])) << "mover colour, ray " << i;
            ASSERT_TRUE(sameBits(s1, s4[l]) && sameBits(f1, f4[l])) << "mover searches, ray " << i;
            met += f1 > 0.0f;
        }
    }
    EXPECT_GT(met, 20) << "rays meeting the mover";
}

// The height-map exit on the device: the same bytes on both paths and any thread count, in
// the static and the separated mode, and a frame unlike the distance-map exit's (the setting
// selects the program). Five objects of the §8 scene, coarsely tessellated.
TEST(ImpostorHeightFrame, SameBytesOnBothPathsAndEveryThreadCount) {
    ChessOptions o;
    o.segments = 12;
    o.sphereSlices = 16;
    o.keep = {"white_queen3", "white_knight6"};
    const ImpostorScene scene = makeChessScene(o);
    auto bytes = [](const ImpostorRenderer& r) {
        std::vector<uint8_t> out;
        for (float v : r.frame().pixels) out.push_back(uint8_t(std::lround(v * 255.0f)));
        return out;
    };
    for (Mode mode : {Mode::Static, Mode::Separated}) {
        ImpostorSettings s;
        s.width = s.height = 40;
        s.envSize = 8;
        s.refractorSize = 8;
        s.lightMapSize = 32;
        s.shadowMapSize = 64;
        s.heightMapSize = 32;
        s.mode = mode;
        s.moverU = 0.5f;
        s.exit = Exit::HeightMap;
        std::vector<uint8_t> first;
        for (auto [path, threads] : {std::pair{Path::Fast, 1}, {Path::Fast, 2}, {Path::Reference, 1}}) {
            ImpostorRenderer r(scene, threads, path);
            const ImpostorFrame f = r.render(scene.closeUp, s);
            EXPECT_GT(f.glassFragments, 50);
            if (first.empty()) first = bytes(r);
            else EXPECT_EQ(bytes(r), first) << modeName(mode) << " threads " << threads;
        }
        ImpostorRenderer r(scene, 2, Path::Fast);
        s.exit = Exit::DistanceMap;
        r.render(scene.closeUp, s);
        EXPECT_NE(bytes(r), first) << "the exit setting changed nothing";
    }
    EXPECT_EQ(exitByName("height-map"), Exit::HeightMap);
    EXPECT_THROW(exitByName("heightmap"), Error);
}

}  // namespace
}  // namespace rg::impostors
