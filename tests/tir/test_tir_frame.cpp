// The tir frame on the emulated geforce8800: the same bytes on both paths and any thread
// count; the passes of Figure 2; the reference tracer against closed forms; bad input.
#include <gtest/gtest.h>

#include <cstring>

#include "core/error.h"
#include "raycore/accel.h"
#include "raycore/shapes.h"
#include "raycore/tracer_refract_tir.h"
#include "tir_renderer.h"

namespace rg::tir {
namespace {

std::vector<uint8_t> frameBytes(const TirRenderer& r) {
    const tex::Texture& t = r.frameTexture();
    const Rgba8* p = const_cast<tex::Texture&>(t).renderData8(0, 0);
    const size_t n = size_t(t.levelSize(0)[0]) * size_t(t.levelSize(0)[1]) * 4;
    std::vector<uint8_t> out(n);
    std::memcpy(out.data(), p, n);
    return out;
}

TEST(TirFrame, SameBytesOnBothPathsAndAnyThreadCount) {
    for (const char* name : {"kitchen", "prism"})
        for (Method method : {Method::Ours, Method::Wyman05}) {
            TirScene scene = makeTirScene(name);
            TirSettings s;
            s.width = 80;
            s.height = 64;
            s.mapScale = 0.5f;
            s.frontAndBack = true;
            s.envSize = 32;
            s.method = method;
            std::vector<uint8_t> first;
            for (auto [path, threads] : {std::pair{Path::Fast, 1}, {Path::Fast, 2}, {Path::Fast, 3}, {Path::Reference, 1}}) {
                TirRenderer r(scene, threads, path, 64);
                TirFrame f = r.render(scene.camera, s);
                ASSERT_EQ(f.passes.size(), 4u);
                EXPECT_GT(f.refractiveFragments, 100);
                if (first.empty()) first = frameBytes(r);
                else EXPECT_EQ(frameBytes(r), first) << name << " " << methodName(method) << " threads " << threads;
            }
        }
}

TEST(TirFrame, PassesWriteWhatFigure2Shows) {
    TirScene scene = makeTirScene("prism");
    TirRenderer r(scene, 2, Path::Fast, 64);
    TirSettings s;
    s.width = s.height = 64;
    s.envSize = 32;
    r.render(scene.camera, s);
    const tex::Texture& back = r.backMap();
    const tex::Texture& front = r.frontMap();
    const glm::vec4* b = const_cast<tex::Texture&>(back).renderDataF(0, 0);
    const glm::vec4* f = const_cast<tex::Texture&>(front).renderDataF(0, 0);
    int covered = 0;
    for (int i = 0; i < 64 * 64; ++i) {
        EXPECT_EQ(b[i].w >= 1.0f, f[i].w >= 1.0f) << i;  // the same silhouette
        if (f[i].w >= 1.0f) continue;
        ++covered;
        EXPECT_LE(f[i].w, b[i].w) << i;   // the front face is nearer than the back face (equal on edges)
        EXPECT_GT(f[i].z, -0.05f) << i;   // front normals face the eye (+z in eye space)…
        EXPECT_LT(b[i].z, 0.05f) << i;    // … back normals away from it
    }
    EXPECT_GT(covered, 500);
}

TEST(TirFrame, BadSettingsAreErrorsNamingThem) {
    TirScene scene = makeTirScene("prism");
    TirRenderer r(scene, 1, Path::Fast, 16);
    TirSettings s;
    s.width = s.height = 16;
    auto expectError = [&](TirSettings bad, const char* words) {
        try {
            r.render(scene.camera, bad);
            FAIL() << words;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
    };
    TirSettings b = s;
    b.bounces = -1;
    expectError(b, "bounces -1");
    b.bounces = kMaxBounces + 1;
    expectError(b, "bounces");
    b = s;
    b.itersFirst = 0;
    expectError(b, "iterations 0");
    b = s;
    b.mapScale = 0.0f;
    expectError(b, "map scale");
    b = s;
    b.width = 100000;
    expectError(b, "frame");
    TirScene badIor = makeTirScene("prism");
    badIor.scene.materials.at(badIor.scene.objects.at(badIor.refractor).material).ior = std::nanf("");
    EXPECT_THROW(TirRenderer(badIor, 1), Error);
    badIor.scene.materials.at(badIor.scene.objects.at(badIor.refractor).material).ior = -1.0f;
    EXPECT_THROW(refractorIor(badIor), Error);
    EXPECT_THROW(makeTirScene("nonesuch"), Error);
}

// With no absorption, no Fresnel split and a white world, every path ends in the white
// environment: the reference image is exactly 1 everywhere, TIR or not (the TIR test of
// raycore's glass-cube scene, for this tracer).
TEST(TirReference, AWhiteWorldThroughClearGlassIsWhite) {
    TirScene scene = makeTirScene("prism");
    scene.scene.environment = ray::Environment{};
    scene.scene.environment.kind = ray::EnvironmentKind::Constant;
    scene.scene.environment.color = glm::vec3(1.0f);
    ASSERT_EQ(scene.scene.objects.size(), 1u);  // the block alone: nothing else to hit
    ray::Accel accel(scene.scene);
    ray::RenderOptions ro;
    ro.width = ro.height = 48;
    for (int segments : {1, 3, 10}) {
        ray::TirPathOptions po;
        po.refractor = scene.refractor;
        po.maxSegments = segments;
        const ray::TirImages ti = ray::renderTirPaths(accel, nullptr, scene.camera, ro, po);
        double tirPixels = 0, refractorPixels = 0;
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 48; ++x) {
                EXPECT_EQ(ti.color.rgb(x, y), glm::vec3(1.0f)) << x << "," << y;
                refractorPixels += ti.refractor.at(x, y, 0);
                tirPixels += ti.tir.at(x, y, 0);
                EXPECT_LE(ti.segments.at(x, y, 0), float(segments));
            }
        EXPECT_GT(refractorPixels, 100);
        if (segments > 1) {
            EXPECT_GT(tirPixels, 0.2 * refractorPixels) << "the prism reflects totally";
        }
    }
    // Without leaving after the budget, paths still inside are black: the budget matters.
    ray::TirPathOptions trapped;
    trapped.refractor = scene.refractor;
    trapped.maxSegments = 1;
    trapped.leaveAfterBudget = false;
    const ray::TirImages ti = ray::renderTirPaths(accel, nullptr, scene.camera, ro, trapped);
    int black = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) black += ti.color.rgb(x, y) == glm::vec3(0.0f) ? 1 : 0;
    EXPECT_GT(black, 0);
}

// A 45°-45°-90° glass prism is a retroreflector: a ray entering the hypotenuse head-on
// meets each leg at 45°, past the critical angle sin⁻¹(1/1.5) = 41.8°, reflects totally
// twice and leaves through the hypotenuse again: three segments, two reflections, on a
// path traced by hand: in at (0.7, 0.3), TIR at (0.4, 0) and (0, 0.4), out at (0.3, 0.7).
TEST(TirReference, ARightAnglePrismReflectsTotallyTwice) {
    ray::Scene scene;
    scene.name = "prism-retroreflector";
    ray::Material glass;
    glass.name = "glass";
    glass.type = ray::MaterialType::Glass;
    glass.ior = 1.5f;
    const uint32_t m = scene.addMaterial(glass);
    scene.addObject("prism", scene.addMesh(ray::makeExtrusion({{0, 0}, {1, 0}, {0, 1}}, 1.0f)), m);
    scene.environment.kind = ray::EnvironmentKind::Gradient;
    ray::Accel accel(scene);
    const glm::vec3 in(-0.70710678f, -0.70710678f, 0.0f);
    for (float along : {0.2f, 0.35f, 0.5f, 0.65f, 0.8f}) {  // where the ray meets the hypotenuse
        ray::Ray r;
        r.dir = in;
        r.origin = glm::vec3(along, 1.0f - along, 0.1f) - in * 2.0f;
        ray::RayCounts counts;
        ray::TirPathOptions o;
        o.refractor = 0;
        const ray::TirPath p = ray::traceTirPath(accel, nullptr, r, o, counts);
        EXPECT_TRUE(p.hitRefractor) << along;
        EXPECT_EQ(p.tirCount, 2) << along;
        EXPECT_EQ(p.segments, 3) << along;
        // Seen from the eye (the ray's origin, beyond the hypotenuse) both legs face away and
        // the hypotenuse faces it: the two reflections lie in the back map, the exit in the
        // front map (Figure 6's question, answered by hand).
        EXPECT_EQ(p.insideHits, 3) << along;
        EXPECT_EQ(p.backFacing, 0b011u) << along;
        // It leaves back towards where it came from: the gradient's colour of −in.
        EXPECT_EQ(p.color, scene.environment.lookup(-in)) << along;
    }
}

}  // namespace
}  // namespace rg::tir
