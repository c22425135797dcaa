// Ray queries against analytic answers: distances to a sphere, rays aimed exactly at shared
// edges and vertices (robust mode), all-intersections with duplicates removed, packets.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include <cmath>

#include "raycore/accel.h"
#include "raycore/builtin_scenes.h"
#include "raycore/shapes.h"

namespace rg::ray {
namespace {

Scene oneObject(Mesh m, MaterialType type = MaterialType::Diffuse) {
    Scene s;
    s.name = "test";
    Material mat;
    mat.name = "m";
    mat.type = type;
    s.addMaterial(mat);
    s.addObject("object", s.addMesh(std::move(m)), 0);
    return s;
}

Ray ray(glm::vec3 o, glm::vec3 d) {
    Ray r;
    r.origin = o;
    r.dir = glm::normalize(d);
    return r;
}

TEST(Accel, RayAtUnitSphereHitsAtTheKnownDistance) {
    Scene s = oneObject(makeSphere(1.0f, 128, 64));
    Accel accel(s);
    // Towards vertices of the tessellation (poles, equator points at multiples of 90°): the
    // hit is exactly on the sphere, at distance 5 − 1 = 4.
    for (glm::vec3 d : {glm::vec3(0, -1, 0), glm::vec3(0, 1, 0), glm::vec3(-1, 0, 0),
                        glm::vec3(0, 0, -1), glm::vec3(1, 0, 0)}) {
        Hit h = accel.intersect(ray(-5.0f * d, d));
        ASSERT_TRUE(h.valid()) << d.x << "," << d.y << "," << d.z;
        EXPECT_NEAR(h.t, 4.0f, 2e-6f * 5) << d.x << "," << d.y << "," << d.z;
        SurfacePoint sp = accel.surface(ray(-5.0f * d, d), h);
        EXPECT_TRUE(sp.frontFace);
        EXPECT_GT(glm::dot(sp.ng, -d), 0.99f);
    }
    // Any other direction through the centre: between the chord and the sphere, i.e. the
    // distance is 4 plus at most the sagitta 1 − cos(π/64) of the tessellation.
    const float sag = 1.0f - std::cos(3.14159265f / 64.0f);
    for (int i = 0; i < 50; ++i) {
        glm::vec3 d = glm::normalize(glm::vec3(std::sin(i * 1.3f), std::cos(i * 0.7f), std::sin(i * 2.1f + 1)));
        Hit h = accel.intersect(ray(-5.0f * d, d));
        ASSERT_TRUE(h.valid());
        EXPECT_GE(h.t, 4.0f - 1e-5f);
        EXPECT_LE(h.t, 4.0f + sag + 1e-5f);
    }
    // Missing the sphere.
    EXPECT_FALSE(accel.intersect(ray({0, 2, 5}, {0, 0, -1})).valid());
    EXPECT_TRUE(accel.occluded(ray({0, 0, 5}, {0, 0, -1})));
    EXPECT_FALSE(accel.occluded(ray({0, 2, 5}, {0, 0, -1})));
}

TEST(Accel, RaysAlongASharedEdgeNeverSlipThrough) {
    // Each cube face is two triangles split along a diagonal; rays through points of that
    // diagonal hit exactly on the shared edge. Robust mode must report a hit every time.
    Scene s = oneObject(makeCube(1.0f));
    Accel accel(s);
    for (int i = 0; i <= 1000; ++i) {
        float a = -0.999f + 1.998f * float(i) / 1000.0f;
        // +z face corners go (−1,−1) → (1,1) along its diagonal.
        Hit h = accel.intersect(ray({a, a, 5.0f}, {0, 0, -1}));
        ASSERT_TRUE(h.valid()) << "ray through (" << a << "," << a << ") missed";
        EXPECT_NEAR(h.t, 4.0f, 1e-5f);
    }
}

TEST(Accel, AllIntersectionsThroughASharedEdgeAreMerged) {
    Scene s = oneObject(makeCube(1.0f));
    Accel accel(s);
    Ray r = ray({0, 0, 5}, {0, 0, -1});  // through both face centres, on both diagonals
    std::vector<Hit> tri = accel.allTriangleHits(r);
    EXPECT_GE(tri.size(), 2u);
    std::vector<Hit> all = accel.allIntersections(r, false);
    ASSERT_EQ(all.size(), 2u) << "one entry, one exit";
    EXPECT_NEAR(all[0].t, 4.0f, 1e-5f);
    EXPECT_NEAR(all[1].t, 6.0f, 1e-5f);
    std::vector<Hit> front = accel.allIntersections(r, true);
    ASSERT_EQ(front.size(), 1u);
    EXPECT_NEAR(front[0].t, 4.0f, 1e-5f);
}

TEST(Accel, AllIntersectionsThroughSharedVerticesAreMerged) {
    // Through two opposite corners of the cube: each corner is shared by three faces
    // (several triangles each), all met at the same t.
    Scene s = oneObject(makeCube(1.0f));
    Accel accel(s);
    Ray r = ray({3, 3, 3}, {-1, -1, -1});
    std::vector<Hit> all = accel.allIntersections(r, false);
    ASSERT_EQ(all.size(), 2u);
    EXPECT_NEAR(all[0].t, 2.0f * std::sqrt(3.0f), 1e-4f);
    EXPECT_NEAR(all[1].t, 4.0f * std::sqrt(3.0f), 1e-4f);
    EXPECT_EQ(accel.allIntersections(r, true).size(), 1u);
    // The sphere's pole is a vertex shared by 128 triangles.
    Scene sp = oneObject(makeSphere(1.0f, 128, 64));
    Accel a2(sp);
    Ray down = ray({0, 5, 0}, {0, -1, 0});
    EXPECT_GE(a2.allTriangleHits(down).size(), 2u);
    std::vector<Hit> poles = a2.allIntersections(down, false);
    ASSERT_EQ(poles.size(), 2u);
    EXPECT_NEAR(poles[0].t, 4.0f, 1e-5f);
    EXPECT_NEAR(poles[1].t, 6.0f, 1e-5f);
}

TEST(Accel, AllIntersectionsContinueThroughOccluders) {
    Scene s;
    s.name = "two spheres";
    s.addMaterial({});
    uint32_t m = s.addMesh(makeSphere(1.0f, 64, 32));
    s.addObject("near", m, 0, glm::mat4(1.0f));
    glm::mat4 far(1.0f);
    far[3] = glm::vec4(0.3f, 0.2f, -4.0f, 1.0f);
    s.addObject("far", m, 0, far);
    Accel accel(s);
    Ray r = ray({0.1f, 0.05f, 5}, {0, 0, -1});
    std::vector<Hit> front = accel.allIntersections(r, true);
    ASSERT_EQ(front.size(), 2u);
    EXPECT_EQ(front[0].object, 0u);
    EXPECT_EQ(front[1].object, 1u);
    EXPECT_LT(front[0].t, front[1].t);
    EXPECT_EQ(accel.allIntersections(r, false).size(), 4u);
    // The nearest of them is what intersect() returns.
    Hit h = accel.intersect(r);
    EXPECT_EQ(h.object, 0u);
    EXPECT_FLOAT_EQ(h.t, front[0].t);
}

TEST(Accel, PacketsAgreeWithSingleRays) {
    Scene s = oneObject(makeSphere(1.0f, 64, 32));
    Accel accel(s);
    std::vector<Ray> rays;
    for (int i = 0; i < 16; ++i)
        rays.push_back(ray({-1.2f + 0.15f * i, 0.3f, 5.0f}, {0.01f * i, 0.0f, -1.0f}));
    Hit h8[8], h16[16];
    accel.intersect8(rays.data(), h8, 8);
    accel.intersect16(rays.data(), h16, 16);
    for (int i = 0; i < 16; ++i) {
        Hit one = accel.intersect(rays[size_t(i)]);
        EXPECT_EQ(h16[i].object, one.object) << i;
        if (one.valid()) {
            EXPECT_EQ(h16[i].triangle, one.triangle);
            EXPECT_EQ(h16[i].t, one.t);
        }
        if (i < 8) {
            EXPECT_EQ(h8[i].object, one.object);
        }
    }
    // A stream gives the same answers.
    std::vector<Hit> stream(rays.size());
    accel.intersectStream(rays.data(), stream.data(), rays.size(), true);
    for (size_t i = 0; i < rays.size(); ++i) {
        EXPECT_EQ(stream[i].object, h16[i].object) << i;
        EXPECT_EQ(stream[i].t, h16[i].t) << i;
    }
    // A partial packet leaves the rest alone and still answers the valid lanes.
    Hit part[16];
    accel.intersect16(rays.data(), part, 5);
    for (int i = 0; i < 5; ++i) EXPECT_EQ(part[i].object, h16[i].object);
}

// Two resolutions of hit i agree bit for bit (floats by their bytes: −0 and NaN payloads
// count).
void expectSameSurface(const SurfacePoint& a, const SurfacePoint& b, size_t i) {
    EXPECT_EQ(std::memcmp(&a.p, &b.p, sizeof a.p), 0) << i;
    EXPECT_EQ(std::memcmp(&a.ng, &b.ng, sizeof a.ng), 0) << i;
    EXPECT_EQ(std::memcmp(&a.ns, &b.ns, sizeof a.ns), 0) << i;
    EXPECT_EQ(std::memcmp(&a.uv, &b.uv, sizeof a.uv), 0) << i;
    EXPECT_EQ(a.frontFace, b.frontFace) << i;
    EXPECT_EQ(a.object, b.object) << i;
    EXPECT_EQ(a.triangle, b.triangle) << i;
    EXPECT_EQ(a.part, b.part) << i;
    EXPECT_EQ(a.material, b.material) << i;
}

// Each batch kernel (and surfaces(), whichever it picks) against surface(), bit for bit;
// every count from 1 to 17 too, so every partial group of four and of eight is seen.
void expectSurfacesMatch(const Accel& accel, const std::vector<Ray>& rays, const std::vector<Hit>& hits) {
    using Kernel = void (Accel::*)(const Ray*, const Hit*, SurfacePoint*, size_t) const;
    std::vector<std::pair<const char*, Kernel>> kernels = {{"surfaces", &Accel::surfaces},
                                                           {"surfacesSse2", &Accel::surfacesSse2}};
    if (Accel::avx2Available()) kernels.push_back({"surfacesAvx2", &Accel::surfacesAvx2});
    for (const auto& [name, kernel] : kernels) {
        for (size_t count : {rays.size(), size_t(1), size_t(3), size_t(5), size_t(7), size_t(9), size_t(17)}) {
            SCOPED_TRACE(std::string(name) + ", " + std::to_string(count) + " hits");
            const size_t offset = rays.size() > 40 ? 13 : 0;  // not at the start of a group
            const size_t n = count == rays.size() ? count : std::min(count, rays.size() - offset);
            const size_t first = count == rays.size() ? 0 : offset;
            std::vector<SurfacePoint> batch(n + 1);
            batch[n].object = 0xdeadbeefu;  // must stay untouched
            (accel.*kernel)(rays.data() + first, hits.data() + first, batch.data(), n);
            EXPECT_EQ(batch[n].object, 0xdeadbeefu) << "wrote past the end";
            for (size_t k = 0; k < n; ++k) {
                const size_t i = first + k;
                const SurfacePoint a = accel.surface(rays[i], hits[i]), &b = batch[k];
                expectSameSurface(a, b, i);
            }
        }
    }
}

// The batched hit resolution (SSE lanes) against the scalar one, bit for bit: rays from
// the camera and from points inside and around the teapot in every direction (front and
// back faces, the room's parts), misses, and a count that leaves a partial group.
TEST(Accel, SurfacesMatchSurfaceBitForBit) {
    Scene s = makeBuiltinScene("teapot-in-room");
    Accel accel(s);
    const Camera cam = s.viewpointPaths[0].at(0);
    std::vector<Ray> rays;
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 32; ++x) rays.push_back(primaryRay(cam, 32, 24, x + 0.25f, y + 0.75f));
    uint32_t state = 12345u;
    auto next = [&] {  // xorshift: fixed sequence
        state ^= state << 13, state ^= state >> 17, state ^= state << 5;
        return float(state >> 8) / 16777216.0f;
    };
    for (int i = 0; i < 1001; ++i) {
        Ray r;
        r.origin = {4.0f * next() - 2.0f, 3.5f * next(), 4.0f * next() - 2.0f};
        r.dir = glm::normalize(glm::vec3(next() - 0.5f, next() - 0.5f, next() - 0.5f) + 1e-6f);
        rays.push_back(r);
    }
    std::vector<Hit> hits(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) hits[i] = accel.intersect(rays[i]);
    hits[3] = Hit();  // misses in the middle of a group
    hits[rays.size() - 2] = Hit();
    int back = 0;
    for (size_t i = 0; i < rays.size(); ++i) back += hits[i].valid() && !accel.surface(rays[i], hits[i]).frontFace;
    EXPECT_GT(back, 10) << "no back faces exercised";
    expectSurfacesMatch(accel, rays, hits);
}

// The same on made-up hits: any object and triangle, barycentrics anywhere in the triangle
// (its edges and corners included), any ray and distance, misses scattered through. An
// extra object has vertex normals that cancel (the interpolated normal has length zero at
// the midpoint of an edge: the geometric-normal fallback) and normals against its winding
// (the flip).
TEST(Accel, SurfacesMatchSurfaceOnRandomHits) {
    Scene s = makeBuiltinScene("teapot-in-room");
    Mesh odd;
    odd.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    odd.normals = {{0, 0, 1}, {0, 0, -1}, {0, 0, -1}, {0, 0, -1}};
    odd.uvs = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    odd.indices = {0, 1, 2, 1, 3, 2};
    s.addObject("odd normals", s.addMesh(odd), 0);
    Accel accel(s);
    uint32_t state = 2463534242u;
    auto bits = [&] {  // xorshift: fixed sequence
        state ^= state << 13, state ^= state >> 17, state ^= state << 5;
        return state;
    };
    auto unit = [&] { return float(bits() >> 8) / 16777216.0f; };
    auto coordinate = [&] {  // now and then exactly 0, 1 or ½
        const uint32_t k = bits() % 16;
        return k == 0 ? 0.0f : k == 1 ? 1.0f : k == 2 ? 0.5f : unit();
    };
    std::vector<Ray> rays;
    std::vector<Hit> hits;
    for (int i = 0; i < 4000; ++i) {
        Ray r;
        r.origin = {8.0f * unit() - 4.0f, 8.0f * unit() - 4.0f, 8.0f * unit() - 4.0f};
        r.dir = glm::normalize(glm::vec3(unit() - 0.5f, unit() - 0.5f, unit() - 0.5f) + 1e-6f);
        Hit h;
        if (bits() % 20 != 0) {
            h.object = i % 7 == 0 ? uint32_t(s.objects.size() - 1) : bits() % uint32_t(s.objects.size());
            h.triangle = bits() % uint32_t(s.meshes[s.objects[h.object].mesh].triangleCount());
            h.u = coordinate();
            h.v = coordinate() * (1.0f - h.u);
            h.t = 10.0f * unit();
        }
        rays.push_back(r);
        hits.push_back(h);
    }
    int fallback = 0, flipped = 0;
    for (size_t i = 0; i < hits.size(); ++i) {
        if (!hits[i].valid() || hits[i].object != s.objects.size() - 1) continue;
        const SurfacePoint p = accel.surface(rays[i], hits[i]);
        fallback += p.ns == p.ng;
        flipped += p.ns != p.ng;
    }
    EXPECT_GT(fallback, 0) << "the zero-length shading normal was not exercised";
    EXPECT_GT(flipped, 0);
    expectSurfacesMatch(accel, rays, hits);
}

// The fused stream (trace, then resolve from Embree's records) against intersectStream and
// surface() of each hit, bit for bit: camera rays, rays from inside the room every way,
// rays from outside pointing away (misses), over several batches and a partial group.
TEST(Accel, StreamSurfacesMatchStreamThenSurface) {
    Scene s = makeBuiltinScene("teapot-in-room");
    Accel accel(s);
    const Camera cam = s.viewpointPaths[0].at(0);
    std::vector<Ray> rays;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 32; ++x) rays.push_back(primaryRay(cam, 32, 12, x + 0.5f, y + 0.5f));
    uint32_t state = 777u;
    auto next = [&] {
        state ^= state << 13, state ^= state >> 17, state ^= state << 5;
        return float(state >> 8) / 16777216.0f;
    };
    for (int i = 0; i < 205; ++i) {
        Ray r;
        const bool outside = i % 5 == 0;
        r.origin = outside ? glm::vec3(0.0f, 1.0f, 1000.0f)
                           : glm::vec3(4.0f * next() - 2.0f, 3.5f * next(), 4.0f * next() - 2.0f);
        glm::vec3 d(next() - 0.5f, next() - 0.5f, next() - 0.5f);
        if (outside) d.z = std::abs(d.z) + 0.1f;
        r.dir = glm::normalize(d + 1e-6f);
        rays.push_back(r);
    }
    for (bool coherent : {true, false}) {
        std::vector<Hit> hits(rays.size());
        accel.intersectStream(rays.data(), hits.data(), rays.size(), coherent);
        std::vector<SurfacePoint> fused(rays.size() + 1);
        fused.back().object = 0xdeadbeefu;
        accel.intersectStreamSurfaces(rays.data(), fused.data(), rays.size(), coherent);
        EXPECT_EQ(fused.back().object, 0xdeadbeefu) << "wrote past the end";
        int misses = 0;
        for (size_t i = 0; i < rays.size(); ++i) {
            const SurfacePoint a = accel.surface(rays[i], hits[i]), &b = fused[i];
            misses += !hits[i].valid();
            expectSameSurface(a, b, i);
        }
        EXPECT_GT(misses, 20);
    }
}

// Camera rays, random rays from inside and around the room every way (front and back
// faces, every part), rays from far outside pointing away (misses), and rays with a random
// short tfar (hits cut off, so misses of every kind).
std::vector<Ray> mixedRoomRays(const Scene& s, uint32_t seed) {
    const Camera cam = s.viewpointPaths[0].at(0);
    std::vector<Ray> rays;
    for (int y = 0; y < 30; ++y)
        for (int x = 0; x < 40; ++x) rays.push_back(primaryRay(cam, 40, 30, x + 0.5f, y + 0.5f));
    uint32_t state = seed;
    auto bits = [&] {  // xorshift: fixed sequence
        state ^= state << 13, state ^= state >> 17, state ^= state << 5;
        return state;
    };
    auto unit = [&] { return float(bits() >> 8) / 16777216.0f; };
    for (int i = 0; i < 5000; ++i) {
        Ray r;
        const bool outside = i % 11 == 0;
        r.origin = outside ? glm::vec3(0.0f, 1.0f, 1000.0f)
                           : glm::vec3(6.0f * unit() - 3.0f, 4.5f * unit() - 0.5f, 6.0f * unit() - 3.0f);
        glm::vec3 d(unit() - 0.5f, unit() - 0.5f, unit() - 0.5f);
        if (outside) d.z = std::abs(d.z) + 0.1f;
        r.dir = glm::normalize(d + 1e-6f);
        if (i % 7 == 0) r.tfar = 2.0f * unit();
        rays.push_back(r);
    }
    return rays;
}

// intersectSurface (trace and resolve from Embree's record in one call; with the Hit too)
// against intersect() then surface(), bit for bit, on mixedRoomRays.
TEST(Accel, IntersectSurfaceMatchesIntersectThenSurface) {
    Scene s = makeBuiltinScene("teapot-in-room");
    Accel accel(s);
    const std::vector<Ray> rays = mixedRoomRays(s, 4242u);
    int misses = 0, back = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
        const Hit h = accel.intersect(rays[i]);
        Hit h2;
        h2.t = -1.0f;  // must be overwritten, on a miss too
        const SurfacePoint a = accel.surface(rays[i], h), b = accel.intersectSurface(rays[i]);
        const SurfacePoint c = accel.intersectSurface(rays[i], h2);
        EXPECT_EQ(std::memcmp(&h, &h2, sizeof h), 0) << i;  // Hit has no padding
        misses += !h.valid();
        back += h.valid() && !a.frontFace;
        for (const SurfacePoint* fused : {&b, &c}) {
            expectSameSurface(a, *fused, i);
        }
    }
    EXPECT_GT(misses, 100) << "misses not exercised";
    EXPECT_GT(back, 100) << "back faces not exercised";
}


// intersectSurfaces (rays traversed one by one, resolved in groups) against
// intersectSurface of each ray, bit for bit, Hit and point, on mixedRoomRays: the whole
// set and counts around the group size, starting inside a group; with and without the
// Hit output. Under Accel.WithoutAvx2 the groups take the SSE2 kernel.
TEST(Accel, IntersectSurfacesMatchIntersectSurfaceOfEachRay) {
    Scene s = makeBuiltinScene("teapot-in-room");
    Accel accel(s);
    const std::vector<Ray> rays = mixedRoomRays(s, 9001u);
    const size_t group = Accel::kSurfaceGroup;
    for (size_t count : {rays.size(), size_t(1), group - 1, group, group + 1, 3 * group + 5}) {
        for (bool withHits : {true, false}) {
            SCOPED_TRACE(std::to_string(count) + " rays, " + (withHits ? "with" : "without") + " hits");
            const size_t offset = count == rays.size() ? 0 : 7;
            std::vector<SurfacePoint> points(count + 1);
            std::vector<Hit> hits(count + 1);
            for (Hit& h : hits) h.t = -1.0f;  // each must be overwritten, on a miss too
            points.back().object = hits.back().object = 0xdeadbeefu;
            accel.intersectSurfaces(rays.data() + offset, points.data(), count,
                                    withHits ? hits.data() : nullptr);
            EXPECT_EQ(points.back().object, 0xdeadbeefu) << "wrote past the end";
            EXPECT_EQ(hits.back().object, 0xdeadbeefu) << "wrote past the end";
            int misses = 0, back = 0;
            for (size_t i = 0; i < count; ++i) {
                Hit h;
                const SurfacePoint a = accel.intersectSurface(rays[offset + i], h);
                if (withHits) {
                    EXPECT_EQ(std::memcmp(&h, &hits[i], sizeof h), 0) << i;  // no padding
                }
                misses += !h.valid();
                back += h.valid() && !a.frontFace;
                expectSameSurface(a, points[i], i);
            }
            if (count == rays.size()) {
                EXPECT_GT(misses, 100) << "misses not exercised";
                EXPECT_GT(back, 100) << "back faces not exercised";
            }
        }
    }
}

}  // namespace
}  // namespace rg::ray
