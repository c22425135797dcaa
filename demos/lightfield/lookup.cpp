// The two lookup routes of §4: pixel texture and its software twin.
#include "lookup.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

namespace rg::lightfield {

HostTexture hostParaboloidMap(const ParaboloidMap& m) {
    HostTexture h;
    h.dims = 3;
    h.size = {m.size, m.size, 2, 1};
    h.texels.resize(size_t(m.size) * m.size * 2);
    for (size_t i = 0; i < h.texels.size(); ++i) h.texels[i] = {m.rgb[3 * i], m.rgb[3 * i + 1], m.rgb[3 * i + 2], 255};
    return h;
}

HostTexture hostLightField4D(const LightField& lf) {
    HostTexture h;
    h.dims = 4;
    h.size = {lf.slab.U, lf.slab.V, lf.slab.S, lf.slab.T};
    h.texels.resize(lf.slab.samples());
    size_t n = 0;
    for (int j = 0; j < lf.slab.T; ++j)
        for (int i = 0; i < lf.slab.S; ++i)
            for (int l = 0; l < lf.slab.V; ++l)
                for (int k = 0; k < lf.slab.U; ++k, ++n) {
                    const uint8_t* p = lf.data.data() + lf.offset(i, j, k, l);
                    h.texels[n] = {p[0], p[1], p[2], lf.channels == 4 ? p[3] : uint8_t(255)};
                }
    return h;
}

SoftwareLookup::SoftwareLookup(const HostTexture& t, bool rgbOnly) : tex_(&t), rgbOnly_(rgbOnly) {
    for (int d = 0; d < t.dims; ++d) {
        const int n = t.size[size_t(d)];
        Axis& a = axis_[size_t(d)];
        for (int v = 0; v < 256; ++v) {
            // u = ⌊(v/255)·n·256⌋ (float product, as the texture unit), minus ½ texel.
            const float c = float(v) / 255.0f;
            const float u = c * float(n);
            float us = u * 256.0f;
            int32_t fixed = int32_t(us);
            if (float(fixed) > us) --fixed;
            const int32_t m = fixed - 128;
            const int32_t i0 = m >> 8;
            const uint32_t frac = uint32_t(m & 255);
            a.i0[v] = std::clamp(i0, 0, n - 1);
            a.i1[v] = std::clamp(i0 + 1, 0, n - 1);
            a.w0[v] = 256 - frac;
            a.w1[v] = frac;
        }
    }
}

Rgba8 SoftwareLookup::lookup(Rgba8 px) const {
    const HostTexture& t = *tex_;
    const uint8_t b[4] = {px.r, px.g, px.b, rgbOnly_ ? uint8_t(255) : px.a};
    const int dims = t.dims;
    uint64_t acc[4] = {0, 0, 0, 0};
    const int nw = dims > 3 ? 2 : 1, nz = dims > 2 ? 2 : 1;
    for (int iw = 0; iw < nw; ++iw) {
        const Axis& A = axis_[3];
        const int32_t w = dims > 3 ? (iw ? A.i1[b[3]] : A.i0[b[3]]) : 0;
        const uint64_t ww = dims > 3 ? (iw ? A.w1[b[3]] : A.w0[b[3]]) : 1;
        if (!ww) continue;
        for (int iz = 0; iz < nz; ++iz) {
            const Axis& Z = axis_[2];
            const int32_t z = dims > 2 ? (iz ? Z.i1[b[2]] : Z.i0[b[2]]) : 0;
            const uint64_t wz = ww * (dims > 2 ? (iz ? Z.w1[b[2]] : Z.w0[b[2]]) : 1);
            if (!wz) continue;
            for (int iy = 0; iy < 2; ++iy) {
                const Axis& Y = axis_[1];
                const int32_t y = iy ? Y.i1[b[1]] : Y.i0[b[1]];
                const uint64_t wy = wz * (iy ? Y.w1[b[1]] : Y.w0[b[1]]);
                const Rgba8* row = t.texels.data() + ((size_t(w) * t.size[2] + size_t(z)) * t.size[1] + size_t(y)) * t.size[0];
                const Axis& X = axis_[0];
                const Rgba8 c0 = row[X.i0[b[0]]], c1 = row[X.i1[b[0]]];
                const uint64_t w0 = wy * X.w0[b[0]], w1 = wy * X.w1[b[0]];
                acc[0] += w0 * c0.r + w1 * c1.r;
                acc[1] += w0 * c0.g + w1 * c1.g;
                acc[2] += w0 * c0.b + w1 * c1.b;
                acc[3] += w0 * c0.a + w1 * c1.a;
            }
        }
    }
    const int bits = 8 * dims;
    const uint64_t half = uint64_t(1) << (bits - 1);
    Rgba8 o{uint8_t((acc[0] + half) >> bits), uint8_t((acc[1] + half) >> bits), uint8_t((acc[2] + half) >> bits),
            uint8_t((acc[3] + half) >> bits)};
    if (rgbOnly_) o.a = px.a;
    return o;
}

void SoftwareLookup::apply(std::vector<Rgba8>& pixels, int threads) const {
    constexpr size_t kChunk = 4096;
    const size_t chunks = (pixels.size() + kChunk - 1) / kChunk;
    auto run = [&](size_t a, size_t b) {
        for (size_t c = a; c < b; ++c)
            for (size_t i = c * kChunk, e = std::min(pixels.size(), (c + 1) * kChunk); i < e; ++i)
                pixels[i] = lookup(pixels[i]);
    };
    if (threads == 1) {
        run(0, chunks);
        return;
    }
    tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, chunks),
                          [&](const tbb::blocked_range<size_t>& r) { run(r.begin(), r.end()); });
    });
}

void pixelTextureLookup(raster::Device& dev, std::shared_ptr<const tex::Texture> texture, tex::PixelTexGenMode mode,
                        const std::vector<Rgba8>& pixels) {
    tex::TextureUnits& tu = dev.textureUnits();
    tex::SamplerState s;
    s.magFilter = s.minFilter = tex::FilterMode::Linear;
    s.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                 tex::AddressMode::ClampToEdge};
    tu.setSampler(0, s);
    tu.setTexture(0, std::move(texture));
    tu.setColorTable(0, nullptr);
    tu.setPixelTexture({true, mode, 0});
    const int w = dev.framebuffer().width(), h = dev.framebuffer().height();
    try {
        dev.drawPixels(0, 0, w, h, pixels);
    } catch (...) {
        tu.setPixelTexture({false, mode, 0});
        throw;
    }
    tu.setPixelTexture({false, mode, 0});
}

}  // namespace rg::lightfield
