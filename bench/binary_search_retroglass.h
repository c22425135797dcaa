// The retroglass side of the binary_search workload (bench/binary_search_workload.h):
// the search as a geforce8800 fragment program, and one frame on a programmable device.
// Shared by bench/bench_programmable.cpp and tests/programmable (which checks the frame
// against binary_search::referenceImage() byte for byte).
#pragma once

#include <cstring>
#include <memory>
#include <vector>

#include "binary_search_workload.h"
#include "core/profile.h"
#include "rasterizer/programmable_device.h"

namespace rg::bench::binary_search {

using raster::ColorTarget;
using raster::FragmentContext;
using raster::ProgrammableDevice;
using raster::ProgramPrimitive;
using raster::Varyings;
namespace bs = binary_search;

struct QuadVertex {
    glm::vec4 clip;
};

struct QuadVP {
    static constexpr int kVaryings = 0;
    glm::vec4 operator()(const QuadVertex& v, Varyings&) const { return v.clip; }
};

// The per-fragment algorithm of the workload header. uv comes from the pixel centre
// (gl_FragCoord.xy / 512), which is exactly the header's (x + ½)/512.
struct BinarySearchFP {
    static constexpr int kVaryings = 0;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    void operator()(FragmentContext& f) const {
        const glm::vec4 fc = f.fragCoord();
        const float u = fc.x / float(bs::kWidth), v = fc.y / float(bs::kHeight);
        const glm::vec3 a(u, v, 0.0f), b(u + bs::kRayDx, v + bs::kRayDy, 1.0f);
        float lo = 0.0f, hi = 1.0f, d = 0.0f;
        for (int step = 0; step < bs::kSteps; ++step) {
            const float mid = 0.5f * (lo + hi);
            const glm::vec3 p = a + (b - a) * mid;
            d = f.sampleLevel(0, glm::vec4(p.x, p.y, 0.0f, 0.0f), 0.0f).x;
            if (p.z > d)
                hi = mid;
            else
                lo = mid;
        }
        f.output(0, glm::vec4(0.5f * (lo + hi), d, 0.0f, 1.0f));
    }
};

// The same algorithm as a quad program (rasterizer/quad_program.h): the pixels of a quad in
// SSE lanes, the branch as a select — what the benchmark runs. Written for any context
// (QuadContext: one quad; QuadGroupContext: several quads interleaved, which the fast path
// uses to overlap the searches' dependent steps).
struct BinarySearchQuadFP {
    static constexpr int kVaryings = 0;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 1;
    static constexpr bool kWritesDepth = false;
    template <class Q>
    void operator()(Q& q) const {
        using F = typename Q::Float;
        using V3 = typename Q::Vec3;
        using V4 = typename Q::Vec4;
        const V4 fc = q.fragCoord();
        const F u = fc.x / F(float(bs::kWidth)), v = fc.y / F(float(bs::kHeight));
        const V3 a(u, v, F(0.0f)), b(u + bs::kRayDx, v + bs::kRayDy, F(1.0f));
        F lo(0.0f), hi(1.0f), d(0.0f);
        for (int step = 0; step < bs::kSteps; ++step) {
            const F mid = F(0.5f) * (lo + hi);
            const V3 p = a + (b - a) * mid;
            d = q.sampleLevel(0, V4(p.x, p.y, F(0.0f), F(0.0f)), F(0.0f)).x;
            const auto above = p.z > d;
            hi = select(above, mid, hi);
            lo = select(above, lo, mid);
        }
        q.output(0, V4(F(0.5f) * (lo + hi), d, F(0.0f), F(1.0f)));
    }
};

// One frame of the workload on a fresh device; the RGBA8 image in the header's row order.
// Used by the benchmark and by tests/programmable (against bs::referenceImage()).
struct BinarySearchScene {
    tex::TextureMemory memory{profile(ProfileId::GeForce8800)};
    std::shared_ptr<tex::Texture> depth, target;
    ProgrammableDevice device;
    std::vector<QuadVertex> quad;

    explicit BinarySearchScene(int threads)
        : device(profile(ProfileId::GeForce8800), raster::DeviceOptions{Path::Fast, threads}) {
        tex::TextureDesc dd;
        dd.format = tex::TexelFormat::R32F;
        dd.width = dd.height = bs::kDepthSize;
        depth = memory.create(dd);
        const std::vector<float> d = bs::depthImage();
        std::vector<uint8_t> bytes(d.size() * 4);
        std::memcpy(bytes.data(), d.data(), bytes.size());
        memory.upload(*depth, 0, 0, bytes);
        tex::TextureDesc td;
        td.width = bs::kWidth;
        td.height = bs::kHeight;
        target = memory.createRenderTarget(td);
        ColorTarget ct{target};
        device.setRenderTargets({&ct, 1});
        tex::SamplerState s;  // NEAREST, REPEAT, level 0
        s.magFilter = s.minFilter = tex::FilterMode::Nearest;
        device.setTexture(0, depth, s);
        // Window y = row: clip y = +1 is row 0 (Direct3D viewport).
        quad = {{{-1, 1, 0.5f, 1}}, {{1, 1, 0.5f, 1}}, {{-1, -1, 0.5f, 1}},
                {{1, 1, 0.5f, 1}},  {{1, -1, 0.5f, 1}}, {{-1, -1, 0.5f, 1}}};
    }
    void frame() {  // the quad program
        device.draw(QuadVP{}, BinarySearchQuadFP{}, ProgramPrimitive::TriangleList,
                    std::span<const QuadVertex>(quad));
    }
    void frameScalar() {  // the pixel-by-pixel program
        device.draw(QuadVP{}, BinarySearchFP{}, ProgramPrimitive::TriangleList,
                    std::span<const QuadVertex>(quad));
    }
};

inline std::vector<uint8_t> renderRetroglass(int threads, bool quadProgram = true, Path path = Path::Fast) {
    BinarySearchScene scene(threads);
    scene.device.setPath(path);
    if (quadProgram)
        scene.frame();
    else
        scene.frameScalar();
    const Rgba8* p = scene.target->renderData8(0, 0);
    std::vector<uint8_t> out(size_t(bs::kWidth) * bs::kHeight * 4);
    std::memcpy(out.data(), p, out.size());
    return out;
}

}  // namespace rg::bench::binary_search
