#pragma once
// Internal: the pieces every planar map shares — input validation, phase timing with progress and
// cancellation, the Dirichlet system L_II u_I = -L_IB u_B with a reusable factorization, and the
// finishing of a result (finite check, normalization, validity counts).

#include <chrono>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "detail/backend.h"
#include "harmonia/boundary.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia::detail {

//! Checks that `mesh` is a disk (indices, finite coordinates, manifold, one boundary loop, genus 0)
//! and returns its boundary loop (mesh to the left, starting at its smallest vertex). On failure
//! sets report.status/message (pointing at `harmonia cut` for non-disks) and returns an empty loop.
[[nodiscard]] std::vector<int> validate_disk_input(const Mesh& mesh, SolveReport& report);

//! Checks the boundary options against the mesh: for `given`, at least 2 distinct vertices in
//! range, one finite uv row per vertex. Sets invalid_input and returns false otherwise.
[[nodiscard]] bool validate_boundary_options(const Mesh& mesh, const BoundaryOptions& options,
                                             SolveReport& report);

//! The backend for the options; on failure sets report.status = unsupported and returns nullptr.
[[nodiscard]] std::unique_ptr<Backend> choose_backend(const SolverOptions& options,
                                                      SolveReport& report);

//! Times named phases into report.timings and reports them to the progress callback.
class PhaseClock {
 public:
  PhaseClock(SolveReport& report, const ProgressCallback& progress)
      : report_(report), progress_(progress) {}
  //! Ends the running phase (if any) and starts `phase`. Returns false, with report.status set to
  //! cancelled, when the progress callback asks to stop.
  [[nodiscard]] bool start(std::string_view phase, int step = 0, int total = 0);
  //! Ends the running phase.
  void stop();
  ~PhaseClock() { stop(); }

 private:
  SolveReport& report_;
  ProgressCallback progress_;
  std::string phase_;
  std::chrono::steady_clock::time_point started_;
  bool running_ = false;
};

//! The Dirichlet problem of a fixed-boundary map: vertices split into free (I) and fixed (B);
//! for an operator L on all vertices solves L_II X_I = -L_IB X_B, two columns (u, v) at once.
//! The pattern of L_II comes from the mesh edges, so it is analyzed once and every later operator
//! with the same connectivity only refactorizes numerically.
class DirichletSystem {
 public:
  DirichletSystem(int vertex_count, const Eigen::MatrixX3i& faces,
                  const Eigen::VectorXi& fixed_vertices, Backend& backend, MatrixKind kind,
                  const SolverOptions& options);

  //! Extracts L_II, L_IB from `operator_matrix` (#V by #V) and factorizes L_II. A symmetric matrix
  //! whose Cholesky fails (not positive definite) is retried with LU. Fills report.solver.
  [[nodiscard]] bool factorize(const Eigen::SparseMatrix<double>& operator_matrix,
                               SolveReport& report);

  //! All #V positions: fixed rows from fixed_uv (#B by 2, in fixed_vertices order), free rows
  //! solved. Accumulates iterations and the worst residual ||A x - b|| / ||b|| into report.
  [[nodiscard]] bool solve(const Eigen::MatrixX2d& fixed_uv, Eigen::MatrixX2d& uv,
                           SolveReport& report);

  [[nodiscard]] int free_count() const { return static_cast<int>(free_vertices_.size()); }

 private:
  void analyze_with(std::unique_ptr<SparseSystemSolver> solver);

  Backend& backend_;
  SolverOptions options_;
  Eigen::VectorXi fixed_vertices_;
  std::vector<int> free_vertices_;
  std::vector<int> free_index_;           // #V: index among the free vertices, or -1.
  std::vector<int> fixed_index_;          // #V: index among the fixed vertices, or -1.
  Eigen::SparseMatrix<double> interior_;  // L_II with the fixed pattern of the mesh edges.
  Eigen::SparseMatrix<double> coupling_;  // L_IB.
  MatrixKind kind_;
  std::unique_ptr<SparseSystemSolver> solver_;
  bool fell_back_to_lu_ = false;
  bool factorized_ = false;
  Eigen::MatrixXd warm_start_;
};

//! Finishes a map: non-finite UVs -> numerical_failure with an empty uv; otherwise normalizes,
//! counts flipped/zero-area triangles and boundary self-intersections, and sets flipped_triangles
//! when there are flipped or zero-area triangles (the UVs are kept).
void finish_map(const Mesh& mesh, UvNormalization normalization, Eigen::MatrixX2d& uv,
                SolveReport& report, PhaseClock& clock);

}  // namespace harmonia::detail
