#pragma once
// Internal: the Dirichlet problem of a fixed-boundary map (thesis eq. 6.1), L_II X_I = -L_IB X_B,
// for a sequence of operators L that share one sparsity pattern (the mesh's vertex adjacency).
//
// The pattern is analyzed once. Each new operator is split into L_II and L_IB by a precomputed
// index map over its compressed arrays (no triplets, no search), then either factorized (direct
// solve) or, when it differs little from the operator factorized last, solved by conjugate
// gradients preconditioned with that older factorization (quasi-harmonic rounds).

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "backend/backend.h"
#include "harmonia/map_result.h"
#include "harmonia/solver_options.h"

namespace harmonia::detail {

//! How a solve with an older factorization ended.
enum class StaleFactorOutcome {
  converged,     //!< The solution meets the accuracy targets.
  too_slow,      //!< It would take too many iterations: refactorize instead (solution untouched).
  failed,        //!< A solver error; report.status/message are set.
};

class DirichletSystem {
 public:
  //! `operator_pattern`: #V by #V, its stored entries a superset of every operator's entries (for
  //! the operators of this library: the diagonal and all vertex pairs sharing a face, the
  //! pattern of detail::AdjacencyPattern). `fixed_vertices`: the B vertices with given
  //! positions; the rest are free. Analyzes the pattern of L_II, with `vertex_ordering` (a
  //! fill-reducing ordering of all #V vertices, fill_reducing_ordering of the operator pattern,
  //! restricted here to the free ones) when one is given.
  DirichletSystem(const Eigen::SparseMatrix<double>& operator_pattern,
                  const Eigen::VectorXi& fixed_vertices, Backend& backend, MatrixKind kind,
                  const SolverOptions& options, const std::vector<int>& vertex_ordering = {});

  //! Extracts L_II and L_IB of `operator_matrix` (#V by #V) without factorizing. Returns false,
  //! with numerical_failure in report, for a non-finite entry in a free row.
  [[nodiscard]] bool load(const Eigen::SparseMatrix<double>& operator_matrix, SolveReport& report);

  //! Factorizes the loaded L_II. A symmetric matrix whose Cholesky fails (not positive definite) is
  //! retried with LU. Fills report.solver.
  [[nodiscard]] bool factorize_loaded(SolveReport& report);

  //! load() then factorize_loaded().
  [[nodiscard]] bool factorize(const Eigen::SparseMatrix<double>& operator_matrix,
                               SolveReport& report) {
    return load(operator_matrix, report) && factorize_loaded(report);
  }

  //! All #V positions: fixed rows from fixed_uv (#B by 2, in fixed_vertices order), free rows
  //! solved with the factorization of the loaded operator. Accumulates iterations and the worst
  //! residual ||A x - b|| / ||b|| into report.
  [[nodiscard]] bool solve(const Eigen::MatrixX2d& fixed_uv, Eigen::MatrixX2d& uv,
                           SolveReport& report);

  //! The Poisson form (thesis eq. 6.2): L_II X_I = load_I - L_IB X_B, with `load` (#V by 2) the
  //! right-hand side of every vertex (the rows of fixed vertices are not used).
  [[nodiscard]] bool solve(const Eigen::MatrixX2d& fixed_uv, const Eigen::MatrixX2d& load,
                           Eigen::MatrixX2d& uv, SolveReport& report);

  //! The same for any number of columns (fixed_values: #B by m; load: empty or #V by m; values:
  //! #V by m), e.g. three coordinates or one column per harmonic field. The last solution warm-starts
  //! an iterative solver when it has the same number of columns.
  [[nodiscard]] bool solve_columns(const Eigen::MatrixXd& fixed_values, const Eigen::MatrixXd& load,
                                   Eigen::MatrixXd& values, SolveReport& report);

  //! For a caller that solves many times per factorization (an editor's frames): the solver keeps
  //! a copy of each factor laid out for fast back-substitution (SparseSystemSolver::
  //! prefer_fast_solves). Call before factorizing.
  void prefer_fast_solves() { solver_->prefer_fast_solves(); }
  //! Solves from now on skip their residual check (a sparse product, about a tenth of a
  //! back-substitution) and leave report.residual untouched: for a direct solver whose residual
  //! has been seen to be at rounding level on the same matrix.
  void skip_residual_checks() { measure_residual_ = false; }

  //! True when the last factorization is a Cholesky factor that can precondition conjugate
  //! gradients on a later operator of the same pattern (direct backend, SPD, factorized once).
  [[nodiscard]] bool has_reusable_factor() const;

  //! Solves the loaded operator's system by conjugate gradients preconditioned with the last
  //! factorization (of an earlier, similar operator), warm-started from the last solution. Stops
  //! when every column has a preconditioned estimate of its relative error |F^-1 r| / |x| <=
  //! `error_target` and relative residual <= `residual_target` (a Laplacian's small residual can
  //! hide a larger error in smooth modes, hence both). Gives up (too_slow, uv untouched) as soon as
  //! the observed convergence rate predicts more than `max_iterations` iterations.
  [[nodiscard]] StaleFactorOutcome solve_with_stale_factor(const Eigen::MatrixX2d& fixed_uv,
                                                           double error_target,
                                                           double residual_target,
                                                           int max_iterations, Eigen::MatrixX2d& uv,
                                                           SolveReport& report);

  [[nodiscard]] int free_count() const { return static_cast<int>(free_vertices_.size()); }

 private:
  // With BackendChoice::automatic, a device whose factorization (preconditioner set-up) or solve
  // failed hands the system to the CPU, which factorizes the loaded operator directly: the caller
  // let harmonia choose where to compute, so a result on the CPU serves it better than an error.
  // The notice goes to report.fallbacks, and the system stays on the CPU from then on.
  [[nodiscard]] bool may_move_to_cpu(const SolveStats& failed) const;
  [[nodiscard]] bool move_to_cpu(const SolveStats& failed, SolveReport& report);
  // The backend the system now computes on: the caller's, or the CPU after move_to_cpu.
  [[nodiscard]] Backend& active_backend() const { return cpu_backend_ ? *cpu_backend_ : backend_; }
  void build_index_maps(const Eigen::SparseMatrix<double>& operator_pattern);
  void analyze_with(std::unique_ptr<SparseSystemSolver> solver,
                    const std::vector<int>& vertex_ordering = {});
  [[nodiscard]] bool scatter_other_pattern(const Eigen::SparseMatrix<double>& operator_matrix,
                                           SolveReport& report);
  [[nodiscard]] Eigen::MatrixXd right_hand_side(const Eigen::MatrixXd& fixed_values) const;
  void record_solution(const Eigen::MatrixXd& solution, const Eigen::MatrixXd& rhs,
                       const Eigen::MatrixXd& fixed_values, Eigen::MatrixXd& values,
                       SolveReport& report);

  Backend& backend_;
  std::unique_ptr<Backend> cpu_backend_;  // After move_to_cpu.
  SolverOptions options_;
  Eigen::VectorXi fixed_vertices_;
  std::vector<int> free_vertices_;
  std::vector<int> free_index_;   // #V: index among the free vertices, or -1.
  std::vector<int> fixed_index_;  // #V: index among the fixed vertices, or -1.
  // The operator pattern the index map was built for, and where each of its stored entries goes:
  // >= 0 a slot of interior_, <= -2 the slot -2 - t of coupling_, -1 nowhere (a fixed row).
  std::vector<int> pattern_outer_;
  std::vector<int> pattern_inner_;
  std::vector<int> slot_target_;
  Eigen::SparseMatrix<double> interior_;  // L_II with the fixed pattern of the mesh edges.
  Eigen::SparseMatrix<double> coupling_;  // L_IB (free rows, fixed columns), fixed pattern.
  MatrixKind kind_;
  std::unique_ptr<SparseSystemSolver> solver_;
  bool fell_back_to_lu_ = false;
  bool measure_residual_ = true;
  bool factorized_ = false;     // The factor belongs to the loaded operator.
  bool has_factor_ = false;     // Some operator of this pattern has been factorized.
  Eigen::MatrixXd last_solution_;  // Free rows of the last solve (warm start).
  Eigen::MatrixXd rhs_;            // The last solve's right-hand side (storage reused).
};

}  // namespace harmonia::detail
