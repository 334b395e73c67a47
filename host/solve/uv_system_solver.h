#pragma once
// Internal: the pinned [u; v] system shared by LSCM and the least-squares reconstruction from
// angles. Both minimize a conformal energy whose matrix (2V x 2V, u_0..u_{V-1} then v_0..v_{V-1})
// is
//     Q = [ L   N ]
//         [ N^T L ],
// one symmetric Laplacian L for both coordinates and an antisymmetric area coupling N that lives
// on few vertices (the boundary, and the edges of degenerate triangles), with two vertices pinned.
//
// Two ways to solve it (uv_system_solver.cpp):
//   * coupled blocks: the 2(V - 2) free unknowns as one SPD system on the backend (a direct
//     factorization on the CPU, PCG on devices);
//   * one Laplacian factor (CPU with CHOLMOD): L's free block is factorized once, its coupled
//     vertices last, and u and v meet only in a dense system on those vertices. About half the
//     arithmetic of the coupled blocks, as long as the coupled vertices are few.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "backend/backend.h"

namespace harmonia::detail {

//! The two vertices whose positions fix the similarity left free by a conformal energy: `first`
//! at (0, 0), `second` at (distance, 0).
struct LayoutPins {
  int first = 0;
  int second = 1;
  double distance = 1.0;
};

enum class UvSystemStrategy {
  automatic,         // One Laplacian factor where available and cheaper, else coupled blocks.
  coupled_blocks,    // Always the 2(V - 2)-unknown system.
  shared_laplacian,  // One Laplacian factor where available (CPU with CHOLMOD).
};

class UvSystemSolver {
 public:
  // `backend` must outlive the solver.
  UvSystemSolver(Backend& backend, const IterativeSettings& settings,
                 const ProgressCallback& progress,
                 UvSystemStrategy strategy = UvSystemStrategy::automatic);
  ~UvSystemSolver();
  UvSystemSolver(const UvSystemSolver&) = delete;
  UvSystemSolver& operator=(const UvSystemSolver&) = delete;

  //! Symbolic work for the pattern of `form` (Q above, both triangles stored) and `pins`; skipped
  //! when both are those of the previous call. `vertex_ordering`: a fill-reducing ordering of the
  //! V vertices, or empty (an AMD ordering is computed).
  void analyze(const Eigen::SparseMatrix<double>& form, const LayoutPins& pins,
               const std::vector<int>& vertex_ordering);
  //! Numeric factorization of `form` (the pattern analyzed last), which the solver takes over
  //! (the caller's is left empty) for the right-hand side and the residual: no copy of the form,
  //! about 0.3 GB for an 827K-face mesh.
  [[nodiscard]] SolveStats factorize(Eigen::SparseMatrix<double>&& form);
  //! The minimizer with the pins in place (#V x 2). stats.relative_residual: that of the free
  //! rows, |Q x|_F / |Q_FP x_P|. `refinement_steps` steps of iterative refinement follow the
  //! solve (each one more solve with the factorization, on the residual): the residual is at the
  //! rounding level already, but the positions' error (the condition number times it, 1e-9
  //! radians in a boundary angle of a long thin mesh) shrinks several times per step. Direct
  //! factorizations only.
  [[nodiscard]] SolveStats solve(Eigen::MatrixX2d& uv, int refinement_steps = 0);

  //! For a caller whose backend was left to harmonia (BackendChoice::automatic): a factorization
  //! or solve that fails on the device (may_retry_on_cpu in solve/backend_selection.h) is done
  //! again on the CPU, which keeps the system from then on. Call before analyze().
  void allow_cpu_retry();
  //! The notice of such a move (cpu_retry_notice), once, for SolveReport::fallbacks; empty when
  //! nothing moved since the last call.
  [[nodiscard]] std::string take_cpu_retry_notice();

  //! e.g. "cholmod-supernodal-llt (one Laplacian factor for u and v, 384 coupled vertices)".
  [[nodiscard]] std::string name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace harmonia::detail
