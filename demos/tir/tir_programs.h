// The geforce8800 programs of Davis & Wyman 2007 (004 §3, Figure 2): one vertex program for
// every pass, the fragment programs of the four passes, and the Wyman 2005 baseline.
// Fragment programs are quad programs written for any context (rasterizer/quad_program.h),
// so the fast path runs them on quad groups and the reference path lane by lane. Programs
// are plain data: their bytes are their constants.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "rasterizer/program.h"
#include "rasterizer/quad_program.h"
#include "tir_search.h"

namespace rg::tir {

// A vertex of every mesh the passes draw (world space). dN: Wyman 2005's precomputed
// distance to the far side along −N (refractor only; 0 elsewhere).
struct TirVertex {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    glm::vec2 uv{0.0f};
    float dN = 0.0f;
};

// World → eye by the view matrix, eye → clip by the projection written as the search
// writes it (toClip), so a map's texel and the search's projection of a point agree.
// Varyings: 0 eye position (w = 1), 1 eye normal, 2 (u, v, dN, 0).
struct EyeVP {
    static constexpr int kVaryings = 3;
    glm::mat4 view{1.0f};
    float px = 1, py = 1, pz = -1, pw = 0;
    glm::vec4 operator()(const TirVertex& v, raster::Varyings& out) const {
        const glm::vec4 eye = view * glm::vec4(v.position, 1.0f);
        const glm::vec4 n = view * glm::vec4(v.normal, 0.0f);
        out[0] = glm::vec4(eye.x, eye.y, eye.z, 1.0f);
        out[1] = glm::vec4(n.x, n.y, n.z, 0.0f);
        out[2] = glm::vec4(v.uv.x, v.uv.y, v.dN, 0.0f);
        return {eye.x * px, eye.y * py, eye.z * pz + pw, -eye.z};
    }
};

// A triangle given in clip coordinates (x, y, z; w = 1): full-screen passes. The
// environment is drawn at z = 1 − 2⁻²⁰, behind every surface (far is fitted 2 % beyond the
// farthest vertex, whose window z stays below 1 − 10⁻⁵), so that with the depth test the
// early test skips its program wherever geometry was drawn.
struct ScreenVP {
    static constexpr int kVaryings = 0;
    glm::vec4 operator()(const TirVertex& v, raster::Varyings&) const {
        return {v.position.x, v.position.y, v.position.z, 1.0f};
    }
};

// The environment behind everything, along each pixel centre's view ray: eye direction
// (ndc_x/px, ndc_y/py, −1) from the pixel centre, turned to world space.
struct EnvFP {
    static constexpr int kVaryings = 0;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b1;
    static constexpr bool kWritesDepth = false;
    SearchConstants k;
    float invWidth = 1, invHeight = 1;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 fc = q.fragCoord();
        const F ndcX = fc.x * F(2.0f * invWidth) - F(1.0f), ndcY = F(1.0f) - fc.y * F(2.0f * invHeight);
        const V3 d(ndcX * F(k.invPx), ndcY * F(k.invPy), F(-1.0f));
        const V3 w = eyeToWorld(k, d);
        const V4 t = q.sampleLevel(0, V4(w.x, w.y, w.z, F(0.0f)), F(0.0f), q.active());
        q.output(0, V4(t.x, t.y, t.z, F(1.0f)));
    }
};

// Pass 4's background when the maps have the frame's size: pass 3's nearby map copied
// texel for texel (point sampled at the pixel centre), so the background is not drawn twice.
struct CopyFP {
    static constexpr int kVaryings = 0;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b1;
    static constexpr bool kWritesDepth = false;
    float invWidth = 1, invHeight = 1;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V4 = typename Q::Vec4;
        const V4 fc = q.fragCoord();
        const V4 t = q.sampleLevel(0, V4(fc.x * F(invWidth), fc.y * F(invHeight), F(0.0f), F(0.0f)), F(0.0f), q.active());
        q.output(0, V4(t.x, t.y, t.z, F(1.0f)));
    }
};

// Passes 1 and 2 (Figure 2): the refractor's back or front faces as eye-space normal and
// linear depth −z/far in one RGBA16F texel. Linear depth keeps binary16's 11 bits of
// precision relative to the depth itself (about 1/2048 of the distance), where window z,
// crowded towards 1 by the perspective divide, would keep almost none.
struct NormalDepthFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    float invFar = 0.01f;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0), nrm = q.varying(1);
        const V3 n = normalize3(V3(nrm.x, nrm.y, nrm.z));
        q.output(0, V4(n.x, n.y, n.z, -pos.z * F(invFar)));
    }
};

// Pass 3 and the background of pass 4: nearby diffuse geometry lit as raycore lights it
// without shadows, albedo·(ambient + Σ I·max(0, n·l)) with n turned to the viewer and no
// fall-off; the albedo texture on unit 0 (a 1×1 white texture for plain colours). w: the
// linear depth (pass 3's map) or 1 (the framebuffer).
struct NearbyFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b1;
    static constexpr bool kWritesDepth = false;
    static constexpr int kMaxLights = 4;
    glm::vec3 albedo{1.0f};
    glm::vec3 ambient{0.0f};
    int32_t lights = 0;
    glm::vec3 lightEye[kMaxLights]{};
    glm::vec3 lightIntensity[kMaxLights]{};
    float invFar = 0.01f;
    int32_t depthInAlpha = 1;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0), nrm = q.varying(1);
        const V3 p(pos.x, pos.y, pos.z);
        const V3 n = facing(normalize3(V3(nrm.x, nrm.y, nrm.z)), p);
        V3 e(F(ambient.x), F(ambient.y), F(ambient.z));
        for (int i = 0; i < lights; ++i) {
            const V3 l = normalize3(V3(F(lightEye[i].x), F(lightEye[i].y), F(lightEye[i].z)) - p);
            const F c = max(dot3(n, l), F(0.0f));
            e = e + V3(F(lightIntensity[i].x), F(lightIntensity[i].y), F(lightIntensity[i].z)) * c;
        }
        const V4 t = q.sample(0, 2);
        const V3 a(F(albedo.x) * t.x, F(albedo.y) * t.y, F(albedo.z) * t.z);
        q.output(0, V4(a.x * e.x, a.y * e.y, a.z * e.z, depthInAlpha ? -pos.z * F(invFar) : F(1.0f)));
    }
};

// Pass 4: the refractor's front faces through the search (tir_search.h). Units: back map,
// front map, nearby map (point-sampled RGBA16F), environment (RGBA32F cube, bilinear).
struct TirFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b1111;
    static constexpr bool kWritesDepth = false;
    SearchConstants k;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using M = typename Q::Mask;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0), nrm = q.varying(1);
        const M live = q.active();
        auto map = [&q](int unit) {
            return [&q, unit](const F& u, const F& v, const M& m) {
                return q.sampleLevel(unit, V4(u, v, F(0.0f), F(0.0f)), F(0.0f), m);
            };
        };
        auto env = [&q](const V3& d, const M& m) {
            const V4 t = q.sampleLevel(kUnitEnv, V4(d.x, d.y, d.z, F(0.0f)), F(0.0f), m);
            return V3(t.x, t.y, t.z);
        };
        const PathState<F, M> st =
            traceInside<F, M>(k, V3(pos.x, pos.y, pos.z), V3(nrm.x, nrm.y, nrm.z), live, map(kUnitBack), map(kUnitFront));
        const V3 c = exitColor<F, M>(k, st.origin, st.dir, live, map(kUnitNearby), env);
        q.output(0, V4(c.x, c.y, c.z, F(1.0f)));
    }
};

// The baseline (Wyman 2005, "An approximate image-space approach for interactive
// refraction", as 004 §3 and Figure 5 describe it): one exit point P2 = P1 + d̃·T1 with
// d̃ = (θt/θi)·d_V + (1 − θt/θi)·d_N, d_V the front-to-back distance along the view ray at
// this pixel (back map), d_N the precomputed distance along −N (varying 2's z); the normal
// at P2 from the back map, refraction out (reflection under TIR, no further search), then
// the same exit lookup as ours.
struct Wyman05FP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = 0b1;
    static constexpr uint32_t kUnits = 0b1111;
    static constexpr bool kWritesDepth = false;
    SearchConstants k;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using M = typename Q::Mask;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 pos = q.varying(0), nrm = q.varying(1), extra = q.varying(2);
        const M live = q.active();
        const V3 p(pos.x, pos.y, pos.z);
        const V3 view = normalize3(p);
        const V3 n = facing(normalize3(V3(nrm.x, nrm.y, nrm.z)), view);
        M tir;
        const V3 t1 = refractOrReflect(view, n, 1.0f / k.eta, tir);
        auto fetch = [&q, &live](int unit, const Clip<F>& c) {
            F u, v;
            mapCoords(c.x, c.y, c.w, u, v);
            return q.sampleLevel(unit, V4(u, v, F(0.0f), F(0.0f)), F(0.0f), live);
        };
        const V4 backHere = fetch(kUnitBack, toClip(k, p));
        const F dV = max(backHere.w * F(k.far) - (-p.z), F(0.0f));
        const F thetaI = acosCg(-dot3(view, n)), thetaT = acosCg(-dot3(t1, n));
        const F ratio = select(thetaI > F(1e-4f), thetaT / thetaI, F(1.0f));
        const F dist = ratio * dV + (F(1.0f) - ratio) * extra.z;
        const V3 p2 = p + t1 * dist;
        const V4 backThere = fetch(kUnitBack, toClip(k, p2));
        M reflects;
        const V3 n2 = facing(normalize3(V3(backThere.x, backThere.y, backThere.z)), t1);
        const V3 t2 = refractOrReflect(t1, n2, k.eta, reflects);
        auto map = [&q](int unit) {
            return [&q, unit](const F& u, const F& v, const M& m) {
                return q.sampleLevel(unit, V4(u, v, F(0.0f), F(0.0f)), F(0.0f), m);
            };
        };
        auto env = [&q](const V3& d, const M& m) {
            const V4 t = q.sampleLevel(kUnitEnv, V4(d.x, d.y, d.z, F(0.0f)), F(0.0f), m);
            return V3(t.x, t.y, t.z);
        };
        const V3 c = exitColor<F, M>(k, p2, t2, live, map(kUnitNearby), env);
        q.output(0, V4(c.x, c.y, c.z, F(1.0f)));
    }
};

// Registers every program above under "tir/…" (program_registry.h); idempotent.
void registerTirPrograms();

}  // namespace rg::tir
