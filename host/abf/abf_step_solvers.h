#pragma once
// Internal: the linear solvers of an ABF Newton step (thesis section 2.4).
//
// Every Newton step of ABF solves the saddle-point system (2.10), written as (2.12):
//     [ H  J^T ] [ dx     ]   [ r ]
//     [ J  0   ] [ lambda ] = [ s ]
// with H the diagonal (positive, see abf_newton.cpp) Hessian of the Lagrangian, J the Jacobian of
// the constraint rows of angle_constraints.h (triangle, vertex, wheel, active boundary), r the
// negative gradient of the Lagrangian and s the negative constraint values; lambda is then the
// change of the multipliers (abf_newton.cpp).
//
// The solvers, all written once against the Backend interface (so they run wherever the backend
// does), differ in how they treat the system:
//   schur_minres  M lambda = J H^-1 r - s with M = J H^-1 J^T (the backend's normal product),
//                 MINRES on M; then dx = H^-1 (r - J^T lambda).
//   uzawa         the modified Uzawa iteration with conjugate directions: conjugate gradients on
//                 the same Schur complement without ever forming M (products with J, J^T, H^-1).
//   full_minres   MINRES on the whole symmetric indefinite matrix S of (2.10).
//   full_cgnr     conjugate gradients on the normal equations S^2 z = S b (S is symmetric).
//   reduced       detail::ReducedAngleSystem: triangle rows eliminated face by face, then CHOLMOD
//                 on the CPU, PCG on devices (schur_direct / automatic).

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "abf/angle_constraints.h"
#include "backend/backend.h"
#include "harmonia/abf.h"

namespace harmonia::detail {

class AbfStepSolver {
 public:
  virtual ~AbfStepSolver() = default;
  // Solves the system above. `hessian`: the diagonal of H (all entries > 0). `lambda`: on entry a
  // warm start (same rows as `jacobian`, or empty for zeros), on exit the multipliers. The
  // pattern of `jacobian` may change between calls (another active boundary set).
  [[nodiscard]] virtual SolveStats solve(const RowMajorSparse& jacobian,
                                         const Eigen::VectorXd& hessian, const Eigen::VectorXd& r,
                                         const Eigen::VectorXd& s, Eigen::VectorXd& dx,
                                         Eigen::VectorXd& lambda) = 0;
  // e.g. "schur-minres", "uzawa-cg", "cholmod-supernodal-llt (reduced, ...)".
  [[nodiscard]] virtual std::string name() const = 0;
  // The notice of a move to the CPU (make_abf_step_solver's `cpu_retry`), once; else empty.
  [[nodiscard]] virtual std::string take_cpu_retry_notice() { return {}; }
};

// The largest relative residual of a step solve that Newton still uses: inexact Newton, a step
// solved to a modest accuracy still makes progress (the Newton tolerances judge the iterate), and
// Krylov solvers may stagnate above a very small relative tolerance on ill-conditioned steps.
inline constexpr double kInexactStepTolerance = 1e-6;

// Whether Newton can take the step a solve returned.
[[nodiscard]] inline bool usable_step(const SolveStats& stats) {
  return stats.status == Status::ok ||
         (stats.status == Status::not_converged && stats.relative_residual <= kInexactStepTolerance);
}

// The solver for `choice` on `backend` (which must outlive it). Returns nullptr and sets `error`
// when the choice is not available there (schur_direct on a device backend). `vertex_ordering`:
// a fill-reducing ordering of all vertices for the reduced system's factorization (see
// ReducedAngleSystem::use_vertex_ordering), or empty. `cpu_retry` (the backend was left to
// harmonia, BackendChoice::automatic): a step whose solve fails on a device in a way the CPU can
// make good (may_retry_on_cpu, solve/backend_selection.h) and that Newton cannot use is solved
// again by the same choice of solver on the CPU, which takes every later step.
[[nodiscard]] std::unique_ptr<AbfStepSolver> make_abf_step_solver(
    AbfSolver choice, Backend& backend, const AngleTopology& topology,
    const IterativeSettings& settings, const ProgressCallback& progress, std::string* error,
    std::vector<int> vertex_ordering = {}, bool cpu_retry = false);

// The Krylov-based solvers (abf_krylov_steps.cpp).
[[nodiscard]] std::unique_ptr<AbfStepSolver> make_schur_minres_step(
    Backend& backend, const IterativeSettings& settings, const ProgressCallback& progress);
[[nodiscard]] std::unique_ptr<AbfStepSolver> make_uzawa_step(Backend& backend,
                                                             const IterativeSettings& settings,
                                                             const ProgressCallback& progress);
[[nodiscard]] std::unique_ptr<AbfStepSolver> make_full_minres_step(
    Backend& backend, const IterativeSettings& settings, const ProgressCallback& progress);
[[nodiscard]] std::unique_ptr<AbfStepSolver> make_full_cgnr_step(
    Backend& backend, const IterativeSettings& settings, const ProgressCallback& progress);

// True when `matrix` has exactly the sparsity pattern recorded in `outer` / `inner`; otherwise
// records the new pattern and returns false. Lets a solver upload once per pattern.
bool same_pattern_or_record(const RowMajorSparse& matrix, std::vector<int>& outer,
                            std::vector<int>& inner);

}  // namespace harmonia::detail
