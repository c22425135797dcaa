#include "inference.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>
#include <type_traits>

#include <Eigen/IterativeLinearSolvers>
#include <tbb/parallel_for.h>

#include "core/error.h"

// ---- the normal matrix as conjugate gradient sees it: y = H p on every core ----------------
//
// CG spends its time in y = H p (one per iteration). Eigen computes it row by row, each row
// a sum over its entries in storage order; here fixed blocks of rows are handed to TBB, and
// every row is still one thread's sum in that same order. No sum crosses a row, so y — and
// with it every iterate, every texel — is the same in every bit for any thread count. The
// dot products and updates between the products stay Eigen's, on one thread. (Eigen's own
// parallel product needs OpenMP, a second thread pool beside TBB's.)
namespace rg::pem {
namespace {
class RowParallelNormalMatrix;
}
}  // namespace rg::pem

namespace Eigen::internal {
template <>
struct traits<rg::pem::RowParallelNormalMatrix>
    : public Eigen::internal::traits<Eigen::SparseMatrix<double>> {};
}  // namespace Eigen::internal

namespace rg::pem {
namespace {

// Rows per TBB task: fixed, so the split never depends on the thread count (it could not
// change the result anyway, each row being summed whole; it keeps tasks ~50 µs).
constexpr int64_t kRowsPerTask = 4096;

class RowParallelNormalMatrix : public Eigen::EigenBase<RowParallelNormalMatrix> {
  public:
    using Scalar = double;
    using RealScalar = double;
    using StorageIndex = int;
    enum { ColsAtCompileTime = Eigen::Dynamic, MaxColsAtCompileTime = Eigen::Dynamic, IsRowMajor = false };

    // H must be symmetric: column i of the column-major matrix is row i.
    explicit RowParallelNormalMatrix(const Eigen::SparseMatrix<double>& H) : H_(&H) {}
    Eigen::Index rows() const { return H_->rows(); }
    Eigen::Index cols() const { return H_->cols(); }
    const Eigen::SparseMatrix<double>& matrix() const { return *H_; }

    template <class Rhs>
    Eigen::Product<RowParallelNormalMatrix, Rhs, Eigen::AliasFreeProduct> operator*(
        const Eigen::MatrixBase<Rhs>& x) const {
        return Eigen::Product<RowParallelNormalMatrix, Rhs, Eigen::AliasFreeProduct>(*this, x.derived());
    }

    // y += alpha · H x
    void multiplyAdd(const Eigen::Ref<const Eigen::VectorXd>& x, double* y, double alpha) const {
        const Eigen::SparseMatrix<double>& H = *H_;
        const int64_t n = H.outerSize();
        const double* values = H.valuePtr();
        const int* inner = H.innerIndexPtr();
        const int* outer = H.outerIndexPtr();
        const double* xs = x.data();
        tbb::parallel_for(int64_t(0), (n + kRowsPerTask - 1) / kRowsPerTask, [&](int64_t block) {
            const int64_t end = std::min(n, (block + 1) * kRowsPerTask);
            for (int64_t i = block * kRowsPerTask; i < end; ++i) {
                double sum = 0.0;
                for (int k = outer[i]; k < outer[i + 1]; ++k) sum += values[k] * xs[inner[k]];
                y[i] += alpha * sum;
            }
        });
    }

  private:
    const Eigen::SparseMatrix<double>* H_;
};

// Jacobi, as Eigen's DiagonalPreconditioner (1 / H_ii, 1 where the diagonal is 0), for an
// operator that is not a sparse matrix itself.
class JacobiPreconditioner {
  public:
    template <class M> JacobiPreconditioner& analyzePattern(const M&) { return *this; }
    template <class M> JacobiPreconditioner& factorize(const M& m) { return compute(m); }
    template <class M> JacobiPreconditioner& compute(const M& m) {
        invDiagonal_ = m.matrix().diagonal();
        for (Eigen::Index i = 0; i < invDiagonal_.size(); ++i)
            invDiagonal_[i] = invDiagonal_[i] != 0.0 ? 1.0 / invDiagonal_[i] : 1.0;
        return *this;
    }
    template <class Rhs> Eigen::VectorXd solve(const Rhs& b) const {
        return invDiagonal_.cwiseProduct(b);
    }
    Eigen::ComputationInfo info() const { return Eigen::Success; }

  private:
    Eigen::VectorXd invDiagonal_;
};

}  // namespace
}  // namespace rg::pem

namespace Eigen::internal {
template <class Rhs>
struct generic_product_impl<rg::pem::RowParallelNormalMatrix, Rhs, SparseShape, DenseShape, GemvProduct>
    : generic_product_impl_base<rg::pem::RowParallelNormalMatrix, Rhs,
                                generic_product_impl<rg::pem::RowParallelNormalMatrix, Rhs>> {
    template <class Dest>
    static void scaleAndAddTo(Dest& dst, const rg::pem::RowParallelNormalMatrix& lhs,
                              const Rhs& rhs, const double& alpha) {
        const Eigen::Ref<const Eigen::VectorXd> x(rhs);  // no copy for CG's plain vectors
        if constexpr (std::is_same_v<Dest, Eigen::VectorXd>) {
            lhs.multiplyAdd(x, dst.data(), alpha);
        } else {
            Eigen::VectorXd y = dst;
            lhs.multiplyAdd(x, y.data(), alpha);
            dst = y;
        }
    }
};
}  // namespace Eigen::internal

namespace rg::pem {

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
    const int64_t n = layout().count();
    if (bs.size() != blocks_.size()) throw Error("inference: one right-hand side per block");
    const InferenceOptions& o = o_;
    // The prior's target: the mean of b, each row weighted as in the least squares.
    double wsum = 0.0, bsum = 0.0;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
    for (size_t k = 0; k < bs.size(); ++k) {
        const Eigen::VectorXd& b = bs[k];
        if (b.size() != blocks_[k].m->A.rows())
            throw Error("layer image does not match the rendering matrix rows");
        const Eigen::VectorXd& c = blocks_[k].confidence;
        if (c.size()) {
            const Eigen::VectorXd c2 = c.cwiseProduct(c);
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

    Eigen::VectorXd x = Eigen::VectorXd::Constant(n, mean);
    Eigen::VectorXd pinWeight = Eigen::VectorXd::Zero(n), pinValue = Eigen::VectorXd::Zero(n);
    InferenceStats s;
    for (int round = 0; round <= o.boundRounds; ++round) {
        Eigen::SparseMatrix<double> Hp;
        Eigen::VectorXd rp = rhs;
        const Eigen::SparseMatrix<double>* H = &H_;
        if (round > 0) {
            Eigen::SparseMatrix<double> P(n, n);
            std::vector<Eigen::Triplet<double>> d;
            for (int64_t i = 0; i < n; ++i)
                if (pinWeight[i] > 0) d.emplace_back(i, i, pinWeight[i]);
            P.setFromTriplets(d.begin(), d.end());
            Hp = H_ + P;
            H = &Hp;
            rp += pinWeight.cwiseProduct(pinValue);
        }
        const RowParallelNormalMatrix op(*H);
        Eigen::ConjugateGradient<RowParallelNormalMatrix, Eigen::Lower | Eigen::Upper,
                                 JacobiPreconditioner> cg;
        cg.setMaxIterations(o.maxIterations);
        cg.setTolerance(o.tolerance);
        cg.compute(op);
        x = cg.solveWithGuess(rp, x);
        s.iterations += int(cg.iterations());
        // Texels outside [0, 1] cannot be stored in an 8-bit texture: pin them to the bound
        // with a strong weight and solve again so their neighbours compensate.
        bool any = false;
        Eigen::VectorXd diag = H->diagonal();
        for (int64_t i = 0; i < n; ++i)
            if (x[i] < 0.0 || x[i] > 1.0) {
                if (pinWeight[i] == 0) any = true;
                pinWeight[i] = 10.0 * (diag[i] + 1.0);
                pinValue[i] = x[i] < 0.0 ? 0.0 : 1.0;
            }
        if (!any) break;
    }
    s.clampedTexels = 0;
    for (int64_t i = 0; i < n; ++i) {
        if (x[i] < 0.0 || x[i] > 1.0) ++s.clampedTexels;
        x[i] = std::clamp(x[i], 0.0, 1.0);
    }
    double num = 0.0, den = 0.0;
    for (size_t k = 0; k < bs.size(); ++k) {
        Eigen::VectorXd r = blocks_[k].m->A * x - bs[k];
        Eigen::VectorXd b = bs[k];
        if (blocks_[k].confidence.size()) {
            r = r.cwiseProduct(blocks_[k].confidence);
            b = b.cwiseProduct(blocks_[k].confidence);
        }
        num += r.squaredNorm();
        den += b.squaredNorm();
        s.rows += blocks_[k].m->A.rows();
        s.nonZeros += blocks_[k].m->A.nonZeros();
    }
    s.residual = den > 0 ? std::sqrt(num / den) : 0.0;
    s.texels = n;
    if (stats) *stats = s;
    return x;
}

Eigen::VectorXd inferChannel(const RenderingMatrix& m, const Eigen::VectorXd& b,
                             const InferenceOptions& o, InferenceStats* stats) {
    return InferenceSystem(m, o).solve(b, stats);
}

}  // namespace rg::pem
