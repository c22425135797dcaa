// Helpers shared by the rasterizer tests: devices, vertices, frame hashes.
#pragma once

#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/profile.h"
#include "rasterizer/device.h"
#include "rasterizer/trace.h"  // sha256Hex: the replay hash, one implementation

namespace rg::testing {

using raster::sha256Hex;

// Seeded draws for the randomized tests (std::mt19937_64; the same cases on every run).
struct Rng {
    std::mt19937_64 g;
    explicit Rng(uint64_t seed) : g(seed) {}
    int i(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(g); }
    int64_t i64(int64_t lo, int64_t hi) { return std::uniform_int_distribution<int64_t>(lo, hi)(g); }
    float f(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(g); }
    bool p(double prob) { return std::bernoulli_distribution(prob)(g); }
    uint8_t byte() { return uint8_t(i(0, 255)); }
};

inline raster::Vertex tv(float x, float y, float z = 0.5f, float rhw = 1.0f,
                         Rgba8 diffuse = {255, 255, 255, 255}, Rgba8 specular = {0, 0, 0, 0}) {
    raster::Vertex v;
    v.position = {x, y, z, rhw};
    v.diffuse = diffuse;
    v.specular = specular;
    return v;
}

// A state with nothing enabled that could hide a pixel: no culling, no depth test.
inline raster::PipelineState plainState() {
    raster::PipelineState s;
    s.cull = raster::CullMode::None;
    s.depthTest = 0;
    s.depthWrite = 0;
    return s;
}

inline std::string frameHash(const raster::Framebuffer& fb) {
    std::string h = sha256Hex(fb.color().data(), fb.color().size_bytes());
    if (!fb.depth().empty()) h += "/" + sha256Hex(fb.depth().data(), fb.depth().size_bytes());
    return h;
}

inline int countIf(const raster::Framebuffer& fb, auto pred) {
    int n = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) n += pred(fb.pixel(x, y)) ? 1 : 0;
    return n;
}

// ---- random commands (the paths-agree and batch tests) -----------------------------
inline raster::PipelineState randomState(Rng& r) {
    raster::PipelineState s;
    s.cull = raster::CullMode(r.i(0, 2));
    s.shade = raster::ShadeMode(r.i(0, 1));
    s.depthTest = uint8_t(r.p(0.6));
    s.depthWrite = uint8_t(r.p(0.7));
    s.depthFunc = raster::CompareFunc(r.i(0, 7));
    s.alphaTest = uint8_t(r.p(0.3));
    s.alphaFunc = raster::CompareFunc(r.i(0, 7));
    s.alphaRef = r.byte();
    s.blend = uint8_t(r.p(0.6));
    s.srcBlend = raster::BlendFactor(r.i(0, 12));
    s.dstBlend = raster::BlendFactor(r.i(0, 10));  // BOTH* are source-only
    s.blendOp = raster::BlendOp(r.i(0, 4));
    s.colorWriteMask = r.p(0.7) ? uint8_t(raster::kWriteRGBA) : uint8_t(r.i(0, 15));
    s.scissorTest = uint8_t(r.p(0.25));
    s.specularEnable = uint8_t(r.p(0.3));
    s.perspectiveColor = uint8_t(r.p(0.5));
    return s;
}

inline Rgba8 randomColor(Rng& r) {
    // Often a shared colour, so that constant-colour span fills are exercised.
    return r.p(0.2) ? Rgba8{200, 100, 50, 180} : Rgba8{r.byte(), r.byte(), r.byte(), r.byte()};
}

inline float weird(Rng& r) {
    const float values[] = {std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity(),
                            -std::numeric_limits<float>::infinity(), 1e30f, -1e30f, 0.0f};
    return values[r.i(0, 5)];
}

// One vertex of the given kind, in window space (pre-transformed) or object space.
inline raster::Vertex randomVertex(Rng& r, raster::VertexSpace space, int kind, int w, int h, const raster::Vertex* near) {
    raster::Vertex v;
    v.diffuse = randomColor(r);
    v.specular = Rgba8{r.byte(), r.byte(), r.byte(), r.byte()};
    float x, y, z, q;
    if (space == raster::VertexSpace::Pretransformed) {
        x = r.f(-10.0f, float(w) + 10.0f);
        y = r.f(-10.0f, float(h) + 10.0f);
        z = r.f(-0.2f, 1.2f);
        q = r.p(0.5) ? 1.0f : r.f(0.05f, 3.0f);
        switch (kind) {
            case 1: x = r.f(-1e6f, 1e6f); y = r.f(-1e6f, 1e6f); break;  // huge
            case 2: if (near) { x = near->position.x + r.f(-0.4f, 0.4f); y = near->position.y + r.f(-0.4f, 0.4f); } break;
            case 3: if (near) { x = near->position.x; y = near->position.y; } break;  // degenerate
            case 4: q = r.p(0.5) ? -q : 0.0f; break;  // behind the eye / w infinite
            case 5: (r.p(0.5) ? x : (r.p(0.5) ? z : q)) = weird(r); break;
            default: break;
        }
        v.position = {x, y, z, q};
    } else {
        x = r.f(-2.5f, 2.5f);
        y = r.f(-2.5f, 2.5f);
        z = r.f(-1.0f, 4.0f);  // the camera sits at z = −3: some vertices behind it
        switch (kind) {
            case 1: x = r.f(-1e5f, 1e5f); y = r.f(-1e5f, 1e5f); break;
            case 2: if (near) { x = near->position.x + r.f(-0.01f, 0.01f); y = near->position.y + r.f(-0.01f, 0.01f); z = near->position.z; } break;
            case 3: if (near) { x = near->position.x; y = near->position.y; z = near->position.z; } break;
            case 4: z = r.f(-6.0f, -3.5f); break;  // behind the eye
            case 5: (r.p(0.5) ? x : z) = weird(r); break;
            default: break;
        }
        v.position = {x, y, z, 1.0f};
    }
    return v;
}

inline std::string firstDifference(const raster::Framebuffer& a, const raster::Framebuffer& b) {
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x) {
            size_t i = size_t(y) * a.width() + x;
            Rgba8 p = a.color()[i], q = b.color()[i];
            if (!(p == q) || (!a.depth().empty() && a.depth()[i] != b.depth()[i])) {
                std::ostringstream s;
                s << "pixel (" << x << ", " << y << "): reference " << int(p.r) << "," << int(p.g)
                  << "," << int(p.b) << "," << int(p.a) << " fast " << int(q.r) << "," << int(q.g)
                  << "," << int(q.b) << "," << int(q.a);
                if (!a.depth().empty()) s << " depth " << a.depth()[i] << " vs " << b.depth()[i];
                return s.str();
            }
        }
    return "none";
}

inline bool sameCounters(const raster::Counters& a, const raster::Counters& b) {
    return a.passes == b.passes && a.drawCalls == b.drawCalls &&
           a.trianglesSubmitted == b.trianglesSubmitted && a.trianglesCulled == b.trianglesCulled &&
           a.trianglesClipped == b.trianglesClipped && a.trianglesDrawn == b.trianglesDrawn &&
           a.trianglesInvalid == b.trianglesInvalid &&
           a.fragmentsGenerated == b.fragmentsGenerated &&
           a.fragmentsWritten == b.fragmentsWritten && a.blendOps == b.blendOps &&
           a.bytesReadBack == b.bytesReadBack;
}

inline const Profile& geforce256() { return profile(ProfileId::GeForce256); }

}  // namespace rg::testing
