#include "inference.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>
#include <limits>

#include <tbb/parallel_for.h>

#include "core/error.h"

namespace rg::pem {

// ---- conjugate gradient for several channels, one pass over H per step, on every core ------
//
// Nearly all of a view's inference is conjugate gradient's product y = H p: H has ~8 M
// entries at paper settings (~100 MB read per product) and the vectors 0.5 M. The channels
// of one map (R, G, B; hybrid's four) share H, so they step together here: one pass over H
// computes every channel's product, and the pass is split into fixed blocks of rows handed
// to TBB. Each row of each channel is still one thread's sum over the row's entries in
// storage order, and everything between the products is Eigen's own conjugate_gradient
// (ConjugateGradient.h, with its DiagonalPreconditioner), expression for expression. So each
// channel gets the bits Eigen's solver gives it alone on one thread, for any thread count
// (tests/pem/test_inference_threads.cpp checks both). Eigen's own parallel product needs
// OpenMP, a second thread pool beside TBB's, and reads H once per channel.
namespace {

// Rows per TBB task: fixed, so the split never depends on the thread count (it could not
// change the result anyway, each row being summed whole). A task's rows of H (~20 entries
// each, 12 bytes an entry: ~250 KB) stay in L2 while each channel's product reads them.
constexpr int64_t kRowsPerTask = 1024;

// One channel's solve: Eigen's conjugate_gradient as a state machine that stops whenever it
// needs y = (H + P) v, P the channel's diagonal pins of this round.
struct ChannelSolve {
    enum class Need { Residual, Direction, Done };
    Need need = Need::Residual;
    Eigen::VectorXd rhs, x, pinWeight, pinValue;      // across rounds
    Eigen::VectorXd rp, diagonal, invDiagonal;        // this round: rhs + P·pins, diag(H + P)
    Eigen::VectorXd residual, p, z, y;                // conjugate gradient's vectors
    double rhsNorm2 = 0, threshold = 0, residualNorm2 = 0, absNew = 0;
    Eigen::Index i = 0;
    int round = 0;
    InferenceStats stats;
    const Eigen::VectorXd& operand() const { return need == Need::Residual ? x : p; }
};

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

    // ---- the steps of one channel between two products (Eigen's conjugate_gradient) --------
    const double tol = o.tolerance;
    const Eigen::Index maxIters = o.maxIterations;
    auto startRound = [&](ChannelSolve& s) {
        // Round 0 solves H x = rhs; later rounds pin texels outside [0, 1] to the bound with a
        // strong diagonal weight, H + P, so their neighbours compensate.
        s.rp = s.rhs;
        if (s.round > 0) s.rp += s.pinWeight.cwiseProduct(s.pinValue);
        s.diagonal = s.round > 0 ? Eigen::VectorXd(hDiagonal + s.pinWeight) : hDiagonal;
        s.invDiagonal = s.diagonal;
        for (int64_t i = 0; i < n; ++i)  // DiagonalPreconditioner: 1 where the diagonal is 0
            s.invDiagonal[i] = s.invDiagonal[i] != 0.0 ? 1.0 / s.invDiagonal[i] : 1.0;
        s.need = ChannelSolve::Need::Residual;
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
    auto afterResidualProduct = [&](ChannelSolve& s) {  // s.y = (H + P) x
        s.residual = s.rp - s.y;
        s.rhsNorm2 = s.rp.squaredNorm();
        s.i = 0;
        if (s.rhsNorm2 == 0) {
            s.x.setZero();
            return endRound(s);
        }
        s.threshold = std::max(tol * tol * s.rhsNorm2, std::numeric_limits<double>::min());
        s.residualNorm2 = s.residual.squaredNorm();
        if (s.residualNorm2 < s.threshold) return endRound(s);
        s.p = s.invDiagonal.array() * s.residual.array();
        s.absNew = s.residual.dot(s.p);
        if (maxIters <= 0) return endRound(s);
        s.need = ChannelSolve::Need::Direction;
    };
    // Element by element, on every core: each element's arithmetic is Eigen's expression's
    // (x += α p is x_i + α p_i), so the split cannot change a bit. The sums (dot products,
    // norms) stay Eigen's, whose order is its own.
    auto eachElement = [n](auto f) {
        constexpr int64_t kElementsPerTask = 16384;
        tbb::parallel_for(int64_t(0), (n + kElementsPerTask - 1) / kElementsPerTask, [&](int64_t b) {
            const int64_t end = std::min(n, (b + 1) * kElementsPerTask);
            for (int64_t i = b * kElementsPerTask; i < end; ++i) f(i);
        });
    };
    auto afterDirectionProduct = [&](ChannelSolve& s) {  // s.y = (H + P) p
        const double alpha = s.absNew / s.p.dot(s.y);
        // x += α p; r −= α y; and z = M⁻¹ r ahead of the test below, in one pass (unused
        // when the test ends the round).
        s.z.resize(n);
        double *x = s.x.data(), *r = s.residual.data(), *z = s.z.data();
        const double *p = s.p.data(), *y = s.y.data(), *inv = s.invDiagonal.data();
        eachElement([=](int64_t i) {
            x[i] += alpha * p[i];
            r[i] -= alpha * y[i];
            z[i] = inv[i] * r[i];
        });
        s.residualNorm2 = s.residual.squaredNorm();
        if (s.residualNorm2 < s.threshold) return endRound(s);
        const double absOld = s.absNew;
        s.absNew = s.residual.dot(s.z);
        const double beta = s.absNew / absOld;
        double* pw = s.p.data();
        eachElement([=](int64_t i) { pw[i] = z[i] + beta * pw[i]; });
        if (++s.i >= maxIters) return endRound(s);
    };
    for (ChannelSolve& s : solves) startRound(s);

    // ---- one pass over H for every channel waiting on a product ------------------------------
    const double* values = H_.valuePtr();
    const int* inner = H_.innerIndexPtr();
    const int* outer = H_.outerIndexPtr();
    for (;;) {
        std::vector<ChannelSolve*> active;
        for (ChannelSolve& s : solves)
            if (s.need != ChannelSolve::Need::Done) {
                s.y.resize(n);
                active.push_back(&s);
            }
        if (active.empty()) break;
        // H is symmetric: column i of the column-major matrix is row i. The pin adds to the
        // diagonal entry, as in the sparse sum H + P.
        tbb::parallel_for(int64_t(0), (n + kRowsPerTask - 1) / kRowsPerTask, [&](int64_t block) {
            const int64_t end = std::min(n, (block + 1) * kRowsPerTask);
            for (ChannelSolve* s : active) {
                const double* v = s->operand().data();
                const double* pin = s->pinWeight.data();
                const bool pinned = s->round > 0;
                double* y = s->y.data();
                for (int64_t i = block * kRowsPerTask; i < end; ++i) {
                    double sum = 0.0;
                    for (int k = outer[i]; k < outer[i + 1]; ++k) {
                        const double h = pinned && inner[k] == i ? values[k] + pin[i] : values[k];
                        sum += h * v[inner[k]];
                    }
                    y[i] = sum;
                }
            }
        });
        for (ChannelSolve* s : active) {
            if (s->need == ChannelSolve::Need::Residual) afterResidualProduct(*s);
            else afterDirectionProduct(*s);
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
