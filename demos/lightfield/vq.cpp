// LBG / k-means vector quantization of light fields and their direct rendering through
// texture colour tables (Heidrich et al. 1999 §5).
#include "vq.h"

#include <Eigen/Dense>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <numeric>
#include <random>

#include "core/error.h"
#include "core/tsan_annotations.h"

namespace rg::lightfield {

namespace {

using Clock = std::chrono::steady_clock;
using MatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Block b's samples as floats in codeword order (parity order).
void gatherBlock(const LightField& lf, const BlockShape& sh, int bi, int bj, int bk, int bl, float* out) {
    int n = 0;
    for (int pt = 0; pt < sh.t; ++pt)
        for (int ps = 0; ps < sh.s; ++ps)
            for (int pv = 0; pv < sh.v; ++pv)
                for (int pu = 0; pu < sh.u; ++pu, ++n) {
                    const uint8_t* p = lf.data.data() + lf.offset(bi * sh.s + ps, bj * sh.t + pt, bk * sh.u + pu, bl * sh.v + pv);
                    out[3 * n] = p[0];
                    out[3 * n + 1] = p[1];
                    out[3 * n + 2] = p[2];
                }
}

// Nearest codeword of every row of X: ‖x − c‖² − ‖x‖² = ‖c‖² − 2 x·c, the row's minimum
// (the lowest index among equal ones, as Eigen's minCoeff) is the nearest codeword.
//
// Per chunk of kChunk rows, the codebook in tiles of kTile codewords: one Eigen product per
// tile into a column-major chunk × tile buffer reused by the thread (no fresh K-wide matrix
// per chunk: at K = 2^16 that was 256 MiB and its page faults), scanned column by column
// (contiguous) into a running minimum per row. Bit for bit the distances of the former
// single product per chunk (MatrixF d = (−2·(X_chunk·Cᵀ)).rowwise() + ‖c‖²): the same rows
// in each product (Eigen's kernel takes rows in steps of 4 to 12 and the leftover ones by
// other routes), tiles of a multiple of its column step with the last one taking the
// remainder, the depth (the block's dims) never split; test_lightfield_vq_assign.cpp
// compares both on float data whose labels rounding decides. (The encoding's distances are
// integers below 2^24, exact in any order; training's codebook is not.) Scanning the tiles
// in order with a strict < keeps the lowest index.
constexpr int kChunk = 1024;
constexpr int kTile = 128;

struct AssignScratch {
    std::vector<float> d;          // kChunk × (< 2·kTile), column-major
    std::vector<float> best;       // per row of the chunk
    std::vector<int> bestIndex;
};

void assignChunk(const MatrixF& X, const MatrixF& C, const Eigen::VectorXf& cn, Eigen::Index a, int n,
                 AssignScratch& s, int* label) {
    const int K = int(C.rows());
    s.best.assign(size_t(n), 0.0f);
    s.bestIndex.assign(size_t(n), 0);
    float* best = s.best.data();
    int* bestIndex = s.bestIndex.data();
    // A few rows (the last chunk's) take the codebook in one product, the former one: a
    // narrow tile beside them could make Eigen pick another route (a coefficient-wise
    // product below 20 rows + columns + depth, a matrix-vector one for one row).
    const int tile = n < 32 ? K : kTile;
    for (int j0 = 0; j0 < K;) {
        // The last tile takes the remainder (kTile to 2·kTile − 1 codewords): never a
        // single-column product.
        const int w = K - j0 < 2 * tile ? K - j0 : tile;
        if (s.d.size() < size_t(n) * size_t(w)) s.d.resize(size_t(n) * size_t(w));
        Eigen::Map<Eigen::MatrixXf> d(s.d.data(), n, w);
        d.noalias() = -2.0f * (X.middleRows(a, n) * C.middleRows(j0, w).transpose());
        int j = 0;
        if (j0 == 0) {  // minCoeff starts from coefficient 0
            const float* col = s.d.data();
            for (int i = 0; i < n; ++i) best[i] = col[i] + cn[0];
            j = 1;
        }
        for (; j < w; ++j) {
            const float* __restrict col = s.d.data() + size_t(j) * size_t(n);
            const float c = cn[j0 + j];
            const int k = j0 + j;
            float* __restrict bst = best;
            int* __restrict idx = bestIndex;
            // Branch-free, so that GCC vectorizes it: a strict < keeps the lowest index.
            for (int i = 0; i < n; ++i) {
                const float v = col[i] + c;
                const float b = bst[i];
                const int lower = -int(v < b);  // all ones where v is lower
                idx[i] = (idx[i] & ~lower) | (k & lower);
                bst[i] = v < b ? v : b;
            }
        }
        j0 += w;
    }
    std::copy(bestIndex, bestIndex + n, label);
}

void assign(const MatrixF& X, const MatrixF& C, std::vector<int>& label, int threads) {
    const Eigen::VectorXf cn = C.rowwise().squaredNorm();
    const int chunks = int((X.rows() + kChunk - 1) / kChunk);
    tbb::enumerable_thread_specific<AssignScratch> scratch;
    tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
    [[maybe_unused]] int forkJoin = 0;  // the address TSan's fork/join edges name
    RG_TSAN_RELEASE(&forkJoin);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, chunks), [&](const tbb::blocked_range<int>& r) {
            RG_TSAN_ACQUIRE(&forkJoin);
            AssignScratch& s = scratch.local();
            for (int c = r.begin(); c != r.end(); ++c) {
                const Eigen::Index a = Eigen::Index(c) * kChunk;
                const int n = int(std::min<Eigen::Index>(kChunk, X.rows() - a));
                assignChunk(X, C, cn, a, n, s, label.data() + a);
            }
            RG_TSAN_RELEASE(&forkJoin);
        });
    });
    // The per-thread scratch is destroyed here, after the join.
    RG_TSAN_ACQUIRE(&forkJoin);
}

// The index as an index texture holds it. The colour table reads entry
// round(v/(2^bits − 1)·(N − 1)) of N = K entries (docs/hardware.md, "Colour tables"), so v
// is the index scaled by (2^bits − 1)/(K − 1), rounded: the table's rounding gives the
// index back. 16 bits when K > 256 (I16), else 8 (I8).
uint32_t indexTexel(uint32_t idx, int K) {
    if (K > 256) return K == 65536 ? idx : uint32_t((uint64_t(idx) * 65535 * 2 + uint64_t(K - 1)) / (2 * uint64_t(K - 1)));
    return (idx * 255 * 2 + uint32_t(K - 1)) / (2 * uint32_t(K - 1));
}

void checkIndices(const VqLightField& vq) {
    for (size_t b = 0; b < vq.indices.size(); ++b)
        if (vq.indices[b] >= vq.K)
            throw Error("vq: block " + std::to_string(b) + " has codebook index " + std::to_string(vq.indices[b]) +
                        ", outside the codebook of " + std::to_string(vq.K));
}

// Table p: entry k = sample p of codeword k ("16 different tables, where each only returns
// a single color value"), alpha 255.
std::vector<std::shared_ptr<const tex::ColorTable>> parityTables(const VqLightField& vq) {
    std::vector<std::shared_ptr<const tex::ColorTable>> tables;
    const int D = vq.shape.dims();
    for (int parity = 0; parity < vq.shape.samples(); ++parity) {
        auto table = std::make_shared<tex::ColorTable>();
        table->format = tex::BaseFormat::Rgba;
        table->entries.resize(size_t(vq.K));
        for (int k = 0; k < vq.K; ++k) {
            const uint8_t* c = vq.codebook.data() + size_t(k) * D + size_t(3 * parity);
            table->entries[size_t(k)] = {c[0], c[1], c[2], 255};
        }
        tables.push_back(std::move(table));
    }
    return tables;
}

}  // namespace

std::vector<int> nearestCodewords(const float* blocks, int64_t rows, const float* codebook, int K, int dims, int threads) {
    const MatrixF X = Eigen::Map<const MatrixF>(blocks, rows, dims);
    const MatrixF C = Eigen::Map<const MatrixF>(codebook, K, dims);
    std::vector<int> label(static_cast<size_t>(rows));
    assign(X, C, label, threads);
    return label;
}

VqLightField quantize(const LightField& lf, const BlockShape& sh, const VqOptions& o) {
    if (lf.channels != 3) throw Error("vq: only RGB light fields are quantized");
    if (lf.slab.S % sh.s || lf.slab.T % sh.t || lf.slab.U % sh.u || lf.slab.V % sh.v)
        throw Error("vq: the block shape does not divide the slab");
    if (o.codebookSize < 2 || o.codebookSize > 65536) throw Error("vq: codebook size outside [2, 65536]");
    VqLightField vq;
    vq.slab = lf.slab;
    vq.shape = sh;
    vq.K = o.codebookSize;
    const int D = sh.dims();
    const int64_t N = int64_t(vq.blocksS()) * vq.blocksT() * vq.blocksU() * vq.blocksV();
    if (N < vq.K) throw Error("vq: " + std::to_string(N) + " blocks for " + std::to_string(vq.K) + " codewords");
    MatrixF X(N, D);
    {
        int64_t b = 0;
        for (int bj = 0; bj < vq.blocksT(); ++bj)
            for (int bi = 0; bi < vq.blocksS(); ++bi)
                for (int bl = 0; bl < vq.blocksV(); ++bl)
                    for (int bk = 0; bk < vq.blocksU(); ++bk, ++b) gatherBlock(lf, sh, bi, bj, bk, bl, X.row(b).data());
    }
    // ---- LBG on a random subset: K distinct blocks to start, then Lloyd iterations --------
    const auto t0 = Clock::now();
    std::mt19937_64 rng(o.seed);
    std::vector<int64_t> order(static_cast<size_t>(N));
    std::iota(order.begin(), order.end(), 0);
    std::shuffle(order.begin(), order.end(), rng);
    const int64_t M = std::min<int64_t>(N, std::max<int64_t>(o.trainingBlocks, vq.K));
    MatrixF T(M, D);
    for (int64_t i = 0; i < M; ++i) T.row(i) = X.row(order[size_t(i)]);
    MatrixF C = T.topRows(vq.K);
    std::vector<int> label(static_cast<size_t>(M));
    for (int it = 0; it < o.iterations; ++it) {
        assign(T, C, label, o.threads);
        MatrixF sum = MatrixF::Zero(vq.K, D);
        std::vector<int> count(size_t(vq.K), 0);
        for (int64_t i = 0; i < M; ++i) {
            sum.row(label[size_t(i)]) += T.row(i);
            ++count[size_t(label[size_t(i)])];
        }
        std::uniform_int_distribution<int64_t> pick(0, M - 1);
        for (int k = 0; k < vq.K; ++k)
            C.row(k) = count[size_t(k)] ? MatrixF(sum.row(k) / float(count[size_t(k)])) : MatrixF(T.row(pick(rng)));  // empty cell: a random block
    }
    vq.trainSeconds = std::chrono::duration<double>(Clock::now() - t0).count();
    // ---- encode every block --------------------------------------------------------------
    const auto t1 = Clock::now();
    vq.codebook.resize(size_t(vq.K) * size_t(D));
    for (int k = 0; k < vq.K; ++k)
        for (int d = 0; d < D; ++d) vq.codebook[size_t(k) * D + size_t(d)] = uint8_t(std::clamp(std::lround(C(k, d)), 0L, 255L));
    // Assign against the rounded codebook (what the tables hold).
    MatrixF Cq(vq.K, D);
    for (int k = 0; k < vq.K; ++k)
        for (int d = 0; d < D; ++d) Cq(k, d) = vq.codebook[size_t(k) * D + size_t(d)];
    std::vector<int> all(static_cast<size_t>(N));
    assign(X, Cq, all, o.threads);
    vq.indices.assign(all.begin(), all.end());
    vq.encodeSeconds = std::chrono::duration<double>(Clock::now() - t1).count();
    return vq;
}

LightField decode(const VqLightField& vq) {
    LightField lf;
    lf.slab = vq.slab;
    lf.channels = 3;
    lf.data.resize(vq.slab.samples() * 3);
    const int D = vq.shape.dims();
    for (int j = 0; j < vq.slab.T; ++j)
        for (int i = 0; i < vq.slab.S; ++i)
            for (int l = 0; l < vq.slab.V; ++l)
                for (int k = 0; k < vq.slab.U; ++k) {
                    const size_t b = vq.blockIndex(i / vq.shape.s, j / vq.shape.t, k / vq.shape.u, l / vq.shape.v);
                    const int idx = vq.indices[b];
                    if (idx >= vq.K)
                        throw Error("vq: block " + std::to_string(b) + " has codebook index " + std::to_string(idx) +
                                    ", outside the codebook of " + std::to_string(vq.K));
                    const uint8_t* c = vq.codebook.data() + size_t(idx) * D + size_t(3 * vq.parity(i, j, k, l));
                    std::copy(c, c + 3, lf.data.begin() + std::ptrdiff_t(lf.offset(i, j, k, l)));
                }
    return lf;
}

VqTextures::VqTextures(std::shared_ptr<tex::TextureMemory> memory, const VqLightField& vq) : vq_(&vq), memory_(memory) {
    const Profile& p = memory->profile();
    p.require(Feature::TextureColorTable, "VQ codebook decoding");
    p.requireLimit("texture colour table size (the VQ codebook)", vq.K, p.colorTableSize);
    checkIndices(vq);
    const tex::TextureDesc desc{tex::TextureTarget::Texture2D, vq.indexBytes() == 2 ? tex::TexelFormat::I16 : tex::TexelFormat::I8,
                                vq.blocksU(), vq.blocksV(), 1, 1, 1};
    const uint64_t basisBytes = 4;  // the 2×2 A8 texture below
    const bool fits = memory->residentBytes() + vq.indexTextureBytes() + basisBytes <= p.textureMemoryBytes;
    if (fits) {
        for (int bj = 0; bj < vq.blocksT(); ++bj)
            for (int bi = 0; bi < vq.blocksS(); ++bi) {
                auto t = memory->create(desc);
                memory->upload(*t, 0, 0, indexBytes(bi, bj));
                textures_.push_back(std::move(t));
            }
    } else {
        stream_ = memory->create(desc);
    }
    tables_ = parityTables(vq);
    // Fig. 5's texture: 2×2, exactly one texel one (texel (0, 0)); the parity is a shift.
    basis_ = memory->create({tex::TextureTarget::Texture2D, tex::TexelFormat::A8, 2, 2, 1, 1, 1});
    const uint8_t one[4] = {255, 0, 0, 0};
    memory->upload(*basis_, 0, 0, one);
}

std::vector<uint8_t> VqTextures::indexBytes(int bi, int bj) const {
    const bool wide = vq_->indexBytes() == 2;
    std::vector<uint8_t> bytes;
    bytes.reserve(size_t(vq_->blocksU()) * size_t(vq_->blocksV()) * 2);
    for (int bl = 0; bl < vq_->blocksV(); ++bl)
        for (int bk = 0; bk < vq_->blocksU(); ++bk) {
            const uint32_t v = indexTexel(vq_->indices[vq_->blockIndex(bi, bj, bk, bl)], vq_->K);
            bytes.push_back(uint8_t(v & 0xff));
            if (wide) bytes.push_back(uint8_t(v >> 8));
        }
    return bytes;
}

std::shared_ptr<const tex::Texture> VqTextures::indexTexture(int bi, int bj) const {
    const int k = bj * vq_->blocksS() + bi;
    if (!stream_) return textures_[size_t(k)];
    if (streamed_ != k) {
        memory_->upload(*stream_, 0, 0, indexBytes(bi, bj));
        streamed_ = k;
    }
    return stream_;
}

uint64_t VqTextures::textureBytes() const {
    uint64_t b = basis_->bytes();
    if (stream_) b += stream_->bytes();
    for (const auto& t : textures_) b += t->bytes();
    return b;
}

// The basis passes leave the last basis weight in the destination alpha: a full-window
// untextured quad writing alpha one (alpha only) makes the frame read as opaque. Both VQ
// routes end with it.
static void setAlphaToOne(raster::Device& dev, int w, int h) {
    raster::PipelineState a = additiveState();
    a.blend = 0;
    a.colorWriteMask = raster::kWriteA;
    dev.setState(a);
    dev.textureUnits().setStage(0, tex::StageState{});
    std::vector<raster::Vertex> q(6);
    const glm::vec2 c[6] = {{0, 0}, {float(w), 0}, {float(w), float(h)}, {0, 0}, {float(w), float(h)}, {0, float(h)}};
    for (int k = 0; k < 6; ++k) {
        q[size_t(k)].position = glm::vec4(c[k], 0.0f, 1.0f);
        q[size_t(k)].diffuse = {255, 255, 255, 255};
    }
    dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Pretransformed, q);
}

VqStats renderVq(raster::Device& dev, const VqTextures& tx, const VqLightField& vq, const ray::Camera& camera) {
    const LightSlab& s = vq.slab;
    const BlockShape& sh = vq.shape;
    const int w = dev.framebuffer().width(), h = dev.framebuffer().height();
    dev.setTransforms(glm::mat4(1.0f), viewMatrix(camera), projectionMatrix(camera, w, h));
    dev.setViewport({0, 0, w, h, 0.0f, 1.0f});
    dev.clear(true, {0, 0, 0, 0}, false, 1.0f);
    tex::TextureUnits& tu = dev.textureUnits();
    tex::SamplerState nearest;
    nearest.magFilter = nearest.minFilter = tex::FilterMode::Nearest;
    nearest.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                       tex::AddressMode::ClampToEdge};
    tex::SamplerState basisSampler;  // LINEAR, WRAP: the 2×2 texture replicated
    tex::TexGenState tg;
    tg.projected = true;
    tu.setTexGen(0, tg);
    const tex::BaseFormat decoded = tex::colorTableResultFormat(tex::BaseFormat::Intensity, tex::BaseFormat::Rgba);
    VqStats st;
    auto frags = [&] { return dev.counters().fragmentsGenerated; };
    // Eye points grouped by (s, t) parity so each table is loaded once per group.
    const int groups = sh.s * sh.t, uvParities = sh.u * sh.v;
    std::vector<raster::Vertex> verts;
    for (int g = 0; g < groups; ++g)
        for (int q = 0; q < uvParities; ++q) {
            const int pu = q % sh.u, pv = q / sh.u;
            const int parity = ((g / sh.s) * sh.s + g % sh.s) * uvParities + q;
            // A table load is new contents (the parity's table); the basis pass only turns the
            // table off (glDisable(TEXTURE_COLOR_TABLE_SGI)) and back on, keeping them.
            const tex::ColorTable* loaded = nullptr;
            for (int j = g / sh.s; j < s.T; j += sh.t)
                for (int i = g % sh.s; i < s.S; i += sh.s) {
                    const std::vector<StTriangle> tris = eyePointTriangles(s, i, j, Triangulation::FixedDiagonal);
                    if (tris.empty()) continue;
                    // Per vertex: the window coordinates, the index offset towards the
                    // hat's block (½ sample: +½ for even, −½ for odd samples), the basis
                    // coordinates (U/2 repetitions, shifted one texel per parity).
                    verts.clear();
                    for (const StTriangle& t : tris)
                        for (const glm::ivec2& gv : t.v) {
                            raster::Vertex v;
                            const glm::vec3 p = s.eyePoint(gv.x, gv.y);
                            v.position = glm::vec4(p, 1.0f);
                            const uint8_t wgt = gv == glm::ivec2(i, j) ? 255 : 0;
                            v.diffuse = {wgt, wgt, wgt, wgt};
                            const glm::vec2 uv = windowCoords(s, camera.eye, p);
                            v.tex[0] = glm::vec4(uv, 0.0f, 1.0f);
                            verts.push_back(v);
                        }
                    std::vector<raster::Vertex> colour = verts, basis = verts;
                    for (auto& v : colour) {
                        if (sh.u == 2) v.tex[0].x += (pu == 0 ? 0.5f : -0.5f) / float(s.U);
                        if (sh.v == 2) v.tex[0].y += (pv == 0 ? 0.5f : -0.5f) / float(s.V);
                    }
                    for (auto& v : basis) {
                        // Texel (0, 0) of the 2×2 texture sits on sample parity 0; one
                        // texel's shift (½ in these units) moves it onto parity 1.
                        v.tex[0].x = v.tex[0].x * float(s.U) * 0.5f - 0.5f * float(pu);
                        v.tex[0].y = v.tex[0].y * float(s.V) * 0.5f - 0.5f * float(pv);
                    }
                    if (sh.uvHalved()) {
                        // Pass A: basis × weight into the destination alpha.
                        raster::PipelineState a = additiveState();
                        a.blend = 0;
                        a.colorWriteMask = raster::kWriteA;
                        dev.setState(a);
                        tu.setColorTable(0, nullptr);
                        tu.setTexture(0, tx.basis());
                        tu.setSampler(0, basisSampler);
                        tu.setStage(0, tex::texEnvStage(tex::TexEnvMode::Modulate, tex::BaseFormat::Alpha));
                        const uint64_t f0 = frags();
                        dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, basis);
                        st.basisFragments += frags() - f0;
                        ++st.basisPasses;
                        // Pass B: the index through the parity's table, weighted by it.
                        raster::PipelineState b = additiveState();
                        b.srcBlend = raster::BlendFactor::DestAlpha;
                        b.colorWriteMask = raster::kWriteR | raster::kWriteG | raster::kWriteB;
                        dev.setState(b);
                        tu.setStage(0, tex::texEnvStage(tex::TexEnvMode::Replace, decoded));
                    } else {
                        dev.setState(additiveState());
                        tu.setStage(0, tex::texEnvStage(tex::TexEnvMode::Modulate, decoded));
                    }
                    if (loaded != tx.table(parity).get()) {
                        loaded = tx.table(parity).get();
                        ++st.tableLoads;
                    }
                    tu.setColorTable(0, tx.table(parity));
                    tu.setTexture(0, tx.indexTexture(i / sh.s, j / sh.t));
                    tu.setSampler(0, nearest);
                    const uint64_t f0 = frags();
                    dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, colour);
                    st.colorFragments += frags() - f0;
                    ++st.colorPasses;
                }
        }
    tu.setColorTable(0, nullptr);
    if (sh.uvHalved()) setAlphaToOne(dev, w, h);  // only the (u, v) basis passes wrote alpha
    return st;
}


// ---- §5 "4D VQ" -----------------------------------------------------------------------

const char* basisReadingName(BasisReading r) {
    return r == BasisReading::OneHot ? "one-hot" : "two pixels";
}

VqTextures4D::VqTextures4D(std::shared_ptr<tex::TextureMemory> memory, const VqLightField& vq, BasisReading reading)
    : reading_(reading) {
    const Profile& p = memory->profile();
    // Asked first, so a profile without 4D textures is named for what it lacks (the 2D
    // route of renderVq is a different algorithm, not a substitute).
    p.require(Feature::Texture4D, "4D-texture rendering of a VQ light field (Heidrich et al. 1999 §5)");
    p.require(Feature::TextureColorTable, "VQ codebook decoding");
    p.requireLimit("texture colour table size (the VQ codebook)", vq.K, p.colorTableSize);
    checkIndices(vq);
    // The index texture: texel (x, y, z, w) = block (bk, bl, bi, bj), the light field's
    // own (u, v, s, t) order, so the 4D coordinate of a ray addresses its block.
    const bool wide = vq.indexBytes() == 2;
    const int bu = vq.blocksU(), bv = vq.blocksV(), bs = vq.blocksS(), bt = vq.blocksT();
    index_ = memory->create({tex::TextureTarget::Texture4D, wide ? tex::TexelFormat::I16 : tex::TexelFormat::I8, bu, bv, bs, bt, 1});
    std::vector<uint8_t> bytes;
    bytes.reserve(vq.indices.size() * 2);
    for (int bj = 0; bj < bt; ++bj)
        for (int bi = 0; bi < bs; ++bi)
            for (int bl = 0; bl < bv; ++bl)
                for (int bk = 0; bk < bu; ++bk) {
                    const uint32_t v = indexTexel(vq.indices[vq.blockIndex(bi, bj, bk, bl)], vq.K);
                    bytes.push_back(uint8_t(v & 0xff));
                    if (wide) bytes.push_back(uint8_t(v >> 8));
                }
    memory->upload(*index_, 0, 0, bytes);
    tables_ = parityTables(vq);
    // The basis texture: one texel per parity class of the block, 2^4 for 2×2×2×2 (an axis
    // that is not halved has extent 1 and, under WRAP, a constant weight of one). One-hot:
    // texel 0 set; "two pixels": texel 0 and the opposite corner.
    const BlockShape& sh = vq.shape;
    basis_ = memory->create({tex::TextureTarget::Texture4D, tex::TexelFormat::A8, sh.u, sh.v, sh.s, sh.t, 1});
    std::vector<uint8_t> texels(size_t(sh.samples()), 0);
    texels.front() = 255;
    if (reading == BasisReading::TwoPixels) texels.back() = 255;
    memory->upload(*basis_, 0, 0, texels);
}

glm::vec4 window4DCoords(const LightSlab& s, const glm::vec3& eye, float wu, float wv) {
    const glm::vec3 p = s.windowPoint(wu, wv);
    const auto stuv = s.intersect(eye, p - eye);
    if (!stuv) throw Error("vq 4D: the camera lies in the window plane; no ray through the window crosses the eye-point plane");
    return s.textureCoords(*stuv);
}

VqStats renderVq4D(raster::Device& dev, const VqTextures4D& tx, const VqLightField& vq, const ray::Camera& camera,
                   Vq4DProbe* probe) {
    const LightSlab& s = vq.slab;
    const BlockShape& sh = vq.shape;
    const int w = dev.framebuffer().width(), h = dev.framebuffer().height();
    dev.setTransforms(glm::mat4(1.0f), viewMatrix(camera), projectionMatrix(camera, w, h));
    dev.setViewport({0, 0, w, h, 0.0f, 1.0f});
    dev.clear(true, {0, 0, 0, 0}, false, 1.0f);
    if (probe) probe->basisSum.assign(size_t(w) * size_t(h), 0);
    tex::TextureUnits& tu = dev.textureUnits();
    tex::SamplerState nearest;
    nearest.magFilter = nearest.minFilter = tex::FilterMode::Nearest;
    nearest.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                       tex::AddressMode::ClampToEdge};
    tex::SamplerState basisSampler;  // LINEAR (quadrilinear on a 4D texture), WRAP on s, t, r, q: replicated
    tex::TexGenState tg;
    tg.projected = true;  // GL's divide; SGIS_texture4D never divides q (texture_units.cpp)
    tu.setTexGen(0, tg);
    const tex::BaseFormat decoded = tex::colorTableResultFormat(tex::BaseFormat::Intensity, tex::BaseFormat::Rgba);
    // ---- the window polygon and its 4D coordinates ------------------------------------------
    // Two triangles over the window, corners (0, 0), (1, 0), (1, 1), (0, 1) in window
    // fractions. Each vertex's (u, v, s, t) is where the ray from the camera through it
    // crosses the two planes: affine in the window point (both planes are z = const), so
    // the interpolated coordinate of every fragment is its own ray's.
    const glm::vec2 corner[6] = {{0, 0}, {1, 0}, {1, 1}, {0, 0}, {1, 1}, {0, 1}};
    std::array<glm::vec4, 6> coord;
    std::vector<raster::Vertex> base(6);
    for (int k = 0; k < 6; ++k) {
        coord[size_t(k)] = window4DCoords(s, camera.eye, corner[k].x, corner[k].y);
        base[size_t(k)].position = glm::vec4(s.windowPoint(corner[k].x, corner[k].y), 1.0f);
        base[size_t(k)].diffuse = {255, 255, 255, 255};
    }
    const glm::ivec4 halved(sh.u == 2, sh.v == 2, sh.s == 2, sh.t == 2);
    const glm::vec4 n(float(s.U), float(s.V), float(s.S), float(s.T));
    VqStats st;
    auto frags = [&] { return dev.counters().fragmentsGenerated; };
    std::vector<raster::Vertex> colour = base, basis = base;
    for (int parity = 0; parity < sh.samples(); ++parity) {
        // The inverse of VqLightField::parity: ((pt·s + ps)·v + pv)·u + pu.
        const glm::ivec4 pb(parity % sh.u, (parity / sh.u) % sh.v, (parity / (sh.u * sh.v)) % sh.s,
                            parity / (sh.u * sh.v * sh.s));
        for (int k = 0; k < 6; ++k) {
            const glm::vec4 c = coord[size_t(k)];
            glm::vec4 ci = c, cb = c;
            for (int a = 0; a < 4; ++a) {
                if (!halved[a]) continue;
                // Index: ½ sample towards the hat's block (+½ even, −½ odd), as renderVq.
                ci[a] += (pb[a] == 0 ? 0.5f : -0.5f) / n[a];
                // Basis: N/2 repetitions of the 2-texel axis; texel 0's centre on the even
                // samples, one texel's shift (½ in these units) onto the odd ones.
                cb[a] = c[a] * n[a] * 0.5f - 0.5f * float(pb[a]);
            }
            colour[size_t(k)].tex[0] = ci;
            basis[size_t(k)].tex[0] = cb;
        }
        // Pass A: the basis into the destination alpha (REPLACE: the texture's alpha).
        raster::PipelineState a = additiveState();
        a.blend = 0;
        a.colorWriteMask = raster::kWriteA;
        dev.setState(a);
        tu.setColorTable(0, nullptr);
        tu.setTexture(0, tx.basis());
        tu.setSampler(0, basisSampler);
        tu.setStage(0, tex::texEnvStage(tex::TexEnvMode::Replace, tex::BaseFormat::Alpha));
        uint64_t f0 = frags();
        dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, basis);
        st.basisFragments += frags() - f0;
        ++st.basisPasses;
        if (probe) {
            const std::vector<Rgba8> px = dev.readPixels(0, 0, w, h);
            for (size_t i = 0; i < px.size(); ++i) probe->basisSum[i] += px[i].a;
        }
        // Pass B: the block's index through this parity's table, weighted by the basis.
        raster::PipelineState b = additiveState();
        b.srcBlend = raster::BlendFactor::DestAlpha;
        b.colorWriteMask = raster::kWriteR | raster::kWriteG | raster::kWriteB;
        dev.setState(b);
        tu.setStage(0, tex::texEnvStage(tex::TexEnvMode::Replace, decoded));
        tu.setColorTable(0, tx.table(parity));
        ++st.tableLoads;
        tu.setTexture(0, tx.indexTexture());
        tu.setSampler(0, nearest);
        f0 = frags();
        dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, colour);
        st.colorFragments += frags() - f0;
        ++st.colorPasses;
    }
    tu.setColorTable(0, nullptr);
    setAlphaToOne(dev, w, h);
    return st;
}

}  // namespace rg::lightfield
