// The geforce8800 program of a glass object whose refracted ray leaves through its refractor
// height map (002 §6, impostor_height_shading.h) instead of its refractor distance map
// (GlassFP, impostor_programs.h). Its kernels are instantiated in impostor_height_programs.cpp,
// apart from impostor_programs.cpp's, so that neither file's minutes of compiling wait on the
// other.
#pragma once

#include <span>

#include "impostor_height_shading.h"
#include "impostor_programs.h"

namespace rg::impostors {

// The units of the object's and the mover's refractor height maps (RGBA32F 2D: normal,
// height; point sampled).
constexpr int kUnitHeight = 4, kUnitMoverHeight = 5;

struct HeightGlassConstants {
    GlassConstants k;
    HeightFrame self;   // the object's height map, in its refractor frame (k.self.toLocal)
    HeightFrame mover;  // the mover's, in its refractor frame (k.mover.toLocal)
};

// GlassFP with the height-map exit: units 0 the environment impostor, 4 the height map; with
// kMover, 2, 3 and 5 the mover's impostor, refractor distance map (a mirror mover's shading
// is shadeOwn's) and refractor height map, searched from the static object's rays
// (throughMoverHeight). Glass only: a mirror has no exit and is drawn with GlassFP.
// Diagnostics as GlassFP's (target 3's searches count 4 where the exit reflects totally).
template <bool kMover, bool kDiagnostics>
struct GlassHeightFP {
    static constexpr int kVaryings = 3;
    static constexpr uint32_t kTargets = kDiagnostics ? 0b1111 : 0b1;
    static constexpr uint32_t kUnits = kMover ? 0b111101 : 0b10001;
    static constexpr bool kWritesDepth = false;
    // The diagnostic variants render the report's analysis frames, never a timed one: the
    // SSE2 kernel (programmable_device.h, kWideKernel), which halves these kernels' compile.
    static constexpr bool kWideKernel = !kDiagnostics;
    static constexpr bool kLaneIndependent = true;  // explicit-λ fetches only, as GlassFP
    static constexpr int kWideQuads = 4;            // as GlassFP
    HeightGlassConstants h;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using M = typename Q::Mask;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const GlassConstants& k = h.k;
        const V4 pos = q.varying(0), nrm = q.varying(1);
        const M live = q.active();
        auto cube = [&q](int unit) {
            return [&q, unit](const V3& d, const M& m) {
                return q.sampleLevel(unit, V4(d.x, d.y, d.z, F(0.0f)), F(0.0f), m);
            };
        };
        auto height = [&q](const F& u, const F& v, const M& m) {
            return q.sampleLevel(kUnitHeight, V4(u, v, F(0.0f), F(0.0f)), F(0.0f), m);
        };
        const V3 P(pos.x, pos.y, pos.z);
        const V3 view = P - splat3<F>(k.eye);
        const V3 V = normalize3(view);
        Shaded<F> s = shadeOwnHeight(k.self, h.self, k.iterations, P, V3(nrm.x, nrm.y, nrm.z), V, live, cube(kUnitEnv),
                                     height);
        if constexpr (kMover) {
            auto moverHeight = [&q](const F& u, const F& v, const M& m) {
                return q.sampleLevel(kUnitMoverHeight, V4(u, v, F(0.0f), F(0.0f)), F(0.0f), m);
            };
            throughMoverHeight(k.mover, h.mover, k.iterations, P, s.reflDir, s.reflD, live, s.reflColour, s.searches,
                               s.moverFlags, 1.0f, cube(kUnitMoverEnv), cube(kUnitMoverRefractor), moverHeight);
            throughMoverHeight(k.mover, h.mover, k.iterations, s.exitOrigin, s.exitDir, s.exitD, live, s.exitColour,
                               s.searches, s.moverFlags, 2.0f, cube(kUnitMoverEnv), cube(kUnitMoverRefractor), moverHeight);
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

// Registers the programs above under "impostors/glass_height…" (program_registry.h);
// idempotent.
void registerImpostorHeightPrograms();

// A triangle-list draw of GlassHeightFP (impostor_height_programs.cpp).
template <bool kMover, bool kDiagnostics>
void drawHeightGlass(raster::ProgrammableDevice& device, const WorldVP& vp, const GlassHeightFP<kMover, kDiagnostics>& fp,
                     std::span<const ImpostorVertex> vertices, std::span<const uint32_t> indices);

}  // namespace rg::impostors
