// Geometry and radiance light fields by ray tracing; dual-paraboloid environment maps.
#include "lf_capture.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "raycore/fresnel.h"

namespace rg::lightfield {

namespace {

uint8_t to8(float v) {
    if (!(v > 0.0f)) return 0;
    if (v >= 1.0f) return 255;
    return uint8_t(std::lround(v * 255.0f));
}

template <class F>
void parallelFor(int threads, int n, F&& f) {
    tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, n), [&](const tbb::blocked_range<int>& r) {
            for (int k = r.begin(); k != r.end(); ++k) f(k);
        });
    });
}

}  // namespace

ParaboloidCoord toParaboloid(glm::vec3 d) {
    d = glm::normalize(d);
    ParaboloidCoord c;
    c.side = d.z >= 0.0f ? 0 : 1;
    const float den = c.side == 0 ? 1.0f + d.z : 1.0f - d.z;
    c.s = (d.x / den + 1.0f) * 0.5f;
    c.t = (d.y / den + 1.0f) * 0.5f;
    return c;
}

glm::vec3 fromParaboloid(float s, float t, int side) {
    const float x = 2.0f * s - 1.0f, y = 2.0f * t - 1.0f;
    const float r2 = x * x + y * y;
    const float z = (1.0f - r2) * (side == 0 ? 1.0f : -1.0f);
    return glm::normalize(glm::vec3(2.0f * x, 2.0f * y, z));
}

std::array<uint8_t, 3> encodeParaboloid(glm::vec3 dir) {
    const ParaboloidCoord c = toParaboloid(dir);
    return {to8(c.s), to8(c.t), uint8_t(c.side ? 255 : 0)};
}

ParaboloidMap makeParaboloidMap(const std::function<glm::vec3(glm::vec3)>& radiance, int size, int n, int threads) {
    ParaboloidMap m;
    m.size = size;
    m.rgb.resize(size_t(size) * size * 2 * 3);
    parallelFor(threads, 2 * size, [&](int row) {
        const int side = row / size, y = row % size;
        for (int x = 0; x < size; ++x) {
            glm::vec3 sum(0.0f);
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx)
                    sum += radiance(fromParaboloid((float(x) + (float(sx) + 0.5f) / float(n)) / float(size),
                                                   (float(y) + (float(sy) + 0.5f) / float(n)) / float(size), side));
            sum /= float(n * n);
            uint8_t* p = m.rgb.data() + ((size_t(side) * size + size_t(y)) * size + size_t(x)) * 3;
            p[0] = to8(sum.x);
            p[1] = to8(sum.y);
            p[2] = to8(sum.z);
        }
    });
    return m;
}

ParaboloidMap makeParaboloidMap(const ray::Environment& env, int size, float exposure, int n) {
    return makeParaboloidMap([&](glm::vec3 d) { return env.lookup(d) * exposure; }, size, n, 0);
}

glm::vec3 sampleParaboloidMap(const ParaboloidMap& m, glm::vec3 dir) {
    const ParaboloidCoord c = toParaboloid(dir);
    const float u = c.s * float(m.size) - 0.5f, v = c.t * float(m.size) - 0.5f;
    const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
    const float fx = u - float(x0), fy = v - float(y0);
    auto at = [&](int x, int y) {
        x = std::clamp(x, 0, m.size - 1);
        y = std::clamp(y, 0, m.size - 1);
        const Rgba8 t = m.texel(c.side, x, y);
        return glm::vec3(t.r, t.g, t.b) / 255.0f;
    };
    return (at(x0, y0) * (1 - fx) + at(x0 + 1, y0) * fx) * (1 - fy) + (at(x0, y0 + 1) * (1 - fx) + at(x0 + 1, y0 + 1) * fx) * fy;
}

ParaboloidMap prefilterPhong(const ParaboloidMap& src, int outSize, float exponent, int threads) {
    // The source texels as directions with their solid angles (the paraboloid's Jacobian:
    // dω = 4/(1 + x² + y²)² dx dy on the map plane), inside the disk only.
    struct Sample { glm::vec3 dir, rgb; float w; };
    std::vector<Sample> samples;
    const int step = std::max(1, src.size / 64);  // 64² source texels a side suffice for a lobe this wide
    for (int side = 0; side < 2; ++side)
        for (int y = 0; y < src.size; y += step)
            for (int x = 0; x < src.size; x += step) {
                glm::vec3 rgb(0.0f);
                for (int yy = y; yy < y + step; ++yy)
                    for (int xx = x; xx < x + step; ++xx) {
                        const Rgba8 t = src.texel(side, xx, yy);
                        rgb += glm::vec3(t.r, t.g, t.b);
                    }
                rgb /= float(step * step) * 255.0f;
                const float s = (float(x) + 0.5f * float(step)) / float(src.size), t = (float(y) + 0.5f * float(step)) / float(src.size);
                const float px = 2 * s - 1, py = 2 * t - 1, r2 = px * px + py * py;
                if (r2 > 1.0f) continue;
                samples.push_back({fromParaboloid(s, t, side), rgb, 4.0f / ((1 + r2) * (1 + r2))});
            }
    return makeParaboloidMap(
        [&](glm::vec3 r) {
            glm::vec3 sum(0.0f);
            float wsum = 0.0f;
            for (const Sample& q : samples) {
                const float c = glm::dot(r, q.dir);
                if (c <= 0.0f) continue;
                const float w = std::pow(c, exponent) * q.w;
                sum += w * q.rgb;
                wsum += w;
            }
            return wsum > 0 ? sum / wsum : glm::vec3(0.0f);
        },
        outSize, 1, threads);
}

std::shared_ptr<tex::Texture> uploadParaboloidMap(tex::TextureMemory& memory, const ParaboloidMap& m) {
    auto t = memory.create({tex::TextureTarget::Texture3D, tex::TexelFormat::RGB8, m.size, m.size, 2, 1, 1});
    memory.upload(*t, 0, 0, m.rgb);
    return t;
}

ExitRay traceExit(const ray::Accel& accel, uint32_t object, const ray::Ray& in, Interaction mode, float ior,
                  int maxSegments) {
    ExitRay out;
    out.origin = in.origin;
    out.dir = in.dir;
    ray::Ray r = in;
    ray::SurfacePoint sp = accel.intersectSurface(r);
    if (sp.object != object) return out;
    out.hit = true;
    glm::vec3 n = sp.frontFace ? sp.ns : -sp.ns;
    out.normal = n;
    out.fresnel = ray::FresnelDielectric(std::max(0.0f, -glm::dot(r.dir, n)), 1.0f, ior);
    if (mode == Interaction::Reflect) {
        out.dir = ray::reflectDir(r.dir, n);
        out.origin = accel.offsetOrigin(sp, out.dir);
        return out;
    }
    // Refraction with total internal reflection, one greedy child.
    glm::vec3 d = r.dir, p = sp.p;
    bool inside = false;
    for (int seg = 0; seg <= maxSegments; ++seg) {
        glm::vec3 nn = sp.frontFace ? sp.ns : -sp.ns;
        if (glm::dot(nn, d) > 0.0f) nn = -nn;
        const float eta = sp.frontFace ? 1.0f / ior : ior;
        glm::vec3 t;
        if (ray::refractDir(d, nn, eta, &t)) {
            d = glm::normalize(t);
            inside = sp.frontFace;
        } else {
            d = ray::reflectDir(d, nn);
        }
        p = accel.offsetOrigin(sp, d);
        if (!inside) break;
        ray::Ray next;
        next.origin = p;
        next.dir = d;
        sp = accel.intersectSurface(next);
        if (sp.object != object) break;  // an open mesh: leave where we are
    }
    out.origin = p;
    out.dir = d;
    return out;
}

LightField captureParaboloidField(const ray::Accel& accel, uint32_t object, const LightSlab& slab, Interaction mode,
                                  float ior, int threads) {
    LightField lf;
    lf.slab = slab;
    lf.content = LightFieldContent::ParaboloidCoordinates;
    lf.channels = 3;
    lf.data.resize(slab.samples() * 3);
    parallelFor(threads, slab.S * slab.T, [&](int e) {
        const int i = e % slab.S, j = e / slab.S;
        for (int l = 0; l < slab.V; ++l)
            for (int k = 0; k < slab.U; ++k) {
                const ExitRay x = traceExit(accel, object, slab.sampleRay(i, j, k, l), mode, ior);
                const auto c = encodeParaboloid(x.dir);
                std::copy(c.begin(), c.end(), lf.data.begin() + std::ptrdiff_t(lf.offset(i, j, k, l)));
            }
    });
    return lf;
}

LightField captureSlabField(const ray::Accel& accel, uint32_t object, const LightSlab& slab, const LightSlab& lighting,
                            Interaction mode, float ior, int threads) {
    LightField lf;
    lf.slab = slab;
    lf.content = LightFieldContent::SlabCoordinates;
    lf.channels = 4;
    lf.data.resize(slab.samples() * 4);
    parallelFor(threads, slab.S * slab.T, [&](int e) {
        const int i = e % slab.S, j = e / slab.S;
        for (int l = 0; l < slab.V; ++l)
            for (int k = 0; k < slab.U; ++k) {
                const ExitRay x = traceExit(accel, object, slab.sampleRay(i, j, k, l), mode, ior);
                const auto stuv = lighting.intersect(x.origin, x.dir);
                const glm::vec4 c = stuv ? lighting.textureCoords(*stuv) : glm::vec4(0.0f);
                uint8_t* p = lf.data.data() + lf.offset(i, j, k, l);
                // RGBA = (u, v, s, t): the 4D texture's (x, y, z, w).
                p[0] = to8(c.x);
                p[1] = to8(c.y);
                p[2] = to8(c.z);
                p[3] = to8(c.w);
            }
    });
    return lf;
}

LightField captureRadianceField(const LightSlab& slab, const std::function<glm::vec3(const ray::Ray&)>& radiance,
                                int threads) {
    LightField lf;
    lf.slab = slab;
    lf.content = LightFieldContent::Radiance;
    lf.channels = 3;
    lf.data.resize(slab.samples() * 3);
    parallelFor(threads, slab.S * slab.T, [&](int e) {
        const int i = e % slab.S, j = e / slab.S;
        for (int l = 0; l < slab.V; ++l)
            for (int k = 0; k < slab.U; ++k) {
                const glm::vec3 c = radiance(slab.sampleRay(i, j, k, l));
                uint8_t* p = lf.data.data() + lf.offset(i, j, k, l);
                p[0] = to8(c.x);
                p[1] = to8(c.y);
                p[2] = to8(c.z);
            }
    });
    return lf;
}

}  // namespace rg::lightfield
