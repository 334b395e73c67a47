#pragma once
// Internal: the backend interface every algorithm is written against (not installed).
//
// A backend owns device-resident sparse matrices and blocks of vectors and offers coarse
// operations: one call = one dispatch over whole arrays. The Eigen CPU backend
// (fallback/cpu_backend.*) and the Vulkan backend (kernels/vulkan_backend.*) implement it; they
// include nothing above this folder. Choosing one for a method's options is solve/'s work
// (solve/backend_selection.h). Topology, CSR patterns and boundary data are built on the host in double precision
// and uploaded once.
//
// Algorithms normally use the highest level, SparseSystemSolver (analyze a pattern once, factorize
// or precondition per value update, solve many right-hand sides). The Krylov loops (PCG, MINRES)
// are written once in host/backend/krylov.cpp on top of the primitives below, and the batched PCG
// of block-diagonal systems in host/backend/block_krylov.cpp; a backend may override them with a
// fused implementation (e.g. several iterations per GPU submission).

#include <cstddef>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "harmonia/solver_options.h"
#include "harmonia/types.h"

namespace harmonia::detail {

using RowMajorSparse = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

enum class Feature {
  float64,               // Arithmetic in double precision.
  direct_factorization,  // Sparse Cholesky/LU available (CPU).
};

enum class MatrixKind {
  symmetric_positive_definite,  // Cholesky / PCG.
  symmetric_indefinite,         // LDLT / MINRES.
  general,                      // LU (CPU) / normal equations on devices without LU.
};

// A CSR matrix living on a backend. The pattern is fixed at upload; values can be refreshed.
class DeviceMatrix {
 public:
  virtual ~DeviceMatrix() = default;
  [[nodiscard]] virtual int rows() const = 0;
  [[nodiscard]] virtual int cols() const = 0;
  // New values in the uploaded pattern's CSR order (A.valuePtr() of a RowMajorSparse of the same
  // pattern).
  virtual void update_values(const Eigen::Ref<const Eigen::VectorXd>& csr_values) = 0;
  // The matrix in double on the host. Every backend keeps it: the CPU's is the matrix itself, a
  // device's serves residuals in double and checks made on the host (block_pcg's block
  // structure). CpuMatrix::host, VulkanMatrix::host and the cross-check backend's matrix.
  [[nodiscard]] virtual const RowMajorSparse& host() const = 0;
};

// A block of `cols` vectors of length `rows` (e.g. u and v together) living on a backend.
class DeviceVectors {
 public:
  virtual ~DeviceVectors() = default;
  [[nodiscard]] virtual int rows() const = 0;
  [[nodiscard]] virtual int cols() const = 0;
  virtual void upload(const Eigen::Ref<const Eigen::MatrixXd>& values) = 0;
  [[nodiscard]] virtual Eigen::MatrixXd download() const = 0;
};

// M = B diag(d) B^T for a fixed pattern of B (the system matrix of the angle-based methods: B is
// a constraint Jacobian, d a weight per angle; both change every Newton step, their patterns do
// not). The pattern of M (every pair of rows of B sharing a column, and the diagonal of each
// non-empty row) is fixed when the product is created; `update` refreshes its values.
class DeviceNormalProduct {
 public:
  virtual ~DeviceNormalProduct() = default;
  // New values of B (CSR order of the RowMajorSparse given at creation) and d (one per column
  // of B); M is recomputed on the backend.
  virtual void update(const Eigen::Ref<const Eigen::VectorXd>& b_values,
                      const Eigen::Ref<const Eigen::VectorXd>& diagonal) = 0;
  // M, usable with the backend's spmv / jacobi / pcg / minres.
  [[nodiscard]] virtual const DeviceMatrix& matrix() const = 0;
  // M in double on the host (rows(B) x rows(B), row-major), e.g. for a direct factorization.
  [[nodiscard]] virtual RowMajorSparse download() const = 0;
};

struct IterativeSettings {
  double relative_tolerance = 1e-10;  // Stop when ||b - A x|| <= tol * ||b|| (per column).
  int max_iterations = 20000;
  int check_every = 8;  // Residual read back every k iterations (devices).
  // SparseSystemSolver's iterative SPD solves: the multilevel V-cycle or the diagonal.
  IterativePreconditioner preconditioner = IterativePreconditioner::multilevel;
};

// The settings a method's public solver options ask for.
[[nodiscard]] IterativeSettings iterative_settings(const SolverOptions& options);

struct SolveStats {
  int iterations = 0;
  double relative_residual = 0.0;  // Largest over columns.
  Status status = Status::ok;      // ok, not_converged, numerical_failure, cancelled.
  std::string message;
};

// The diagonal blocks of a block-diagonal matrix: block k owns rows (and columns) offsets[k] ..
// offsets[k + 1] - 1, with offsets[0] = 0, offsets nondecreasing and offsets.back() = the rows
// of the matrix (an empty block is allowed; it has nothing to solve). E.g. one block per
// texture-atlas chart, or one per mesh of a batch solved together.
struct BlockRows {
  std::vector<int> offsets;
  [[nodiscard]] int count() const {
    return offsets.empty() ? 0 : static_cast<int>(offsets.size()) - 1;
  }
  [[nodiscard]] int begin(int block) const { return offsets[block]; }
  [[nodiscard]] int size(int block) const { return offsets[block + 1] - offsets[block]; }
};

// Empty when `matrix` is square, `blocks` covers its rows as BlockRows says and no stored entry
// (even a stored zero: values may be refreshed later) lies outside its diagonal block; else a
// one-line reason, naming the first entry outside its block in CSR order: "entry (row 5,
// column 12) lies outside block 0 (rows 0..9)".
[[nodiscard]] std::string block_structure_error(const RowMajorSparse& matrix,
                                                const BlockRows& blocks);

// What block_pcg reports of one system (one diagonal block in one column of the vectors).
struct BlockSystemStats {
  int iterations = 0;
  double relative_residual = 0.0;  // ||b_k - A_kk x_k|| / ||b_k|| in double (b_k = 0: absolute).
  Status status = Status::ok;      // ok, not_converged, numerical_failure.
  std::string message;             // Why, when not ok (e.g. "not positive definite").
};

// block_pcg's report: the SolveStats of the whole batch (iterations: the most any system took;
// relative_residual: the largest; status: ok when every system converged, else numerical_failure
// when one broke down, else not_converged, or invalid_input / cancelled for the whole batch, with
// a message naming the first failed block) and one entry per system.
struct BlockSolveStats : SolveStats {
  int block_count = 0;
  std::vector<BlockSystemStats> systems;  // Block k of column c at k + c * block_count.
  [[nodiscard]] const BlockSystemStats& system(int block, int column = 0) const {
    return systems[static_cast<std::size_t>(block + column * block_count)];
  }
  // Sets the batch's iterations, relative_residual, status and message from the systems.
  void summarize(const BlockRows& blocks);
};

// Per-face 2x2 tensors, one row (C00, C01, C10, C11) per face: the layout of
// harmonia::TriangleTensors (harmonia/quasi_harmonic_operator.h, a layer this one does not see).
using TriangleTensorRows = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>;

// One quasi-harmonic round's operator: the tensors of a map and the operator they define.
struct QuasiHarmonicOperator {
  TriangleTensorRows tensors;          // C = sqrt(I)^-1 (5.7); infinite for a zero-area uv face.
  Eigen::SparseMatrix<double> matrix;  // The tensor-cotangent operator (5.10) under them.
};

// The operators a method assembles triangle by triangle, for one connectivity (the faces given
// at creation; positions and layouts change from call to call), computed where the backend
// computes and returned to the host in double. Every matrix is #V x #V, column-major, with the
// pattern and the sign convention (positive semi-definite) of harmonia::laplacian: the diagonal
// and every vertex pair sharing a face, so that a DirichletSystem loads it as it is. The CPU
// backend's are the host functions named below (fallback/cpu_triangle_operators.h); a device's
// agree with them within the error bounds of its kernels.
class TriangleOperators {
 public:
  virtual ~TriangleOperators() = default;
  // The cotangent Laplacian (4.41) of the surface with these positions (#V x 3):
  // harmonia::laplacian(mesh, WeightScheme::cotangent).
  [[nodiscard]] virtual Eigen::SparseMatrix<double> cotangent(
      const Eigen::MatrixX3d& positions) = 0;
  // The tensor-cotangent operator (5.10) of the planar map uv (#V x 2) under one tensor per face:
  // harmonia::tensor_cotangent_laplacian.
  [[nodiscard]] virtual Eigen::SparseMatrix<double> tensor_cotangent(
      const Eigen::MatrixX2d& uv, const TriangleTensorRows& tensors) = 0;
  // The quasi-harmonic tensors of the map uv -> positions and the tensor-cotangent operator of uv
  // under them: harmonia::quasi_harmonic_tensors, then harmonia::tensor_cotangent_laplacian.
  [[nodiscard]] virtual QuasiHarmonicOperator quasi_harmonic(const Eigen::MatrixX3d& positions,
                                                             const Eigen::MatrixX2d& uv) = 0;
  // The Poisson right-hand side of a fragmented mesh (6.2.2), #V x m: every face's cotangent
  // stiffness (4.41) on the surface with these positions, applied to the face's own fragment
  // (fragments.row(3 f + k): the target of corner k of face f; 3 #F x m) and summed at the shared
  // vertices: harmonia::fragment_poisson_rhs, up to the order of the sums.
  [[nodiscard]] virtual Eigen::MatrixXd fragment_poisson_rhs(const Eigen::MatrixX3d& positions,
                                                             const Eigen::MatrixXd& fragments) = 0;
};

class AggregationHierarchy;  // backend/aggregation_hierarchy.h

// z = M r for a symmetric positive definite M that approximates A^-1, applied with one backend's
// operations (every column on its own). Made by that backend; it must not outlive it.
class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  virtual void apply(const DeviceVectors& r, DeviceVectors& z) = 0;
};

class Backend {
 public:
  virtual ~Backend() = default;

  [[nodiscard]] virtual BackendKind kind() const = 0;
  [[nodiscard]] virtual std::string description() const = 0;  // e.g. "cpu (eigen, cholmod)".
  [[nodiscard]] virtual bool supports(Feature feature) const = 0;
  // Largest difference seen so far between this backend and the CPU fallback when cross-checking
  // (SolverOptions::cross_check; solve/cross_check_backend.h), else 0. Every method copies it
  // into SolveReport::cross_check_error at the end.
  [[nodiscard]] virtual double cross_check_error() const { return 0.0; }

  // Data movement.
  [[nodiscard]] virtual std::unique_ptr<DeviceMatrix> upload(const RowMajorSparse& matrix) = 0;
  [[nodiscard]] virtual std::unique_ptr<DeviceVectors> upload(
      const Eigen::Ref<const Eigen::MatrixXd>& values) = 0;
  [[nodiscard]] virtual std::unique_ptr<DeviceVectors> allocate(int rows, int cols) = 0;  // zeros

  // BLAS-1 and SpMV; every operation acts column by column on the blocks.
  virtual void spmv(const DeviceMatrix& a, const DeviceVectors& x,
                    DeviceVectors& y) = 0;  // y = A x
  [[nodiscard]] virtual Eigen::VectorXd dot(const DeviceVectors& x, const DeviceVectors& y) = 0;
  virtual void axpy(const Eigen::VectorXd& alpha, const DeviceVectors& x,
                    DeviceVectors& y) = 0;  // y += a x
  virtual void xpay(const DeviceVectors& x, const Eigen::VectorXd& beta,
                    DeviceVectors& y) = 0;                          // y = x + b y
  virtual void copy(const DeviceVectors& x, DeviceVectors& y) = 0;  // y = x
  // Jacobi preconditioner: z = r ./ diag(A).
  virtual void jacobi(const DeviceMatrix& a, const DeviceVectors& r, DeviceVectors& z) = 0;

  // M = B diag(d) B^T with B's pattern fixed; `b` gives the pattern and first values, `diagonal`
  // the first d. The default computes M on the host and uploads its values; a device backend
  // may override it with a kernel (the Vulkan backend: shaders/normal_product.comp).
  [[nodiscard]] virtual std::unique_ptr<DeviceNormalProduct> normal_product(
      const RowMajorSparse& b, const Eigen::Ref<const Eigen::VectorXd>& diagonal);

  // The per-triangle operators of the connectivity `faces` (#F x 3) over `vertex_count` vertices;
  // a face index outside [0, vertex_count) throws harmonia::Error(invalid_input) naming the face.
  // A device backend's must not outlive it.
  [[nodiscard]] virtual std::unique_ptr<TriangleOperators> triangle_operators(
      const Eigen::MatrixX3i& faces, int vertex_count) = 0;

  // The V-cycle of a smoothed-aggregation hierarchy on this backend: its matrices are uploaded
  // once, and the default (multilevel_preconditioner.cpp) applies it with spmv, xpay and axpy
  // alone. The hierarchy may be destroyed afterwards.
  [[nodiscard]] virtual std::unique_ptr<Preconditioner> multilevel_preconditioner(
      const AggregationHierarchy& hierarchy);

  // Krylov solvers; the defaults (krylov.cpp) use only the primitives above. x holds the warm
  // start. pcg() is preconditioned by the diagonal (Jacobi), preconditioned_pcg() by
  // `preconditioner`, which this backend made (multilevel_preconditioner()).
  virtual SolveStats pcg(const DeviceMatrix& a, const DeviceVectors& b, DeviceVectors& x,
                         const IterativeSettings& settings, const ProgressCallback& progress);
  virtual SolveStats preconditioned_pcg(const DeviceMatrix& a, Preconditioner& preconditioner,
                                        const DeviceVectors& b, DeviceVectors& x,
                                        const IterativeSettings& settings,
                                        const ProgressCallback& progress);
  virtual SolveStats minres(const DeviceMatrix& a, const DeviceVectors& b, DeviceVectors& x,
                            const IterativeSettings& settings, const ProgressCallback& progress);
  // Jacobi-PCG on a block-diagonal A: every diagonal block k of every column c is its own system
  // A_kk x_k = b_k, with its own step lengths, direction weights and residual norm (a global dot
  // product would couple the blocks and change every iteration), and stops when
  // ||b_k - A_kk x_k|| <= relative_tolerance ||b_k||; a block with b_k = 0 gets x_k = 0 at once.
  // A system that breaks down (A_kk not positive definite, a non-finite residual) fails alone and
  // keeps its last iterate; the others go on. Each system's result is what pcg() on that block
  // alone gives. The block structure is checked on the host first (block_structure_error: a
  // violation returns Status::invalid_input and leaves x alone). max_iterations caps each system.
  // Progress: stage "block_pcg", in the backend's own steps (the default: systems done; a device:
  // iterations). The default (block_krylov.cpp) runs pcg() block by block and column by column;
  // a device backend solves all blocks together, several iterations per submission. x holds the
  // warm start.
  virtual BlockSolveStats block_pcg(const DeviceMatrix& a, const BlockRows& blocks,
                                    const DeviceVectors& b, DeviceVectors& x,
                                    const IterativeSettings& settings,
                                    const ProgressCallback& progress);
};

// Solves A X = B for one sparsity pattern, many value updates and many right-hand sides.
class SparseSystemSolver {
 public:
  virtual ~SparseSystemSolver() = default;
  // Symbolic analysis of the pattern (kept across factorize calls with the same pattern).
  virtual void analyze(const Eigen::SparseMatrix<double>& pattern) = 0;
  // The same with a fill-reducing ordering computed beforehand (ordering[k]: the row eliminated
  // k-th), so that the ordering can be computed off the critical path. Solvers that order the
  // unknowns themselves ignore it.
  virtual void analyze_with_ordering(const Eigen::SparseMatrix<double>& pattern,
                                     const std::vector<int>& ordering) {
    (void)ordering;
    analyze(pattern);
  }
  // The same with an ordering that is already a postorder of its elimination tree
  // (postordered_ordering()): used as it is, and the solver may renumber the matrix once so that
  // every factorization reads it as stored (CHOLMOD otherwise permutes and transposes it each
  // time), or split it on two threads.
  virtual void analyze_in_elimination_order(const Eigen::SparseMatrix<double>& pattern,
                                            const std::vector<int>& order) {
    analyze_with_ordering(pattern, order);
  }
  // Numeric factorization (direct) or upload + preconditioner setup (iterative).
  [[nodiscard]] virtual SolveStats factorize(const Eigen::SparseMatrix<double>& matrix) = 0;
  // Analysis and numeric factorization at once, in the elimination order first_half,
  // second_half, separator, where `separator` splits the rows of the two halves (a separator-first
  // nested dissection, separator_first_ordering.h; each half postordered) and the second half's
  // order may still be being computed: a solver that can factorizes the first half meanwhile.
  // `meanwhile` (if any): other work of the caller's, run once on the calling thread while the
  // second half is ordered or factorized. Later factorize() calls reuse the analysis. By default,
  // runs `meanwhile` and then waits for the whole order.
  [[nodiscard]] virtual SolveStats factorize_in_halves(
      const Eigen::SparseMatrix<double>& matrix, const std::vector<int>& separator,
      const std::vector<int>& first_half, const std::shared_future<std::vector<int>>& second_half,
      const std::function<void()>& meanwhile = {}) {
    if (meanwhile) meanwhile();
    std::vector<int> order = first_half;
    const std::vector<int>& second = second_half.get();
    order.insert(order.end(), second.begin(), second.end());
    order.insert(order.end(), separator.begin(), separator.end());
    analyze_in_elimination_order(matrix, order);
    return factorize(matrix);
  }
  // A hint that many solves will follow each factorization: a direct solver may keep a second copy
  // of its factor laid out for fast back-substitution (more memory, the same results up to
  // rounding). Iterative solvers ignore it.
  virtual void prefer_fast_solves() {}
  // X: #rows by k; on entry a warm start (iterative solvers), on exit the solution.
  [[nodiscard]] virtual SolveStats solve(const Eigen::MatrixXd& rhs, Eigen::MatrixXd& solution) = 0;
  [[nodiscard]] virtual std::string name()
      const = 0;  // e.g. "cholmod-supernodal-llt", "pcg-jacobi".
};

}  // namespace harmonia::detail
