#include "rendering_matrix.h"

#include <chrono>
#include <functional>
#include <map>
#include <mutex>

#include "core/error.h"
#include "texunit/stages.h"

namespace rg::pem {

const char* emLayerName(EmLayer layer) {
    switch (layer) {
        case EmLayer::Local: return "local";
        case EmLayer::Distant: return "distant";
        case EmLayer::Infinite: return "infinite";
        case EmLayer::Ptm: return "ptm";
    }
    return "?";
}

TexelLayout layoutFor(EmLayer layer, int baseSize) {
    return TexelLayout{baseSize, layer == EmLayer::Ptm ? 1 : 6};
}

namespace {

using Clock = std::chrono::steady_clock;

// A complete RGBA8 cube map (or 2D texture, `faces` = 1) whose texel (level, face, x, y)
// is fill(level, face, x, y).
template <class Fill>
std::shared_ptr<tex::Texture> makeMap(tex::TextureMemory& memory, const TexelLayout& layout,
                                      Fill fill) {
    tex::TextureDesc d;
    d.target = layout.faces == 6 ? tex::TextureTarget::CubeMap : tex::TextureTarget::Texture2D;
    d.format = tex::TexelFormat::RGBA8;
    d.width = d.height = layout.baseSize;
    d.levels = layout.levels();
    auto t = memory.create(d);
    for (int l = 0; l < d.levels; ++l) {
        int s = layout.levelSize(l);
        std::vector<uint8_t> bytes(size_t(s) * s * 4);
        for (int f = 0; f < layout.faces; ++f) {
            for (int y = 0; y < s; ++y)
                for (int x = 0; x < s; ++x) {
                    Rgba8 c = fill(l, f, x, y);
                    uint8_t* b = &bytes[(size_t(y) * s + x) * 4];
                    b[0] = c.r, b[1] = c.g, b[2] = c.b, b[3] = c.a;
                }
            memory.upload(*t, l, f, bytes);
        }
    }
    return t;
}

// One isolating rendering: depth of the whole reflector first, then the layer's triangles
// of `part` at depth EQUAL with stage 0 = SELECTARG1(TEXTURE) on the layer's coordinates.
void renderLayer(raster::Device& device, PemRenderer& renderer, const ray::Camera& camera,
                 size_t part, EmLayer layer, const std::shared_ptr<const tex::Texture>& texture,
                 const tex::SamplerState& sampler) {
    device.beginFrame();
    renderer.setCameraTransforms(camera);
    tex::TextureUnits& tu = device.textureUnits();
    for (int s = 0; s < device.profile().maxTextureStages; ++s) tu.setStage(s, {});
    raster::PipelineState st;
    st.cull = raster::CullMode::CW;
    st.colorWriteMask = 0;
    st.depthFunc = raster::CompareFunc::LessEqual;
    device.setState(st);
    device.clear(true, {0, 0, 0, 0}, true, 1.0f);
    device.beginPass("isolate: depth of the reflector");
    for (size_t p = 0; p < renderer.scene().parts.size(); ++p)
        device.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed,
                    renderer.vertices(p), renderer.allIndices(p));
    device.beginPass(std::string("isolate: ") + emLayerName(layer) + " EM texels");
    st.colorWriteMask = raster::kWriteRGBA;
    st.depthFunc = raster::CompareFunc::Equal;
    st.depthWrite = 0;
    device.setState(st);
    tex::StageState s0;
    s0.colorOp = tex::TextureOp::SelectArg1;
    s0.colorArg1 = tex::arg::Texture;
    s0.alphaOp = tex::TextureOp::SelectArg1;
    s0.alphaArg1 = tex::arg::Texture;
    s0.texCoordIndex = layer == EmLayer::Local ? 1 : layer == EmLayer::Ptm ? 3 : 0;
    tu.setStage(0, s0);
    tu.setSampler(0, sampler);
    tu.setTexture(0, texture);
    const auto& idx = layer == EmLayer::Local ? renderer.offHullIndices(part)
                                              : renderer.allIndices(part);
    if (!idx.empty())
        device.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed,
                    renderer.vertices(part), idx);
    device.endFrame();
    tu.setStage(0, {});
    tu.setTexture(0, nullptr);
}

EmMode modeFor(EmLayer layer) {
    return layer == EmLayer::Infinite ? EmMode::SingleInfinite : EmMode::Layered;
}

}  // namespace

std::shared_ptr<tex::Texture> makeMapFromTexels(tex::TextureMemory& memory,
                                                const TexelLayout& layout,
                                                const std::function<Rgba8(int64_t)>& texel) {
    return makeMap(memory, layout, [&](int l, int f, int x, int y) {
        return texel(layout.index(l, f, x, y));
    });
}

namespace {

IsolatingRendering pemIsolating(raster::Device& device, PemRenderer& renderer,
                                const ray::Camera& camera, size_t part, EmLayer layer,
                                int baseSize) {
    renderer.prepare(camera, modeFor(layer));
    IsolatingRendering r;
    r.layout = layoutFor(layer, baseSize);
    r.subsample = 1;
    r.sampler = PemRenderer::cubeSampler();
    r.render = [&device, &renderer, camera, part, layer](
                   const std::shared_ptr<const tex::Texture>& texture,
                   const tex::SamplerState& sampler) {
        renderLayer(device, renderer, camera, part, layer, texture, sampler);
    };
    return r;
}

}  // namespace

RenderingMatrix buildMatrixByTestRenderings(raster::Device& device, tex::TextureMemory& memory,
                                            const IsolatingRendering& R,
                                            MatrixBuildStats* stats) {
    auto t0 = Clock::now();
    const int n = std::max(1, R.subsample);
    const int DW = device.framebuffer().width(), DH = device.framebuffer().height();
    if (DW % n || DH % n)
        throw Error("rendering matrix: the device is not a whole multiple of the display");
    const int W = DW / n, H = DH / n;
    RenderingMatrix m;
    m.layout = R.layout;
    m.width = W;
    m.height = H;
    int renderings = 0;
    const double subWeight = 1.0 / double(n * n);
    auto displayOf = [&](size_t i) {
        const int x = int(i % size_t(DW)), y = int(i / size_t(DW));
        return size_t(y / n) * size_t(W) + size_t(x / n);
    };

    // Row of every display pixel the layer draws (alpha 255 in an identification rendering
    // on any of its subpixels).
    std::vector<int32_t> rowOf(size_t(W) * H, -1);
    std::vector<std::map<int64_t, double>> rows;
    for (int level = 0; level < m.layout.levels(); ++level) {
        // ---- identification: nearest texel on `level`, encoded in the colour ----------
        auto id = makeMap(memory, m.layout, [&](int l, int f, int x, int y) {
            if (l != level) return Rgba8{0, 0, 0, 0};
            return Rgba8{uint8_t(x & 255), uint8_t(y & 255),
                         uint8_t(f | ((x >> 8) << 3) | ((y >> 8) << 5)), 255};
        });
        tex::SamplerState nearest = R.sampler;
        nearest.magFilter = nearest.minFilter = tex::FilterMode::Nearest;
        nearest.mipFilter = tex::MipMode::None;
        nearest.baseLevel = level;
        nearest.maxLevel = level;
        R.render(id, nearest);
        ++renderings;
        std::vector<Rgba8> idImage(device.framebuffer().color().begin(),
                                   device.framebuffer().color().end());
        if (level == 0) {
            for (size_t i = 0; i < idImage.size(); ++i)
                if (idImage[i].a == 255 && rowOf[displayOf(i)] < 0) rowOf[displayOf(i)] = 0;
            for (size_t d = 0; d < rowOf.size(); ++d)
                if (rowOf[d] == 0) {
                    rowOf[d] = int32_t(m.rowPixel.size());
                    m.rowPixel.push_back(int32_t(d));
                    rows.emplace_back();
                }
        }
        const int size = m.layout.levelSize(level);
        // ---- 9 isolating renderings -------------------------------------------------------
        for (int py = 0; py < 3; ++py)
            for (int px = 0; px < 3; ++px) {
                auto lit = makeMap(memory, m.layout, [&](int l, int, int x, int y) {
                    bool on = l == level && x % 3 == px && y % 3 == py;
                    return on ? Rgba8{255, 255, 255, 255} : Rgba8{0, 0, 0, 0};
                });
                R.render(lit, R.sampler);
                ++renderings;
                const auto color = device.framebuffer().color();
                for (size_t i = 0; i < color.size(); ++i) {
                    const int32_t row = rowOf[displayOf(i)];
                    if (row < 0 || color[i].r == 0 || idImage[i].a != 255) continue;
                    const Rgba8 c = idImage[i];
                    int face = c.b & 7;
                    int xn = c.r | (((c.b >> 3) & 3) << 8), yn = c.g | (((c.b >> 5) & 3) << 8);
                    // The lit texel among xn−1, xn, xn+1 (resp. y) of this class.
                    int xc = xn - 1 + ((px - (xn - 1)) % 3 + 3) % 3;
                    int yc = yn - 1 + ((py - (yn - 1)) % 3 + 3) % 3;
                    if (xc < 0 || yc < 0 || xc >= size || yc >= size) continue;
                    rows[size_t(row)][m.layout.index(level, face, xc, yc)] +=
                        subWeight * color[i].r / 255.0;
                }
            }
    }
    std::vector<Eigen::Triplet<double>> trip;
    for (size_t r = 0; r < rows.size(); ++r)
        for (const auto& [col, v] : rows[r]) trip.emplace_back(int(r), int(col), v);
    m.A.resize(int64_t(rows.size()), m.layout.count());
    m.A.setFromTriplets(trip.begin(), trip.end());
    if (stats) {
        stats->renderings = renderings;
        stats->seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    }
    return m;
}

RenderingMatrix buildMatrixByInstrumentedPass(raster::Device& device,
                                              tex::TextureMemory& memory,
                                              const IsolatingRendering& R,
                                              MatrixBuildStats* stats) {
    auto t0 = Clock::now();
    const int n = std::max(1, R.subsample);
    const int DW = device.framebuffer().width(), DH = device.framebuffer().height();
    if (DW % n || DH % n)
        throw Error("rendering matrix: the device is not a whole multiple of the display");
    const int W = DW / n, H = DH / n;
    RenderingMatrix m;
    m.layout = R.layout;
    m.width = W;
    m.height = H;

    // Any texture of the right shape: the taps do not depend on the texel values.
    auto probe = makeMap(memory, m.layout,
                          [](int, int, int, int) { return Rgba8{255, 255, 255, 255}; });
    // Per display pixel, the taps of its subpixels (a subpixel overwritten by a later
    // fragment replaces its own taps: the last fragment written is what the frame shows).
    struct SubpixelTaps {
        int count = -1;  // −1: the layer did not reach the subpixel
        std::array<std::pair<int64_t, double>, tex::TapList::kMax> taps;
    };
    std::vector<SubpixelTaps> perSub(size_t(DW) * DH);
    const tex::TextureUnits& tu = device.textureUnits();
    int layerPass = 0;
    device.setFragmentObserver([&](const tex::FragmentQuad& quad, uint8_t passed) {
        if (layerPass == 0) return;  // the depth pass
        for (int i = 0; i < 4; ++i) {
            if (!(passed & (1u << i))) continue;
            int x = quad.x + (i & 1), y = quad.y + (i >> 1);
            SubpixelTaps& pt = perSub[size_t(y) * DW + x];
            tex::TapList list = tu.queryTaps(0, quad, i);
            pt.count = 0;
            for (int k = 0; k < list.count; ++k) {
                const tex::TexelTap& t = list.taps[size_t(k)];
                if (t.border || t.weight == 0) continue;
                pt.taps[size_t(pt.count++)] = {
                    m.layout.index(t.level, t.face, t.xyzw[0], t.xyzw[1]), list.weightOf(k)};
            }
        }
    });
    device.setPassObserver([&](const raster::PassRecord&, const raster::Framebuffer&) {
        ++layerPass;
    });
    R.render(probe, R.sampler);
    device.setFragmentObserver({});
    device.setPassObserver({});

    std::vector<Eigen::Triplet<double>> trip;
    const double subWeight = 1.0 / double(n * n);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            bool any = false;
            for (int sy = 0; sy < n && !any; ++sy)
                for (int sx = 0; sx < n && !any; ++sx)
                    any = perSub[size_t(y * n + sy) * DW + size_t(x * n + sx)].count >= 0;
            if (!any) continue;
            const int r = int(m.rowPixel.size());
            m.rowPixel.push_back(int32_t(y * W + x));
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    const SubpixelTaps& pt = perSub[size_t(y * n + sy) * DW + size_t(x * n + sx)];
                    for (int k = 0; k < pt.count; ++k)
                        trip.emplace_back(r, int(pt.taps[size_t(k)].first),
                                          subWeight * pt.taps[size_t(k)].second);
                }
        }
    m.A.resize(int64_t(m.rowPixel.size()), m.layout.count());
    m.A.setFromTriplets(trip.begin(), trip.end());  // sums duplicate taps (clamped edges)
    if (stats) {
        stats->renderings = 1;
        stats->seconds = std::chrono::duration<double>(Clock::now() - t0).count();
    }
    return m;
}

RenderingMatrix buildMatrixByTestRenderings(raster::Device& device, PemRenderer& renderer,
                                            const ray::Camera& camera, size_t part, EmLayer layer,
                                            int baseSize, MatrixBuildStats* stats) {
    return buildMatrixByTestRenderings(
        device, renderer.memory(), pemIsolating(device, renderer, camera, part, layer, baseSize),
        stats);
}

RenderingMatrix buildMatrixByInstrumentedPass(raster::Device& device, PemRenderer& renderer,
                                              const ray::Camera& camera, size_t part,
                                              EmLayer layer, int baseSize,
                                              MatrixBuildStats* stats) {
    return buildMatrixByInstrumentedPass(
        device, renderer.memory(), pemIsolating(device, renderer, camera, part, layer, baseSize),
        stats);
}

MatrixAgreement compareMatrices(const RenderingMatrix& a, const RenderingMatrix& b,
                                double ignoreBelow) {
    MatrixAgreement g;
    g.rowsA = a.A.rows();
    g.rowsB = b.A.rows();
    g.nonZerosA = a.A.nonZeros();
    g.nonZerosB = b.A.nonZeros();
    g.sameRows = a.rowPixel == b.rowPixel;
    std::map<int32_t, int> rowB;
    for (size_t r = 0; r < b.rowPixel.size(); ++r) rowB[b.rowPixel[r]] = int(r);
    using It = Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator;
    for (size_t ra = 0; ra < a.rowPixel.size(); ++ra) {
        std::map<int64_t, double> entries;
        for (It it(a.A, int(ra)); it; ++it) entries[it.col()] += it.value();
        auto f = rowB.find(a.rowPixel[ra]);
        if (f != rowB.end())
            for (It it(b.A, f->second); it; ++it) entries[it.col()] -= it.value();
        for (const auto& [col, d] : entries) {
            g.maxAbsDifference = std::max(g.maxAbsDifference, std::abs(d));
            if (std::abs(d) > ignoreBelow) ++g.unmatched;
        }
    }
    return g;
}

}  // namespace rg::pem
