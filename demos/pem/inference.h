// EM inference (Hakura, Snyder & Lengyel 2001, §4 "EM Inference", "EM MIPMAPs"; the
// method of Hakura, Lengyel & Snyder, EGWR 2000 [10]).
//
// Hardware rendering is linear in the texels: the rendering matrix A maps every texel of
// every MIPMAP level to the display pixels it contributes to. Given the ray tracer's
// layer image b, the inferred EM x is the regularised least-squares solution of A x = b,
// all MIPMAP levels solved jointly.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Sparse>

namespace rg::pem {

// Texel numbering of a MIPMAPped texture: a cube map (6 faces) or a 2D texture (1 face,
// for the PTM baseline). Level 0 is baseSize², each next level halves to 1×1.
struct TexelLayout {
    int baseSize = 0;
    int faces = 6;
    int levels() const;
    int levelSize(int level) const { return std::max(1, baseSize >> level); }
    int64_t levelOffset(int level) const;  // index of (level, face 0, 0, 0)
    int64_t index(int level, int face, int x, int y) const;
    int64_t count() const;
};

// A sparse rendering matrix: row = a display pixel inside the object's mask, column = a
// texel. Entries are the weights (0..1) with which the texel reaches the pixel.
struct RenderingMatrix {
    TexelLayout layout;
    int width = 0, height = 0;           // the display
    std::vector<int32_t> rowPixel;       // row → pixel index y·width + x
    Eigen::SparseMatrix<double, Eigen::RowMajor> A;

    // Rows: finest level with any contribution (§4 "EM Resolution"), −1 when empty.
    int finestLevelAccessed() const;
};

struct InferenceOptions {
    double smoothness = 1e-3;   // λ: neighbour differences (fills non-contributing texels)
    double levelCoupling = 1e-3;// parent ≈ mean of its 4 children across MIPMAP levels
    double prior = 1e-6;        // μ: pull towards the mean of b (makes the system definite)
    int maxIterations = 300;
    double tolerance = 1e-5;    // relative residual of CG; far below 8-bit quantization
    int boundRounds = 2;        // active-set rounds that pin out-of-range texels to [0, 1]
    bool scalarProducts = false;// the plain loop for the packed products, not AVX2 (tests)
};

struct InferenceStats {
    int iterations = 0;
    double residual = 0.0;      // relative residual ‖Ax − b‖ / ‖b‖ after clamping
    int64_t texels = 0, rows = 0, nonZeros = 0;
    int64_t clampedTexels = 0;
};

// One block of a stacked system: a rendering matrix and a weight per row. 000 §4.3
// multiplies both sides of A x = b by the confidence c, so a row's least-squares weight
// is c²; `confidence` empty means 1 for every row.
struct WeightedMatrix {
    const RenderingMatrix* m = nullptr;
    Eigen::VectorXd confidence;
};

// The normal equations, built once and shared by the channels (and layers) that use the
// same matrices:  H = Σ_k A_kᵀ C_k² A_k + R + μI, with R the regulariser. One block is
// the PEM's A x = b; several stack 000 §4.3's simultaneous systems (both terms, A_R x = b_R
// and A_T x = b_T; several viewpoints; several lens objects sharing a layer), all on
// the texel layout of the first block.
class InferenceSystem {
  public:
    InferenceSystem(const RenderingMatrix& m, const InferenceOptions& options);
    InferenceSystem(std::vector<WeightedMatrix> blocks, const InferenceOptions& options);
    // Solves one channel; thread-safe (channels may be solved in parallel). `b` has one
    // entry per row of the matrix, in [0, 1].
    Eigen::VectorXd solve(const Eigen::VectorXd& b, InferenceStats* stats = nullptr) const;
    // The stacked form: one right-hand side per block, in block order.
    Eigen::VectorXd solve(const std::vector<Eigen::VectorXd>& b,
                          InferenceStats* stats = nullptr) const;
    // Several channels at once (a map's R, G, B, A), each in the stacked form: one pass over
    // the normal matrix serves all of them at every step, on every core. Each result is the
    // same bits as solve() of that channel alone, for any thread count.
    std::vector<Eigen::VectorXd> solveChannels(const std::vector<std::vector<Eigen::VectorXd>>& b,
                                               std::vector<InferenceStats>* stats = nullptr) const;
    // The normal equations' matrix H (symmetric; for tests against a reference solver).
    const Eigen::SparseMatrix<double>& normalMatrix() const { return H_; }
    const RenderingMatrix& matrix() const { return *blocks_.at(0).m; }
    const TexelLayout& layout() const { return blocks_.at(0).m->layout; }

  private:
    // H's strictly lower and upper triangles, per row only the entries on the row's own
    // face: symmetric Gauss–Seidel's L and U, block by block (inference.cpp).
    struct Triangle {
        std::vector<int> outer, inner;
        std::vector<double> values;
    };
    std::vector<WeightedMatrix> blocks_;
    InferenceOptions o_;
    std::vector<Eigen::SparseMatrix<double>> AtC2_;  // A_kᵀ C_k² per block
    Eigen::SparseMatrix<double> H_;
    // The preconditioner's blocks: one per face, each the face's texels at every level, one
    // range [begin, end) of texels per level, in increasing texel order.
    std::vector<std::vector<std::pair<int64_t, int64_t>>> faces_;
    Triangle lower_, upper_;
};

// Convenience: builds the system and solves one channel.
Eigen::VectorXd inferChannel(const RenderingMatrix& m, const Eigen::VectorXd& b,
                             const InferenceOptions& options, InferenceStats* stats = nullptr);

}  // namespace rg::pem
