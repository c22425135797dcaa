#include "inference.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <limits>
#include <tuple>

#include <immintrin.h>
#include <tbb/parallel_for.h>

#include "core/cpu.h"
#include "core/error.h"

namespace rg::pem {

// ---- conjugate gradient for several channels, in few passes, on every core ------------------
//
// Nearly all of a view's inference is conjugate gradient. At paper settings each of a view's
// six systems has 0.5 M texels and H 4.2-4.9 M entries, and takes 230-420 steps; the core
// retires ~2.4 instructions a cycle through it (perf stat), so what a step costs is mostly
// the instructions it takes. The channels of one map (R, G, B; hybrid's four) share H and
// step together:
//   1. one pass over H computes every channel's product y = (H + P) p and, in the same pass,
//      p·y; the channels' operands are packed four to a texel, so that with AVX2 one
//      instruction multiplies an entry of H into all four (PackedOperands);
//   2. a second pass updates x and r and sums r·r and r·M⁻¹r;
//   3. a third sets the next direction p = M⁻¹r + βp.
// M is the diagonal (Jacobi) preconditioner and every step is Eigen's conjugate_gradient's
// (ConjugateGradient.h) expression for expression, but where Eigen's reads the vectors in six
// passes with its dot products on one thread, here three passes on every core do it.
// Measured on one paper view (docs/performance.md): 321 G instructions and 135 G cycles of
// the whole view before, 194 G and 109 G after.
//
// Bit for bit on any thread count: every pass is split into blocks of fixed size; a row of a
// product is one sum over the row's entries in storage order, then the channel's pin (its
// diagonal weight of this round) times v_i; every dot product is the sum, in block order, of
// each block's sum over four interleaved lanes (Lanes). Nothing depends on which thread ran
// which block, on the kernel (AVX2 or the plain loop, packed or one channel alone: their
// lanes do the same IEEE operations in the same order), or on the other channels. The sums'
// order differs from Eigen's, so the result is Eigen's solution to its rounding, not its bits
// (tests/pem/test_inference_threads.cpp checks all of these).
namespace {

// Rows per task of a product: a task's rows of H (~9 entries each, 12 bytes an entry:
// ~110 KB) and the channels' operands near them stay in L2.
constexpr int64_t kRowsPerTask = 1024;
// Elements per task, and per partial sum, of the element-wise passes (a multiple of four:
// Lanes).
constexpr int64_t kElementsPerTask = 16384;
static_assert(kElementsPerTask % 4 == 0);

// Four interleaved partial sums over one block (element i to lane i mod 4): independent
// additions the compiler can pipeline and vectorise without reassociating anything, in an
// order fixed by the block alone.
struct Lanes {
    double s[4] = {0.0, 0.0, 0.0, 0.0};
    void add(int64_t i, double v) { s[i & 3] += v; }
    double total() const { return (s[0] + s[1]) + (s[2] + s[3]); }
};

// One channel's solve: Eigen's conjugate_gradient as a state machine that stops whenever it
// needs y = (H + P) v, P the channel's diagonal pins of this round.
struct ChannelSolve {
    enum class Need { Residual, Direction, Done };
    Need need = Need::Residual;
    Eigen::VectorXd rhs, x, pinWeight, pinValue;      // across rounds
    Eigen::VectorXd rp, diagonal, invDiagonal;        // this round: rhs + P·pins, diag(H + P)
    Eigen::VectorXd residual, p, y;                   // conjugate gradient's vectors
    std::vector<double> partial;                      // per block: the pass's partial sums
    double threshold = 0, residualNorm2 = 0, absNew = 0, alpha = 0, beta = 0;
    Eigen::Index i = 0;
    int round = 0;
    InferenceStats stats;
    double* packedV = nullptr;                        // its slot of its group's operands,
    double* packedPin = nullptr;                      // stride 4; nullptr: a group of one
    const Eigen::VectorXd& operand() const { return need == Need::Residual ? x : p; }
};

// H's rows for the product: H is symmetric, so column i of the column-major matrix is row i.
struct NormalRows {
    const double* values;
    const int* inner;
    const int* outer;
};

NormalRows normalRows(const Eigen::SparseMatrix<double>& H) {
    return {H.valuePtr(), H.innerIndexPtr(), H.outerIndexPtr()};
}

// One channel's product y = (H + P) v over rows [begin, end), and py += v_i y_i row by row.
// A row is one sum: its entries of H in storage order, then the channel's pin of this round
// (P's diagonal) times v_i. One loop a row, no split at the diagonal: a row's end is the
// branch the core mispredicts, so one per row, not two.
void productRows(int64_t begin, int64_t end, const NormalRows& H, const double* v,
                 const double* pin, double* y, double& py) {
    for (int64_t i = begin; i < end; ++i) {
        double sum = 0.0;
        for (int k = H.outer[i]; k < H.outer[i + 1]; ++k) sum += H.values[k] * v[H.inner[k]];
        sum += pin[i] * v[i];
        y[i] = sum;
        py += v[i] * sum;
    }
}

// Channels that share H step together, four to a group, their operands packed: slot s of
// texel i at v[4 i + s] (and the pins likewise), so that one entry of H and one cache line of
// operands serve the group's four sums. Each slot's sum is the one-channel kernel's, term for
// term: the same bits whichever kernel runs (tests/pem/test_inference_threads.cpp).
constexpr int kSlots = 4;
struct PackedOperands {
    const double* v;    // 4 n
    const double* pin;  // 4 n
    double* y[kSlots];  // nullptr: slot idle (an empty slot, or a channel done)
};

// The plain loop, and the reference for the AVX2 one.
void packedProductRowsScalar(int64_t begin, int64_t end, const NormalRows& H,
                             const PackedOperands& ops, double* py) {
    for (int64_t i = begin; i < end; ++i) {
        double sum[kSlots] = {0.0, 0.0, 0.0, 0.0};
        for (int k = H.outer[i]; k < H.outer[i + 1]; ++k)
            for (int c = 0; c < kSlots; ++c) sum[c] += H.values[k] * ops.v[kSlots * H.inner[k] + c];
        const double* vi = ops.v + kSlots * i;
        const double* pin = ops.pin + kSlots * i;
        for (int c = 0; c < kSlots; ++c) {
            sum[c] += pin[c] * vi[c];
            if (ops.y[c]) ops.y[c][i] = sum[c];
            py[c] += vi[c] * sum[c];
        }
    }
}

// The same with the four slots in one AVX2 register: separate multiplies and adds (no FMA),
// lane for lane the scalar operations.
__attribute__((target("avx2"))) void packedProductRowsAvx2(int64_t begin, int64_t end,
                                                           const NormalRows& H,
                                                           const PackedOperands& ops, double* py) {
    __m256d pySum = _mm256_loadu_pd(py);
    for (int64_t i = begin; i < end; ++i) {
        __m256d sum = _mm256_setzero_pd();
        for (int k = H.outer[i]; k < H.outer[i + 1]; ++k)
            sum = _mm256_add_pd(sum, _mm256_mul_pd(_mm256_set1_pd(H.values[k]),
                                                   _mm256_loadu_pd(ops.v + kSlots * H.inner[k])));
        const __m256d vi = _mm256_loadu_pd(ops.v + kSlots * i);
        sum = _mm256_add_pd(sum, _mm256_mul_pd(_mm256_loadu_pd(ops.pin + kSlots * i), vi));
        alignas(32) double t[kSlots];
        _mm256_store_pd(t, sum);
        for (int c = 0; c < kSlots; ++c)
            if (ops.y[c]) ops.y[c][i] = t[c];
        pySum = _mm256_add_pd(pySum, _mm256_mul_pd(vi, sum));
    }
    _mm256_storeu_pd(py, pySum);
}

}  // namespace

int TexelLayout::levels() const {
    int n = 1;
    for (int s = baseSize; s > 1; s >>= 1) ++n;
    return n;
}

int64_t TexelLayout::levelOffset(int level) const {
    int64_t off = 0;
    for (int l = 0; l < level; ++l) off += int64_t(faces) * levelSize(l) * levelSize(l);
    return off;
}

int64_t TexelLayout::index(int level, int face, int x, int y) const {
    int s = levelSize(level);
    return levelOffset(level) + (int64_t(face) * s + y) * s + x;
}

int64_t TexelLayout::count() const { return levelOffset(levels()); }

int RenderingMatrix::finestLevelAccessed() const {
    int64_t firstCol = -1;
    for (int k = 0; k < A.outerSize(); ++k)
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(A, k); it; ++it)
            if (it.value() > 0 && (firstCol < 0 || it.col() < firstCol)) firstCol = it.col();
    if (firstCol < 0) return -1;
    for (int l = layout.levels() - 1; l >= 0; --l)
        if (firstCol >= layout.levelOffset(l)) return l;
    return 0;
}

namespace {

// The regulariser R = λ·Σ_neighbours (x_i − x_j)² + κ·Σ_parents (x_p − mean children)²,
// as a sparse symmetric matrix (the quadratic form's Hessian / 2).
Eigen::SparseMatrix<double> regulariser(const TexelLayout& L, const InferenceOptions& o) {
    std::vector<Eigen::Triplet<double>> t;
    auto addDiff = [&](int64_t i, int64_t j, double w) {  // w (x_i − x_j)²
        t.emplace_back(i, i, w);
        t.emplace_back(j, j, w);
        t.emplace_back(i, j, -w);
        t.emplace_back(j, i, -w);
    };
    for (int l = 0; l < L.levels(); ++l) {
        int s = L.levelSize(l);
        for (int f = 0; f < L.faces; ++f)
            for (int y = 0; y < s; ++y)
                for (int x = 0; x < s; ++x) {
                    int64_t i = L.index(l, f, x, y);
                    if (x + 1 < s) addDiff(i, L.index(l, f, x + 1, y), o.smoothness);
                    if (y + 1 < s) addDiff(i, L.index(l, f, x, y + 1), o.smoothness);
                    if (l > 0 && o.levelCoupling > 0) {
                        // (x_p − ¼Σ c_k)²: gradient terms over {p, c0..c3}
                        int64_t ids[5] = {i, L.index(l - 1, f, 2 * x, 2 * y),
                                          L.index(l - 1, f, std::min(2 * x + 1, L.levelSize(l - 1) - 1), 2 * y),
                                          L.index(l - 1, f, 2 * x, std::min(2 * y + 1, L.levelSize(l - 1) - 1)),
                                          L.index(l - 1, f, std::min(2 * x + 1, L.levelSize(l - 1) - 1),
                                                  std::min(2 * y + 1, L.levelSize(l - 1) - 1))};
                        double c[5] = {1.0, -0.25, -0.25, -0.25, -0.25};
                        for (int a = 0; a < 5; ++a)
                            for (int b = 0; b < 5; ++b)
                                t.emplace_back(ids[a], ids[b], o.levelCoupling * c[a] * c[b]);
                    }
                }
    }
    Eigen::SparseMatrix<double> R(L.count(), L.count());
    R.setFromTriplets(t.begin(), t.end());
    return R;
}

// The regulariser depends only on the layout and the weights, and every layer of every
// view of a PEM shares them: build it once per process.
std::shared_ptr<const Eigen::SparseMatrix<double>> cachedRegulariser(const TexelLayout& L,
                                                                     const InferenceOptions& o) {
    static std::mutex mutex;
    static std::map<std::tuple<int, int, double, double>,
                    std::shared_ptr<const Eigen::SparseMatrix<double>>> cache;
    auto key = std::make_tuple(L.baseSize, L.faces, o.smoothness, o.levelCoupling);
    // Built under the lock: the systems of a view are built side by side and all need the
    // same R, so the others wait for it rather than each building their own.
    std::lock_guard lock(mutex);
    if (auto it = cache.find(key); it != cache.end()) return it->second;
    auto R = std::make_shared<const Eigen::SparseMatrix<double>>(regulariser(L, o));
    return cache.emplace(key, R).first->second;
}

}  // namespace

InferenceSystem::InferenceSystem(const RenderingMatrix& m, const InferenceOptions& o)
    : InferenceSystem(std::vector<WeightedMatrix>{{&m, {}}}, o) {}

InferenceSystem::InferenceSystem(std::vector<WeightedMatrix> blocks, const InferenceOptions& o)
    : blocks_(std::move(blocks)), o_(o) {
    if (blocks_.empty()) throw Error("inference: a system of no rendering matrix");
    const TexelLayout& L = blocks_[0].m->layout;
    const int64_t n = L.count();
    H_.resize(n, n);
    for (const WeightedMatrix& b : blocks_) {
        const RenderingMatrix& m = *b.m;
        if (m.A.cols() != n || m.layout.baseSize != L.baseSize || m.layout.faces != L.faces)
            throw Error("rendering matrix has the wrong number of columns");
        if (b.confidence.size() && b.confidence.size() != m.A.rows())
            throw Error("inference: a confidence per row of the rendering matrix is needed");
        // Normal equations of  Σ_k ‖C_k(A_k x − b_k)‖² + xᵀRx + μ‖x − x̄‖².
        Eigen::SparseMatrix<double> At = m.A.transpose();
        if (b.confidence.size()) {
            const Eigen::VectorXd c2 = b.confidence.cwiseProduct(b.confidence);
            At = At * c2.asDiagonal();
        }
        H_ += At * m.A;
        AtC2_.push_back(std::move(At));
    }
    H_ += *cachedRegulariser(L, o);
    Eigen::SparseMatrix<double> I(n, n);
    I.setIdentity();
    H_ += o.prior * I;
}

Eigen::VectorXd InferenceSystem::solve(const Eigen::VectorXd& b, InferenceStats* stats) const {
    return solve(std::vector<Eigen::VectorXd>{b}, stats);
}

Eigen::VectorXd InferenceSystem::solve(const std::vector<Eigen::VectorXd>& bs,
                                       InferenceStats* stats) const {
    std::vector<InferenceStats> st;
    Eigen::VectorXd x = std::move(solveChannels({bs}, stats ? &st : nullptr).at(0));
    if (stats) *stats = st.at(0);
    return x;
}

std::vector<Eigen::VectorXd> InferenceSystem::solveChannels(
    const std::vector<std::vector<Eigen::VectorXd>>& channels,
    std::vector<InferenceStats>* stats) const {
    const int64_t n = layout().count();
    const InferenceOptions& o = o_;
    const Eigen::VectorXd hDiagonal = H_.diagonal();
    std::vector<ChannelSolve> solves(channels.size());

    // ---- per channel: the right-hand side, the prior's target, the guess -------------------
    for (size_t c = 0; c < channels.size(); ++c) {
        const std::vector<Eigen::VectorXd>& bs = channels[c];
        if (bs.size() != blocks_.size()) throw Error("inference: one right-hand side per block");
        // The prior's target: the mean of b, each row weighted as in the least squares.
        double wsum = 0.0, bsum = 0.0;
        Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
        for (size_t k = 0; k < bs.size(); ++k) {
            const Eigen::VectorXd& b = bs[k];
            if (b.size() != blocks_[k].m->A.rows())
                throw Error("layer image does not match the rendering matrix rows");
            const Eigen::VectorXd& conf = blocks_[k].confidence;
            if (conf.size()) {
                const Eigen::VectorXd c2 = conf.cwiseProduct(conf);
                wsum += c2.sum();
                bsum += c2.dot(b);
            } else {
                wsum += double(b.size());
                bsum += b.sum();
            }
            rhs += AtC2_[k] * b;
        }
        const double mean = wsum > 0 ? bsum / wsum : 0.5;
        rhs.array() += o.prior * mean;
        ChannelSolve& s = solves[c];
        s.rhs = std::move(rhs);
        s.x = Eigen::VectorXd::Constant(n, mean);
        s.pinWeight = Eigen::VectorXd::Zero(n);
        s.pinValue = Eigen::VectorXd::Zero(n);
    }

    // ---- the steps of one channel between two passes (Eigen's conjugate_gradient) ----------
    const double tol = o.tolerance;
    const Eigen::Index maxIters = o.maxIterations;
    const int64_t elementBlocks = (n + kElementsPerTask - 1) / kElementsPerTask;
    const int64_t rowBlocks = (n + kRowsPerTask - 1) / kRowsPerTask;
    auto startRound = [&](ChannelSolve& s) {
        // Round 0 solves H x = rhs; later rounds pin texels outside [0, 1] to the bound with a
        // strong diagonal weight, H + P, so their neighbours compensate.
        s.rp = s.rhs;
        if (s.round > 0) s.rp += s.pinWeight.cwiseProduct(s.pinValue);
        s.diagonal = s.round > 0 ? Eigen::VectorXd(hDiagonal + s.pinWeight) : hDiagonal;
        s.invDiagonal = s.diagonal;
        for (int64_t i = 0; i < n; ++i)  // DiagonalPreconditioner: 1 where the diagonal is 0
            s.invDiagonal[i] = s.invDiagonal[i] != 0.0 ? 1.0 / s.invDiagonal[i] : 1.0;
        s.residual.resize(n);
        s.p.resize(n);
        s.need = ChannelSolve::Need::Residual;
        if (s.packedV)  // the round's first product is H x, with this round's pins
            for (int64_t i = 0; i < n; ++i) {
                s.packedV[kSlots * i] = s.x[i];
                s.packedPin[kSlots * i] = s.pinWeight[i];
            }
    };
    auto endRound = [&](ChannelSolve& s) {
        s.stats.iterations += int(s.i);
        // Texels outside [0, 1] cannot be stored in an 8-bit texture: pin them (next round).
        bool any = false;
        for (int64_t i = 0; i < n; ++i)
            if (s.x[i] < 0.0 || s.x[i] > 1.0) {
                if (s.pinWeight[i] == 0) any = true;
                s.pinWeight[i] = 10.0 * (s.diagonal[i] + 1.0);
                s.pinValue[i] = s.x[i] < 0.0 ? 0.0 : 1.0;
            }
        if (!any || s.round == o.boundRounds) {
            s.need = ChannelSolve::Need::Done;
            return;
        }
        ++s.round;
        startRound(s);
    };
    // An element-wise pass over every channel in `cs`, on every core in fixed blocks:
    // f(s, begin, end, sums) does elements [begin, end) of channel s and adds to its K sums,
    // which come back in s.partial[0..K), each the blocks' sums in block order.
    auto elementPass = [&](const std::vector<ChannelSolve*>& cs, int K, auto f) {
        for (ChannelSolve* s : cs) s->partial.assign(size_t(elementBlocks * K), 0.0);
        tbb::parallel_for(int64_t(0), elementBlocks, [&](int64_t b) {
            const int64_t begin = b * kElementsPerTask, end = std::min(n, begin + kElementsPerTask);
            for (ChannelSolve* s : cs) {
                Lanes sums[3];
                f(*s, begin, end, sums);
                for (int k = 0; k < K; ++k) s->partial[size_t(b * K + k)] = sums[k].total();
            }
        });
        for (ChannelSolve* s : cs)
            for (int k = 0; k < K; ++k) {
                double total = 0.0;
                for (int64_t b = 0; b < elementBlocks; ++b) total += s->partial[size_t(b * K + k)];
                s->partial[size_t(k)] = total;
            }
    };
    // Groups of four channels; a group of several packs its operands (PackedOperands).
    struct Group {
        size_t first = 0, count = 0;
        std::vector<double> v, pin;
    };
    std::vector<Group> groups;
    for (size_t c = 0; c < solves.size(); c += kSlots) {
        Group& g = groups.emplace_back();
        g.first = c;
        g.count = std::min(solves.size() - c, size_t(kSlots));
        if (g.count == 1) continue;
        g.v.assign(size_t(n) * kSlots, 0.0);
        g.pin.assign(size_t(n) * kSlots, 0.0);
        for (size_t k = 0; k < g.count; ++k) {
            solves[c + k].packedV = g.v.data() + k;
            solves[c + k].packedPin = g.pin.data() + k;
        }
    }
    for (ChannelSolve& s : solves) startRound(s);

    const NormalRows H = normalRows(H_);
    const bool avx2 = avx2Enabled() && !o.scalarProducts;
    std::vector<double> pyPartial;
    for (;;) {
        std::vector<ChannelSolve*> active;
        for (ChannelSolve& s : solves)
            if (s.need != ChannelSolve::Need::Done) {
                s.y.resize(n);
                active.push_back(&s);
            }
        if (active.empty()) break;

        // ---- pass 1: y = (H + P) v for every channel, and p·y of those stepping -------------
        // A row's sum is its entries of H in storage order, then the channel's pin times v_i
        // (productRows). A group of several channels runs the packed kernel over all four
        // slots and keeps the sums of those not done; p·y is summed row by row within a
        // block, and the blocks in order.
        const size_t N = solves.size();
        pyPartial.assign(size_t(rowBlocks) * N, 0.0);
        tbb::parallel_for(int64_t(0), rowBlocks, [&](int64_t block) {
            const int64_t begin = block * kRowsPerTask, end = std::min(n, begin + kRowsPerTask);
            double* py = pyPartial.data() + size_t(block) * N;
            for (Group& g : groups) {
                ChannelSolve* first = &solves[g.first];
                if (g.count == 1) {
                    if (first->need != ChannelSolve::Need::Done)
                        productRows(begin, end, H, first->operand().data(), first->pinWeight.data(),
                                    first->y.data(), py[g.first]);
                    continue;
                }
                PackedOperands ops{g.v.data(), g.pin.data(), {nullptr, nullptr, nullptr, nullptr}};
                bool any = false;
                for (size_t k = 0; k < g.count; ++k)
                    if (solves[g.first + k].need != ChannelSolve::Need::Done) {
                        ops.y[k] = solves[g.first + k].y.data();
                        any = true;
                    }
                if (!any) continue;
                double sums[kSlots] = {0.0, 0.0, 0.0, 0.0};
                if (avx2) packedProductRowsAvx2(begin, end, H, ops, sums);
                else packedProductRowsScalar(begin, end, H, ops, sums);
                for (size_t k = 0; k < g.count; ++k) py[g.first + k] = sums[k];
            }
        });

        // ---- residual channels (a round's first product): r = rp − H x, p = M⁻¹ r ----------
        std::vector<ChannelSolve*> starting, stepping;
        for (ChannelSolve* s : active) {
            if (s->need == ChannelSolve::Need::Residual) {
                starting.push_back(s);
            } else {
                const size_t c = size_t(s - solves.data());
                double py = 0.0;
                for (int64_t b = 0; b < rowBlocks; ++b) py += pyPartial[size_t(b) * N + c];
                s->alpha = s->absNew / py;
                stepping.push_back(s);
            }
        }
        if (!starting.empty()) {
            elementPass(starting, 3, [](ChannelSolve& s, int64_t begin, int64_t end, Lanes* sums) {
                const double *rp = s.rp.data(), *y = s.y.data(), *inv = s.invDiagonal.data();
                double *r = s.residual.data(), *p = s.p.data();
                double* packed = s.packedV;
                for (int64_t i = begin; i < end; ++i) {
                    r[i] = rp[i] - y[i];
                    p[i] = inv[i] * r[i];
                    if (packed) packed[kSlots * i] = p[i];
                    sums[0].add(i, rp[i] * rp[i]);
                    sums[1].add(i, r[i] * r[i]);
                    sums[2].add(i, r[i] * p[i]);
                }
            });
            for (ChannelSolve* s : starting) {
                const double rhsNorm2 = s->partial[0];
                s->i = 0;
                if (rhsNorm2 == 0) {
                    s->x.setZero();
                    endRound(*s);
                    continue;
                }
                s->threshold = std::max(tol * tol * rhsNorm2, std::numeric_limits<double>::min());
                s->residualNorm2 = s->partial[1];
                if (s->residualNorm2 < s->threshold || maxIters <= 0) {
                    endRound(*s);
                    continue;
                }
                s->absNew = s->partial[2];
                s->need = ChannelSolve::Need::Direction;
            }
        }

        // ---- pass 2: x += α p, r −= α y; r·r and r·M⁻¹r -------------------------------------
        if (stepping.empty()) continue;
        elementPass(stepping, 2, [](ChannelSolve& s, int64_t begin, int64_t end, Lanes* sums) {
            // Lanes 0-1 and 2-3 in one SSE2 register each (x86-64's baseline: the same IEEE
            // operations as the scalar code, two at a time). Blocks start at multiples of four.
            const __m128d alpha = _mm_set1_pd(s.alpha);
            const double *p = s.p.data(), *y = s.y.data(), *inv = s.invDiagonal.data();
            double *x = s.x.data(), *r = s.residual.data();
            __m128d rr01 = _mm_setzero_pd(), rr23 = _mm_setzero_pd();
            __m128d rz01 = _mm_setzero_pd(), rz23 = _mm_setzero_pd();
            int64_t i = begin;
            for (; i + 4 <= end; i += 4) {
                // x += α p
                _mm_storeu_pd(x + i, _mm_add_pd(_mm_loadu_pd(x + i), _mm_mul_pd(alpha, _mm_loadu_pd(p + i))));
                _mm_storeu_pd(x + i + 2, _mm_add_pd(_mm_loadu_pd(x + i + 2),
                                                    _mm_mul_pd(alpha, _mm_loadu_pd(p + i + 2))));
                // r −= α y; r·r += r r; r·z += r (M⁻¹ r)
                const __m128d r01 = _mm_sub_pd(_mm_loadu_pd(r + i), _mm_mul_pd(alpha, _mm_loadu_pd(y + i)));
                const __m128d r23 = _mm_sub_pd(_mm_loadu_pd(r + i + 2), _mm_mul_pd(alpha, _mm_loadu_pd(y + i + 2)));
                _mm_storeu_pd(r + i, r01);
                _mm_storeu_pd(r + i + 2, r23);
                rr01 = _mm_add_pd(rr01, _mm_mul_pd(r01, r01));
                rr23 = _mm_add_pd(rr23, _mm_mul_pd(r23, r23));
                rz01 = _mm_add_pd(rz01, _mm_mul_pd(r01, _mm_mul_pd(_mm_loadu_pd(inv + i), r01)));
                rz23 = _mm_add_pd(rz23, _mm_mul_pd(r23, _mm_mul_pd(_mm_loadu_pd(inv + i + 2), r23)));
            }
            double rr[4], rz[4];
            _mm_storeu_pd(rr, rr01);
            _mm_storeu_pd(rr + 2, rr23);
            _mm_storeu_pd(rz, rz01);
            _mm_storeu_pd(rz + 2, rz23);
            for (; i < end; ++i) {
                x[i] += s.alpha * p[i];
                r[i] -= s.alpha * y[i];
                rr[i & 3] += r[i] * r[i];
                rz[i & 3] += r[i] * (inv[i] * r[i]);
            }
            for (int l = 0; l < 4; ++l) {
                sums[0].s[l] = rr[l];
                sums[1].s[l] = rz[l];
            }
        });
        std::vector<ChannelSolve*> onward;
        for (ChannelSolve* s : stepping) {
            s->residualNorm2 = s->partial[0];
            if (s->residualNorm2 < s->threshold) {
                endRound(*s);
                continue;
            }
            const double absOld = s->absNew;
            s->absNew = s->partial[1];
            s->beta = s->absNew / absOld;
            onward.push_back(s);
        }

        // ---- pass 3: p = M⁻¹ r + β p ---------------------------------------------------------
        if (onward.empty()) continue;
        elementPass(onward, 0, [](ChannelSolve& s, int64_t begin, int64_t end, Lanes*) {
            const __m128d beta = _mm_set1_pd(s.beta);
            const double *r = s.residual.data(), *inv = s.invDiagonal.data();
            double* p = s.p.data();
            double* packed = s.packedV;
            int64_t i = begin;
            for (; i + 2 <= end; i += 2) {
                const __m128d pi = _mm_add_pd(_mm_mul_pd(_mm_loadu_pd(inv + i), _mm_loadu_pd(r + i)),
                                              _mm_mul_pd(beta, _mm_loadu_pd(p + i)));
                _mm_storeu_pd(p + i, pi);
                if (packed) {
                    _mm_storel_pd(packed + kSlots * i, pi);
                    _mm_storeh_pd(packed + kSlots * (i + 1), pi);
                }
            }
            for (; i < end; ++i) {
                p[i] = inv[i] * r[i] + s.beta * p[i];
                if (packed) packed[kSlots * i] = p[i];
            }
        });
        for (ChannelSolve* s : onward)
            if (++s->i >= maxIters) endRound(*s);
    }

    // ---- clamp, and how well each channel's clamped map reproduces its b ---------------------
    std::vector<Eigen::VectorXd> xs;
    if (stats) stats->clear();
    for (size_t c = 0; c < solves.size(); ++c) {
        ChannelSolve& s = solves[c];
        Eigen::VectorXd& x = s.x;
        for (int64_t i = 0; i < n; ++i) {
            if (x[i] < 0.0 || x[i] > 1.0) ++s.stats.clampedTexels;
            x[i] = std::clamp(x[i], 0.0, 1.0);
        }
        double num = 0.0, den = 0.0;
        for (size_t k = 0; k < blocks_.size(); ++k) {
            Eigen::VectorXd r = blocks_[k].m->A * x - channels[c][k];
            Eigen::VectorXd b = channels[c][k];
            if (blocks_[k].confidence.size()) {
                r = r.cwiseProduct(blocks_[k].confidence);
                b = b.cwiseProduct(blocks_[k].confidence);
            }
            num += r.squaredNorm();
            den += b.squaredNorm();
            s.stats.rows += blocks_[k].m->A.rows();
            s.stats.nonZeros += blocks_[k].m->A.nonZeros();
        }
        s.stats.residual = den > 0 ? std::sqrt(num / den) : 0.0;
        s.stats.texels = n;
        if (stats) stats->push_back(s.stats);
        xs.push_back(std::move(x));
    }
    return xs;
}

Eigen::VectorXd inferChannel(const RenderingMatrix& m, const Eigen::VectorXd& b,
                             const InferenceOptions& o, InferenceStats* stats) {
    return InferenceSystem(m, o).solve(b, stats);
}

}  // namespace rg::pem
