// The geforce8800 programs of Dancsik & Minarik: one vertex program for every mesh pass,
// the sky behind everything, diffuse surfaces (the board, with its light map), the normal +
// distance pass of the refractor distance maps, and the glass and mirror objects through
// their impostors (impostor_shading.h). Fragment programs are quad programs written for any
// context (rasterizer/quad_program.h), so the fast path runs them on quad groups and the
// reference path lane by lane. Programs are plain data: their bytes are their constants.
//
// Every pass writes RGBA: the frame (RGBA8) its colour with w = 1; an environment distance
// impostor (RGBA16F cube) the radiance with w = the distance from its reference point
// (002 §3: "the distances from the reference point coded into the alpha channel"); a
// refractor distance map the normal with w = the distance from the mesh's centre.
#pragma once

#include <glm/mat4x4.hpp>

#include <span>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "impostor_grid.h"
#include "impostor_shading.h"
#include "rasterizer/program.h"
#include "rasterizer/programmable_device.h"
#include "rasterizer/quad_program.h"

namespace rg::impostors {

// Units of the glass programs: the object's environment impostor and refractor map, the
// mover's (§5.2).
constexpr int kUnitEnv = 0, kUnitRefractor = 1, kUnitMoverEnv = 2, kUnitMoverRefractor = 3;
// Units of the diffuse program: the albedo texture, the light maps of the static pieces
// and of the mover (§7: "Two different light maps are used").
constexpr int kUnitAlbedo = 0, kUnitLightMap = 1, kUnitLightMapMover = 2;
// The distance written where the sky shows: far beyond the scene, within binary16 (its
// largest finite value is 65504).
constexpr float kSkyDistance = 4096.0f;

// A vertex of every mesh the passes draw (world space, or the mesh's model space for the
// refractor maps).
struct ImpostorVertex {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    glm::vec2 uv{0.0f};
};

// Position by the view-projection matrix. Varyings: 0 position (w = 1), 1 normal, 2 uv.
struct WorldVP {
    static constexpr int kVaryings = 3;
    glm::mat4 viewProj{1.0f};
    glm::vec4 operator()(const ImpostorVertex& v, raster::Varyings& out) const {
        out[0] = glm::vec4(v.position, 1.0f);
        out[1] = glm::vec4(v.normal, 0.0f);
        out[2] = glm::vec4(v.uv, 0.0f, 0.0f);
        return viewProj * glm::vec4(v.position, 1.0f);
    }
};

// A triangle given in clip coordinates (x, y, z; w = 1): full-screen passes.
struct ScreenVP {
    static constexpr int kVaryings = 0;
    glm::vec4 operator()(const ImpostorVertex& v, raster::Varyings&) const {
        return {v.position.x, v.position.y, v.position.z, 1.0f};
    }
};

// The sky behind everything, along each pixel centre's view ray: eye direction
// (ndc_x·invPx, ndc_y·invPy, −1) turned to world space by `toWorld` (rows), read from the
// world's cube map; w = kSkyDistance (an impostor) or 1 (the frame).
struct SkyFP {
    static constexpr int kVaryings = 0;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b1;
    static constexpr bool kWritesDepth = false;
    float toWorld[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    float invPx = 1, invPy = 1, invWidth = 1, invHeight = 1;
    int32_t writeDistance = 0;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 fc = q.fragCoord();
        const F ndcX = fc.x * F(2.0f * invWidth) - F(1.0f), ndcY = F(1.0f) - fc.y * F(2.0f * invHeight);
        const V3 d = mul3(toWorld, V3(ndcX * F(invPx), ndcY * F(invPy), F(-1.0f)));
        const V4 t = q.sampleLevel(0, V4(d.x, d.y, d.z, F(0.0f)), F(0.0f), q.active());
        q.output(0, V4(t.x, t.y, t.z, F(writeDistance ? kSkyDistance : 1.0f)));
    }
};

// The board's texture space: a vertex at uv (u, v) lands on the light map's texel there
// (clip x = 2u − 1, y = 1 − 2v: row 0 at the top, as the sampler reads t = 0). Varyings as
// WorldVP's.
struct TextureSpaceVP {
    static constexpr int kVaryings = 3;
    glm::vec4 operator()(const ImpostorVertex& v, raster::Varyings& out) const {
        out[0] = glm::vec4(v.position, 1.0f);
        out[1] = glm::vec4(v.normal, 0.0f);
        out[2] = glm::vec4(v.uv, 0.0f, 0.0f);
        return {v.uv.x * 2.0f - 1.0f, 1.0f - v.uv.y * 2.0f, 0.5f, 1.0f};
    }
};

// A point by a matrix of constants (glm's column-major layout), w = 1.
template <class F>
Vec4L<F> mulPoint(const glm::mat4& m, const Vec3L<F>& p) {
    auto row = [&](int r) { return ((p.x * F(m[0][r]) + p.y * F(m[1][r])) + p.z * F(m[2][r])) + F(m[3][r]); };
    return {row(0), row(1), row(2), row(3)};
}

// §7's shadows resolved into the board's light map: per light i, the 2×2 percentage-closer
// visibility from its shadow map (unit i, Depth32F, LINEAR: sampleCompare) at the texel's
// world point, into channel i (RGBA8).
struct LightMapFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b11;
    static constexpr bool kWritesDepth = false;
    glm::mat4 lightViewProj[2] = {glm::mat4(1.0f), glm::mat4(1.0f)};
    int32_t lights = 0;
    float bias = 1e-5f;  // window z: the board is no caster, so only the pieces' own
                         // bottoms (at the board's height) need it
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0);
        const V3 p(pos.x, pos.y, pos.z);
        F vis[2] = {F(1.0f), F(1.0f)};
        for (int i = 0; i < lights && i < 2; ++i) {
            const V4 c = mulPoint(lightViewProj[i], p);
            const F inv = F(1.0f) / c.w;
            const F u = F(0.5f) + F(0.5f) * (c.x * inv), v = F(0.5f) - F(0.5f) * (c.y * inv);
            vis[i] = q.sampleCompare(i, V4(u, v, F(0.0f), F(0.0f)), c.z * inv - F(bias), q.active());
        }
        q.output(0, V4(vis[0], vis[1], F(0.0f), F(1.0f)));
    }
};

// Diffuse surfaces as raycore's diffuseLighting lights them, albedo·texture·(ambient +
// Σ I_i·max(n·l_i, 0)·visibility_i), n turned to the viewer, no fall-off. The board's top
// face reads the visibility of light i from its light maps (channel i of units 1 and 2,
// multiplied: the static pieces' and the mover's shadows); other surfaces are unshadowed.
struct DiffuseFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b111;
    static constexpr bool kWritesDepth = false;
    static constexpr int kMaxLights = 2;
    float eye[3] = {0, 0, 0};
    float albedo[3] = {1, 1, 1};
    float ambient[3] = {0, 0, 0};
    int32_t lights = 0;
    float lightPos[kMaxLights][3] = {};
    float lightIntensity[kMaxLights][3] = {};
    int32_t writeDistance = 0;
    int32_t lightMapped = 0;  // the light map applies to faces whose normal is +y
    template <class Q>
    void operator()(Q& q) const {
        shade(q, [](const auto&, auto&) {});
    }
    // The lighting, with addLight(top, light) called after the lights and before the albedo:
    // the hook through which CausticDiffuseFP (impostor_caustics.h) adds the caustic
    // irradiance on the board's top face, so that both programs light the board alike.
    template <class Q, class AddLight>
    void shade(Q& q, AddLight&& addLight) const {
        using F = typename Q::Float;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0), nrm = q.varying(1);
        const V3 p(pos.x, pos.y, pos.z);
        const V3 e = splat3<F>(eye);
        const V3 view = p - e;
        const V3 n = facing(normalize3(V3(nrm.x, nrm.y, nrm.z)), view);
        const V4 visStatic = q.sample(kUnitLightMap, 2), visMover = q.sample(kUnitLightMapMover, 2);
        const V4 vis(visStatic.x * visMover.x, visStatic.y * visMover.y, F(1.0f), F(1.0f));
        const auto top = nrm.y > F(0.5f);
        V3 light = splat3<F>(ambient);
        for (int i = 0; i < lights; ++i) {
            const V3 l = normalize3(splat3<F>(lightPos[i]) - p);
            F c = max(dot3(n, l), F(0.0f));
            if (lightMapped) c = c * select(top, i == 0 ? vis.x : vis.y, F(1.0f));
            light = light + splat3<F>(lightIntensity[i]) * c;
        }
        addLight(top, light);
        const V4 t = q.sample(kUnitAlbedo, 2);
        const V3 a = V3(F(albedo[0]) * t.x, F(albedo[1]) * t.y, F(albedo[2]) * t.z);
        const F w = writeDistance ? length3(view) : F(1.0f);
        q.output(0, V4(a.x * light.x, a.y * light.y, a.z * light.z, w));
    }
};

// The refractor distance map of a mesh (002 §3): the unit normal and the distance from the
// map's centre (model space).
struct NormalDistanceFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    float centre[3] = {0, 0, 0};
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0), nrm = q.varying(1);
        const V3 n = normalize3(V3(nrm.x, nrm.y, nrm.z));
        q.output(0, V4(n.x, n.y, n.z, length3(V3(pos.x, pos.y, pos.z) - splat3<F>(centre))));
    }
};

// Depth only (the shadow maps of §7): no colour target.
struct DepthOnlyFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    template <class Q>
    void operator()(Q&) const {}
};

// A glass or mirror object through its impostors (002 §3, §5). kMover: a static object's
// rays also search the mover's refractor map from outside (§4.1, §5.2). kDiagnostics:
// targets 1–3 (RGBA32F) get the reflected ray's direction and environment hit distance,
// the exit point and its ray's hit distance, the exit direction and searches + 64·flags
// (Figure 5's counts, Figure 9's class map).
template <bool kMover, bool kDiagnostics>
struct GlassFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = kDiagnostics ? 0b1111 : 0b1;
    static constexpr uint32_t kUnits = kMover ? 0b1111 : 0b11;
    static constexpr bool kWritesDepth = false;
    // The diagnostic variants render the report's analysis frames, never a timed one: the
    // SSE2 kernel (programmable_device.h, kWideKernel), which halves these kernels' compile.
    static constexpr bool kWideKernel = !kDiagnostics;
    // Explicit-λ fetches only: the fast path may fill a quad with pixels of several of the
    // pieces' one- or two-pixel triangles (programmable_device.h, kLaneIndependent).
    static constexpr bool kLaneIndependent = true;
    // Four quads a group on the AVX2 kernel, not eight: the searches' values, four
    // registers wide at eight quads, spilled most of the time (programmable_device.h,
    // kWideQuads).
    static constexpr int kWideQuads = 4;
    GlassConstants k;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using M = typename Q::Mask;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0), nrm = q.varying(1);
        const M live = q.active();
        auto cube = [&q](int unit) {
            return [&q, unit](const V3& d, const M& m) {
                return q.sampleLevel(unit, V4(d.x, d.y, d.z, F(0.0f)), F(0.0f), m);
            };
        };
        const V3 P(pos.x, pos.y, pos.z);
        const V3 view = P - splat3<F>(k.eye);
        const V3 V = normalize3(view);
        Shaded<F> s = shadeOwn(k.self, k.iterations, P, V3(nrm.x, nrm.y, nrm.z), V, live, cube(kUnitEnv),
                               cube(kUnitRefractor));
        if constexpr (kMover) {
            // Figure 5: the static hits (1, 3) against the mover (4), the nearest wins.
            throughMover(k.mover, k.iterations, P, s.reflDir, s.reflD, live, s.reflColour, s.searches, s.moverFlags,
                         1.0f, cube(kUnitMoverEnv), cube(kUnitMoverRefractor));
            if (!k.self.mirror)
                throughMover(k.mover, k.iterations, s.exitOrigin, s.exitDir, s.exitD, live, s.exitColour, s.searches,
                             s.moverFlags, 2.0f, cube(kUnitMoverEnv), cube(kUnitMoverRefractor));
            s.colour = combine(k.self, s);
        }
        const F w = k.writeDistance ? length3(view) : F(1.0f);
        q.output(0, V4(s.colour.x, s.colour.y, s.colour.z, w));
        if constexpr (kDiagnostics) {
            q.output(1, V4(s.reflDir.x, s.reflDir.y, s.reflDir.z, s.reflD));
            q.output(2, V4(s.exitOrigin.x, s.exitOrigin.y, s.exitOrigin.z, s.exitD));
            q.output(3, V4(s.exitDir.x, s.exitDir.y, s.exitDir.z, s.searches + s.moverFlags * F(64.0f)));
        }
    }
};

// Mode A (002 §4.2, impostor_grid.h): a glass object with refractor maps only. Units: the
// refractor maps 0–6, the board's albedo and light maps, the sky, the grid's occupancy.
struct GridFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0xFFF;
    static constexpr bool kWritesDepth = false;
    static constexpr bool kLaneIndependent = true;  // explicit-λ fetches only, as GlassFP
    static constexpr int kWideQuads = 4;          // as GlassFP
    GridConstants g;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using M = typename Q::Mask;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0), nrm = q.varying(1);
        const M live = q.active();
        auto fetch = [&q](int unit, const V4& c, const M& m) { return q.sampleLevel(unit, c, F(0.0f), m); };
        const ObjectFrame& self = g.frame[g.self];
        const int unit = g.map[g.self];
        auto fetchOwn = [&q, unit](const V3& d, const M& m) {
            return q.sampleLevel(unit, V4(d.x, d.y, d.z, F(0.0f)), F(0.0f), m);
        };
        const V3 P(pos.x, pos.y, pos.z);
        const V3 V = normalize3(P - splat3<F>(g.eye));
        F searches(0.0f);
        V3 colour;
        if (self.mirror) {
            const V3 r = reflect3(V, facing(normalize3(V3(nrm.x, nrm.y, nrm.z)), V));
            colour = gridRadiance(g, P, r, live, searches, fetch) * splat3<F>(self.reflectance);
        } else {
            const GlassPaths<F, M> p = tracePaths(self, g.iterations, P, V3(nrm.x, nrm.y, nrm.z), V, live, fetchOwn);
            searches = p.searches;
            const V3 cr = gridRadiance(g, p.reflOrigin, p.reflDir, live, searches, fetch);
            const V3 ct = gridRadiance(g, p.exitOrigin, p.exitDir, live, searches, fetch);
            colour = cr * p.fresnel + (ct * p.transmit) * (F(1.0f) - p.fresnel);
        }
        q.output(0, V4(colour.x, colour.y, colour.z, F(1.0f)));
    }
};

// Registers every program above under "impostors/…" (program_registry.h); idempotent.
void registerImpostorPrograms();

// A triangle-list draw of one of the programs above. Defined, and the programs' kernels
// instantiated, once in impostor_programs.cpp (the glass programs' kernels take minutes to
// compile; every other file only calls them).
template <class VP, class FP>
void drawTriangles(raster::ProgrammableDevice& device, const VP& vp, const FP& fp,
                   std::span<const ImpostorVertex> vertices, std::span<const uint32_t> indices = {});

}  // namespace rg::impostors
