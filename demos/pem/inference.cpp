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
// six systems has 0.5 M texels and H 4.2-4.9 M entries. The channels of one map (R, G, B;
// hybrid's four) share H and step together, their vectors packed four to a texel (a group of
// one channel: one to a texel), so that one pass over H serves them all. A step is
//   1. one pass over H: every channel's product y = (H + P) p, and in the same pass p·y;
//      with AVX2 one instruction multiplies an entry of H into all four channels;
//   2. an element pass: x += α p, r −= α y, and r·r;
//   3. the preconditioner z = M⁻¹ r: symmetric Gauss–Seidel, face by face (below), and r·z;
//   4. an element pass: the next direction p = z + β p.
// Every step is Eigen's conjugate_gradient's (ConjugateGradient.h) expression for expression;
// only the preconditioner differs from Eigen's diagonal one.
//
// The preconditioner. With Jacobi's (M = D) the systems took 230-420 steps: each pixel's
// value is shared between a texel and its parents one MIPMAP level up (trilinear), so H has
// strongly coupled pairs across levels that only the weak level coupling and smoothness (1e-3
// against data weights of 1-150) tell apart, and a diagonal preconditioner sees none of that.
// Symmetric Gauss–Seidel, M = (D + L) D⁻¹ (D + U) with L and U H's strict triangles, sees every
// coupling of a row. Measured on view 10's six systems at paper settings (round 0): 58-68
// steps against 211-258 with Jacobi; an incomplete Cholesky factor did no better (54-63).
// Its two sweeps are sequential, so M is block-diagonal: one block per cube face, the face's
// texels at every level in texel order (L and U keep only entries within the face). Neither
// the regulariser nor a bilinear footprint couples two faces, so dropping those entries cost
// nothing measurable (the same step counts as one sweep over all texels), and the six faces
// run side by side.
//
// Bit for bit on any thread count: every pass is split into blocks of fixed size (the
// preconditioner's blocks are the faces); a row of a product is one sum over the row's entries
// in storage order, then the channel's pin (its diagonal weight of this round) times v_i; a
// sweep's row likewise, in storage order; every dot product is the sum, in block order, of each
// block's sum, four interleaved lanes in an element pass, row order in a sweep. Nothing
// depends on which thread ran which block, on the kernel (AVX2 or the plain loop, packed or
// one channel alone: their lanes do the same IEEE operations in the same order), or on the
// other channels (tests/pem/test_inference_threads.cpp checks all of these).
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

// A group's vectors that the passes over H read or write, packed: channel (slot) c of texel i
// at [stride·i + c], stride 4 for a group of several channels, 1 for a group of one.
struct Packed {
    int stride = 1;
    std::vector<double> v;     // the product's operand: x at a round's start, then p
    std::vector<double> pin;   // the channel's pin weight of this round (P's diagonal)
    std::vector<double> r;     // the residual, the preconditioner's input
    std::vector<double> z;     // M⁻¹ r (the forward sweep's result first, in place)
    std::vector<double> d, invD;  // diag(H + P) and its inverse (1 where it is 0)
};

// One channel's solve: Eigen's conjugate_gradient as a state machine that stops whenever it
// needs y = (H + P) v or z = M⁻¹ r, P the channel's diagonal pins of this round.
struct ChannelSolve {
    enum class Need { Residual, Direction, Done };
    Need need = Need::Residual;
    Eigen::VectorXd rhs, x, pinWeight, pinValue;      // across rounds
    Eigen::VectorXd rp, diagonal;                     // this round: rhs + P·pins, diag(H + P)
    Eigen::VectorXd residual, p, y;                   // conjugate gradient's vectors
    std::vector<double> partial;                      // per block: the pass's partial sums
    double threshold = 0, residualNorm2 = 0, absNew = 0, alpha = 0, beta = 0, rz = 0;
    Eigen::Index i = 0;
    int round = 0;
    bool starting = false;                            // this step began a round
    InferenceStats stats;
    Packed* packed = nullptr;                         // its group's
    int slot = 0;
    double& at(std::vector<double>& v, int64_t i) const { return v[size_t(packed->stride * i + slot)]; }
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

// ---- symmetric Gauss–Seidel over one block: z = (D + U)⁻¹ D (D + L)⁻¹ r -------------------
// Forward, rows in increasing order: t_i = (r_i − Σ_{j<i} H_ij t_j) / d_i, the row's lower
// entries subtracted in storage order, then multiplied by 1/d_i. Backward, rows in decreasing
// order: z_i = (d_i t_i − Σ_{j>i} H_ij z_j) / d_i, in place over t (z_j, j > i, is done when row
// i reads it). rz += r_i z_i in the backward sweep's row order. S channels packed per texel;
// each slot's operations are those of S = 1.
struct TriangleRows {
    const double* values;
    const int* inner;
    const int* outer;
};

template <int S>
void sweepBlockScalar(const std::vector<std::pair<int64_t, int64_t>>& ranges, const TriangleRows& L,
                      const TriangleRows& U, const Packed& g, double* z, double* rz) {
    const double *r = g.r.data(), *d = g.d.data(), *invD = g.invD.data();
    for (const auto& [begin, end] : ranges)
        for (int64_t i = begin; i < end; ++i) {
            double sum[S];
            for (int c = 0; c < S; ++c) sum[c] = r[S * i + c];
            for (int k = L.outer[i]; k < L.outer[i + 1]; ++k)
                for (int c = 0; c < S; ++c) sum[c] -= L.values[k] * z[S * int64_t(L.inner[k]) + c];
            for (int c = 0; c < S; ++c) z[S * i + c] = sum[c] * invD[S * i + c];
        }
    for (auto range = ranges.rbegin(); range != ranges.rend(); ++range)
        for (int64_t i = range->second - 1; i >= range->first; --i) {
            double sum[S];
            for (int c = 0; c < S; ++c) sum[c] = d[S * i + c] * z[S * i + c];
            for (int k = U.outer[i]; k < U.outer[i + 1]; ++k)
                for (int c = 0; c < S; ++c) sum[c] -= U.values[k] * z[S * int64_t(U.inner[k]) + c];
            for (int c = 0; c < S; ++c) {
                z[S * i + c] = sum[c] * invD[S * i + c];
                rz[c] += r[S * i + c] * z[S * i + c];
            }
        }
}

__attribute__((target("avx2"))) void sweepBlockAvx2(
    const std::vector<std::pair<int64_t, int64_t>>& ranges, const TriangleRows& L,
    const TriangleRows& U, const Packed& g, double* z, double* rz) {
    const double *r = g.r.data(), *d = g.d.data(), *invD = g.invD.data();
    for (const auto& [begin, end] : ranges)
        for (int64_t i = begin; i < end; ++i) {
            __m256d sum = _mm256_loadu_pd(r + kSlots * i);
            for (int k = L.outer[i]; k < L.outer[i + 1]; ++k)
                sum = _mm256_sub_pd(sum, _mm256_mul_pd(_mm256_set1_pd(L.values[k]),
                                                       _mm256_loadu_pd(z + kSlots * int64_t(L.inner[k]))));
            _mm256_storeu_pd(z + kSlots * i, _mm256_mul_pd(sum, _mm256_loadu_pd(invD + kSlots * i)));
        }
    __m256d rzSum = _mm256_loadu_pd(rz);
    for (auto range = ranges.rbegin(); range != ranges.rend(); ++range)
        for (int64_t i = range->second - 1; i >= range->first; --i) {
            __m256d sum = _mm256_mul_pd(_mm256_loadu_pd(d + kSlots * i), _mm256_loadu_pd(z + kSlots * i));
            for (int k = U.outer[i]; k < U.outer[i + 1]; ++k)
                sum = _mm256_sub_pd(sum, _mm256_mul_pd(_mm256_set1_pd(U.values[k]),
                                                       _mm256_loadu_pd(z + kSlots * int64_t(U.inner[k]))));
            const __m256d zi = _mm256_mul_pd(sum, _mm256_loadu_pd(invD + kSlots * i));
            _mm256_storeu_pd(z + kSlots * i, zi);
            rzSum = _mm256_add_pd(rzSum, _mm256_mul_pd(_mm256_loadu_pd(r + kSlots * i), zi));
        }
    _mm256_storeu_pd(rz, rzSum);
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
    H_.makeCompressed();

    // ---- the preconditioner's blocks (faces) and H's triangles within them ------------------
    std::vector<int> faceOf(size_t(n), 0);
    faces_.assign(size_t(L.faces), {});
    for (int l = 0; l < L.levels(); ++l) {
        const int64_t s2 = int64_t(L.levelSize(l)) * L.levelSize(l);
        for (int f = 0; f < L.faces; ++f) {
            const int64_t begin = L.levelOffset(l) + f * s2;
            faces_[size_t(f)].emplace_back(begin, begin + s2);
            std::fill(faceOf.begin() + begin, faceOf.begin() + begin + s2, f);
        }
    }
    const NormalRows rows = normalRows(H_);
    for (Triangle* t : {&lower_, &upper_}) {
        t->outer.assign(size_t(n) + 1, 0);
        t->inner.clear();
        t->values.clear();
    }
    for (int64_t i = 0; i < n; ++i) {
        for (int k = rows.outer[i]; k < rows.outer[i + 1]; ++k) {
            const int j = rows.inner[k];
            if (j == i || faceOf[size_t(j)] != faceOf[size_t(i)]) continue;
            Triangle& t = j < i ? lower_ : upper_;
            t.inner.push_back(j);
            t.values.push_back(rows.values[k]);
        }
        lower_.outer[size_t(i) + 1] = int(lower_.inner.size());
        upper_.outer[size_t(i) + 1] = int(upper_.inner.size());
    }
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

    // ---- the channels' groups: four to a group, their vectors packed (Packed) -------------
    std::vector<std::unique_ptr<Packed>> groups;
    for (size_t c = 0; c < solves.size(); c += kSlots) {
        const size_t count = std::min(solves.size() - c, size_t(kSlots));
        auto& g = groups.emplace_back(std::make_unique<Packed>());
        g->stride = count == 1 ? 1 : kSlots;
        const size_t size = size_t(n) * size_t(g->stride);
        g->v.assign(size, 0.0);
        g->pin.assign(size, 0.0);
        g->r.assign(size, 0.0);
        g->z.assign(size, 0.0);
        g->d.assign(size, 1.0);  // an empty slot: finite, never read back
        g->invD.assign(size, 1.0);
        for (size_t k = 0; k < count; ++k) {
            solves[c + k].packed = g.get();
            solves[c + k].slot = int(k);
        }
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
        s.residual.resize(n);
        s.p.resize(n);
        s.need = ChannelSolve::Need::Residual;
        Packed& g = *s.packed;
        for (int64_t i = 0; i < n; ++i) {  // the round's first product is H x, with its pins
            s.at(g.v, i) = s.x[i];
            s.at(g.pin, i) = s.pinWeight[i];
            s.at(g.d, i) = s.diagonal[i];
            s.at(g.invD, i) = s.diagonal[i] != 0.0 ? 1.0 / s.diagonal[i] : 1.0;
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
    for (ChannelSolve& s : solves) startRound(s);

    const NormalRows H = normalRows(H_);
    const TriangleRows lower{lower_.values.data(), lower_.inner.data(), lower_.outer.data()};
    const TriangleRows upper{upper_.values.data(), upper_.inner.data(), upper_.outer.data()};
    const bool avx2 = avx2Enabled() && !o.scalarProducts;
    const int64_t faceBlocks = int64_t(faces_.size());
    std::vector<double> pyPartial, rzPartial;
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
            for (size_t gi = 0; gi < groups.size(); ++gi) {
                const Packed& g = *groups[gi];
                const size_t first = gi * kSlots;
                if (g.stride == 1) {
                    if (solves[first].need != ChannelSolve::Need::Done)
                        productRows(begin, end, H, g.v.data(), g.pin.data(), solves[first].y.data(),
                                    py[first]);
                    continue;
                }
                PackedOperands ops{g.v.data(), g.pin.data(), {nullptr, nullptr, nullptr, nullptr}};
                bool any = false;
                for (size_t k = 0; k < kSlots && first + k < N; ++k)
                    if (solves[first + k].need != ChannelSolve::Need::Done) {
                        ops.y[k] = solves[first + k].y.data();
                        any = true;
                    }
                if (!any) continue;
                double sums[kSlots] = {0.0, 0.0, 0.0, 0.0};
                if (avx2) packedProductRowsAvx2(begin, end, H, ops, sums);
                else packedProductRowsScalar(begin, end, H, ops, sums);
                for (size_t k = 0; k < kSlots && first + k < N; ++k) py[first + k] = sums[k];
            }
        });

        // ---- pass 2: a round's start r = rp − H x; a step x += α p, r −= α y; and r·r --------
        std::vector<ChannelSolve*> starting, stepping;
        for (ChannelSolve* s : active) {
            s->starting = s->need == ChannelSolve::Need::Residual;
            if (s->starting) {
                starting.push_back(s);
            } else {
                const size_t c = size_t(s - solves.data());
                double py = 0.0;
                for (int64_t b = 0; b < rowBlocks; ++b) py += pyPartial[size_t(b) * N + c];
                s->alpha = s->absNew / py;
                stepping.push_back(s);
            }
        }
        std::vector<ChannelSolve*> sweeping;
        if (!starting.empty()) {
            elementPass(starting, 2, [](ChannelSolve& s, int64_t begin, int64_t end, Lanes* sums) {
                const double *rp = s.rp.data(), *y = s.y.data();
                double* r = s.residual.data();
                const int stride = s.packed->stride;
                double* packed = s.packed->r.data() + s.slot;
                for (int64_t i = begin; i < end; ++i) {
                    r[i] = rp[i] - y[i];
                    packed[stride * i] = r[i];
                    sums[0].add(i, rp[i] * rp[i]);
                    sums[1].add(i, r[i] * r[i]);
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
                sweeping.push_back(s);
            }
        }
        if (!stepping.empty()) {
            elementPass(stepping, 1, [](ChannelSolve& s, int64_t begin, int64_t end, Lanes* sums) {
                // Lanes 0-1 and 2-3 in one SSE2 register each (x86-64's baseline: the same IEEE
                // operations as the scalar code, two at a time). Blocks start at multiples of four.
                const __m128d alpha = _mm_set1_pd(s.alpha);
                const double *p = s.p.data(), *y = s.y.data();
                double *x = s.x.data(), *r = s.residual.data();
                const int stride = s.packed->stride;
                double* packed = s.packed->r.data() + s.slot;
                __m128d rr01 = _mm_setzero_pd(), rr23 = _mm_setzero_pd();
                int64_t i = begin;
                for (; i + 4 <= end; i += 4) {
                    // x += α p
                    _mm_storeu_pd(x + i, _mm_add_pd(_mm_loadu_pd(x + i), _mm_mul_pd(alpha, _mm_loadu_pd(p + i))));
                    _mm_storeu_pd(x + i + 2, _mm_add_pd(_mm_loadu_pd(x + i + 2),
                                                        _mm_mul_pd(alpha, _mm_loadu_pd(p + i + 2))));
                    // r −= α y; r·r += r r
                    const __m128d r01 = _mm_sub_pd(_mm_loadu_pd(r + i), _mm_mul_pd(alpha, _mm_loadu_pd(y + i)));
                    const __m128d r23 = _mm_sub_pd(_mm_loadu_pd(r + i + 2), _mm_mul_pd(alpha, _mm_loadu_pd(y + i + 2)));
                    _mm_storeu_pd(r + i, r01);
                    _mm_storeu_pd(r + i + 2, r23);
                    _mm_storel_pd(packed + stride * i, r01);
                    _mm_storeh_pd(packed + stride * (i + 1), r01);
                    _mm_storel_pd(packed + stride * (i + 2), r23);
                    _mm_storeh_pd(packed + stride * (i + 3), r23);
                    rr01 = _mm_add_pd(rr01, _mm_mul_pd(r01, r01));
                    rr23 = _mm_add_pd(rr23, _mm_mul_pd(r23, r23));
                }
                double rr[4];
                _mm_storeu_pd(rr, rr01);
                _mm_storeu_pd(rr + 2, rr23);
                for (; i < end; ++i) {
                    x[i] += s.alpha * p[i];
                    r[i] -= s.alpha * y[i];
                    packed[stride * i] = r[i];
                    rr[i & 3] += r[i] * r[i];
                }
                for (int l = 0; l < 4; ++l) sums[0].s[l] = rr[l];
            });
            for (ChannelSolve* s : stepping) {
                s->residualNorm2 = s->partial[0];
                if (s->residualNorm2 < s->threshold) {
                    endRound(*s);
                    continue;
                }
                sweeping.push_back(s);
            }
        }
        if (sweeping.empty()) continue;

        // ---- pass 3: z = M⁻¹ r, face by face, and r·z ---------------------------------------
        // Every slot of a group is swept (an idle slot's lanes are finite and never read); r·z
        // is each face's sum in its backward sweep's order, then the faces in order.
        std::vector<size_t> sweptGroups;
        for (size_t gi = 0; gi < groups.size(); ++gi)
            for (ChannelSolve* s : sweeping)
                if (s->packed == groups[gi].get()) {
                    sweptGroups.push_back(gi);
                    break;
                }
        rzPartial.assign(sweptGroups.size() * size_t(faceBlocks) * kSlots, 0.0);
        tbb::parallel_for(int64_t(0), int64_t(sweptGroups.size()) * faceBlocks, [&](int64_t task) {
            Packed& g = *groups[sweptGroups[size_t(task / faceBlocks)]];
            const auto& ranges = faces_[size_t(task % faceBlocks)];
            double* rz = rzPartial.data() + size_t(task) * kSlots;
            if (g.stride == 1) sweepBlockScalar<1>(ranges, lower, upper, g, g.z.data(), rz);
            else if (avx2) sweepBlockAvx2(ranges, lower, upper, g, g.z.data(), rz);
            else sweepBlockScalar<kSlots>(ranges, lower, upper, g, g.z.data(), rz);
        });
        for (size_t t = 0; t < sweptGroups.size(); ++t)
            for (ChannelSolve* s : sweeping) {
                if (s->packed != groups[sweptGroups[t]].get()) continue;
                double rz = 0.0;
                for (int64_t f = 0; f < faceBlocks; ++f)
                    rz += rzPartial[(t * size_t(faceBlocks) + size_t(f)) * kSlots + size_t(s->slot)];
                s->rz = rz;
            }

        // ---- pass 4: p = z (a round's start) or p = z + β p -------------------------------
        for (ChannelSolve* s : sweeping) {
            if (s->starting) {
                s->absNew = s->rz;
                s->beta = 0.0;
            } else {
                const double absOld = s->absNew;
                s->absNew = s->rz;
                s->beta = s->absNew / absOld;
            }
        }
        elementPass(sweeping, 0, [](ChannelSolve& s, int64_t begin, int64_t end, Lanes*) {
            const int stride = s.packed->stride;
            const double* z = s.packed->z.data() + s.slot;
            double* packed = s.packed->v.data() + s.slot;
            double* p = s.p.data();
            if (s.starting) {
                for (int64_t i = begin; i < end; ++i) packed[stride * i] = p[i] = z[stride * i];
                return;
            }
            for (int64_t i = begin; i < end; ++i) packed[stride * i] = p[i] = z[stride * i] + s.beta * p[i];
        });
        for (ChannelSolve* s : sweeping) {
            if (s->starting) {
                s->need = ChannelSolve::Need::Direction;
            } else if (++s->i >= maxIters) {
                endRound(*s);
            }
        }
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
