#pragma once
// Internal: the Newton/Lagrange iteration of nonlinear ABF (thesis section 2.3) with the boundary
// inequalities (2.6) handled by an active set.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "abf/abf_step_solvers.h"
#include "abf/angle_constraints.h"
#include "harmonia/solver_options.h"

namespace harmonia::detail {

struct AbfNewtonSettings {
  double boundary_t = 2.0;
  bool underdetermined = false;  // Objective zero: a feasible point close to the start (2.4.3).
  int max_iterations = 50;
  double constraint_tolerance = 1e-10;
  double gradient_tolerance = 1e-8;
  Eigen::VectorXd start;  // Start angles (3F); empty: the targets.
  // Warm start of the multipliers (continuation in t): the equality rows' (F + 2I) and one per
  // boundary vertex (loop order; nonzero marks a row that was active). Empty: zeros.
  Eigen::VectorXd start_equality_multipliers;
  Eigen::VectorXd start_boundary_multipliers;
};

struct AbfNewtonResult {
  Eigen::VectorXd angles;            // 3F, the final iterate.
  int steps = 0;                     // Newton steps taken.
  int inner_iterations = 0;          // Summed over the step solves.
  double inner_residual = 0.0;       // Largest relative residual of a step solve.
  double constraint_residual = 0.0;  // Largest violation (equalities, all boundary rows).
  double gradient_residual = 0.0;    // |grad L|_inf / max(1, |grad f|_inf) at the end.
  std::vector<int> active_boundary;  // Boundary vertices whose row (2.6) was active at the end.
  Eigen::VectorXd equality_multipliers;  // At the final iterate (for a warm start).
  Eigen::VectorXd boundary_multipliers;  // Per boundary vertex, zero where inactive.
  Status status = Status::ok;
  std::string message;
};

// The sum of the angles at every boundary vertex (topology.boundary_vertices order).
[[nodiscard]] Eigen::VectorXd boundary_angle_sums(const AngleTopology& topology,
                                                  const Eigen::VectorXd& angles);

// Minimizes (2.8) sum w (x - a)^2, w = 1/a^2, from x = a under the angle constraints, every
// angle kept above 1 % of its target (see kSmallestAngleFraction in abf_newton.cpp); calls
// `progress` once per Newton step with the stage "newton K (violation V)".
[[nodiscard]] AbfNewtonResult solve_abf_angles(const AngleTopology& topology,
                                               const Eigen::VectorXd& targets,
                                               const AbfNewtonSettings& settings,
                                               AbfStepSolver& step_solver,
                                               const ProgressCallback& progress);

}  // namespace harmonia::detail
