// EM inference (Hakura, Snyder & Lengyel 2001, §4 "EM Inference", "EM MIPMAPs"; the
// method of Hakura, Lengyel & Snyder, EGWR 2000 [10]).
//
// Hardware rendering is linear in the texels: the rendering matrix A maps every texel of
// every MIPMAP level to the display pixels it contributes to. Given the ray tracer's
// layer image b, the inferred EM x is the regularised least-squares solution of A x = b,
// all MIPMAP levels solved jointly.
#pragma once

#include <cstdint>
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
};

struct InferenceStats {
    int iterations = 0;
    double residual = 0.0;      // relative residual ‖Ax − b‖ / ‖b‖ after clamping
    int64_t texels = 0, rows = 0, nonZeros = 0;
    int64_t clampedTexels = 0;
};

// The normal equations of one rendering matrix, built once and shared by the channels
// (and layers) that use the same A:  H = AᵀA + R + μI, with R the regulariser.
class InferenceSystem {
  public:
    InferenceSystem(const RenderingMatrix& m, const InferenceOptions& options);
    // Solves one channel; thread-safe (channels may be solved in parallel). `b` has one
    // entry per row of the matrix, in [0, 1].
    Eigen::VectorXd solve(const Eigen::VectorXd& b, InferenceStats* stats = nullptr) const;
    const RenderingMatrix& matrix() const { return m_; }

  private:
    const RenderingMatrix& m_;
    InferenceOptions o_;
    Eigen::SparseMatrix<double> At_, H_;
};

// Convenience: builds the system and solves one channel.
Eigen::VectorXd inferChannel(const RenderingMatrix& m, const Eigen::VectorXd& b,
                             const InferenceOptions& options, InferenceStats* stats = nullptr);

}  // namespace rg::pem
