// The Newton/Lagrange iteration of nonlinear ABF (thesis sections 2.3-2.4).
//
// Lagrangian L = f(x) + lambda^T h(x) over the rows of angle_constraints.h, with f the objective
// (2.8) and the boundary inequalities (2.6) g_b(x) = (sum of angles at b) - t pi <= 0 handled by
// an active set (section 2.3; the rule is at choose_active_set): active rows are equalities,
// inactive ones have mu_b = 0. Each step solves (2.10) for the step of the angles and of the
// multipliers with the diagonal Hessian that the log-sine wheel rows (2.11) allow:
//   H_ii = f''(x_i) - m_i / sin^2 x_i,  m_i = the wheel multipliers of the rows x_i appears in,
//          +lambda_v where x_i is a left angle beta of the wheel of v, -lambda_v where it is a
//          right angle gamma,
// plus the curvature of the barrier that keeps every angle above a small fraction of its target
// (kSmallestAngleFraction).

#include "abf/abf_newton.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace harmonia::detail {
namespace {

// The wheel terms can make H_ii small or negative; the step solvers need H > 0 (H^-1 in the
// Schur complement, CHOLMOD on J H^-1 J^T). A negative entry is replaced by its magnitude (the
// curvature's size is kept, its sign made convex) and every entry is at least this fraction of
// f''(x_i) = 2 w_i. Where the true H is positive (the usual case near the solution: small
// multipliers) Newton's fast local convergence is kept; where it is not, convergence is linear.
constexpr double kHessianFloor = 0.1;
// Step control: an angle may move at most this fraction of the way to pi in one step ...
constexpr double kAngleMargin = 0.5;
// ... the weights of the angles that would go further are multiplied by this, up to so many
// times, before the step is shortened instead; a step shorter than the last is a failure.
constexpr double kReweightFactor = 10.0;
constexpr int kMaxReweights = 4;
// Steps shorter than this (a fraction of the Newton step) turn on the lower-side reweighting.
constexpr double kStallingStepLength = 0.1;
constexpr double kShortestStep = 1e-12;
// Lower bounds l = kSmallestAngleFraction * a on the angles. The objective (2.8) charges at most
// w a^2 = 1 for an angle driven all the way to 0, so on a mesh whose angle-preserving flattening
// needs extreme changes of scale (long protrusions left uncut, e.g. the legs of a cow cut open
// along its back) the infimum lies at triangles with zero angles: Newton crawls towards it and
// never converges. With the bounds a minimum exists. They are kept by the logarithmic barrier
// -mu sum log(x - l) added to (2.8), in primal-dual form (bound multipliers z with
// z (x - l) = mu): its weight mu is so small that where no angle comes near its bound it moves
// the angles by about mu a^2 (far below every tolerance), while next to a bound its curvature
// z / (x - l) takes that angle out of the step.
constexpr double kSmallestAngleFraction = 0.01;
constexpr double kBarrierWeight = 1e-10;
// Fraction to the bound: a step may take an angle at most this fraction of its remaining
// distance to its lower bound.
constexpr double kLowerMargin = 0.9;
// After each step z is kept within [c / k, c k] of its central value c = mu / (x - l).
constexpr double kBoundMultiplierBand = 1e10;

double infinity_norm(const Eigen::VectorXd& v) { return v.size() ? v.cwiseAbs().maxCoeff() : 0.0; }

// The diagonal of the Hessian of the Lagrangian (see the file comment), floored.
Eigen::VectorXd lagrangian_hessian(const AngleTopology& topology, const Eigen::VectorXd& angles,
                                   const Eigen::VectorXd& weights,
                                   const Eigen::VectorXd& multipliers) {
  const int faces = topology.face_count;
  const int interior = topology.interior_count();
  Eigen::VectorXd wheel_multiplier = Eigen::VectorXd::Zero(angles.size());
  for (int i = 0; i < interior; ++i) {
    const int vertex = topology.interior_vertices[static_cast<std::size_t>(i)];
    const double lambda = multipliers[faces + interior + i];
    for (int k = topology.vertex_corner_offsets[static_cast<std::size_t>(vertex)];
         k < topology.vertex_corner_offsets[static_cast<std::size_t>(vertex) + 1]; ++k) {
      const int corner = topology.vertex_corners[static_cast<std::size_t>(k)];
      const int face_base = corner - corner % 3;
      wheel_multiplier[face_base + (corner + 1) % 3] += lambda;  // beta: the next corner
      wheel_multiplier[face_base + (corner + 2) % 3] -= lambda;  // gamma: the previous corner
    }
  }
  Eigen::VectorXd hessian(angles.size());
  for (Eigen::Index i = 0; i < angles.size(); ++i) {
    const double sine = std::sin(angles[i]);
    const double objective_part = 2.0 * weights[i];
    hessian[i] = std::max(std::abs(objective_part - wheel_multiplier[i] / (sine * sine)),
                          kHessianFloor * objective_part);
  }
  return hessian;
}

// The active boundary vertices (loop order). A violated row (g > 0) is always active; a row that
// was active stays so while its multiplier has the sign of a pushing constraint (mu >= 0), and
// leaves when the multiplier says it pulls (the active-set rule of section 2.3 with the
// multiplier test applied only to rows that are satisfied: a rule g + mu / c >= 0 with a fixed c
// let violated rows go when the multipliers are large). The underdetermined variant has no
// meaningful multipliers and keeps a row active once it was violated. Never all of them: with
// every row (2.6) an equality the rows would contradict the angle sum pi (n - 2) of the boundary
// (2.7) for any t > 1 - 2/n, so the least violated one is left out.
std::vector<int> choose_active_set(const Eigen::VectorXd& boundary_values,
                                   const Eigen::VectorXd& boundary_multipliers,
                                   std::vector<bool>& was_active, bool underdetermined) {
  const Eigen::Index n = boundary_values.size();
  std::vector<int> active;
  Eigen::Index least = -1;
  for (Eigen::Index b = 0; b < n; ++b) {
    const auto position = static_cast<std::size_t>(b);
    const bool is_active =
        boundary_values[b] > 0.0 ||
        (was_active[position] && (underdetermined || boundary_multipliers[b] >= 0.0));
    if (!is_active) continue;
    active.push_back(static_cast<int>(b));
    if (least < 0 || boundary_values[b] < boundary_values[least]) least = b;
  }
  if (n > 0 && static_cast<Eigen::Index>(active.size()) == n)
    active.erase(std::find(active.begin(), active.end(), static_cast<int>(least)));
  std::fill(was_active.begin(), was_active.end(), false);
  for (const int b : active) was_active[static_cast<std::size_t>(b)] = true;
  return active;
}

}  // namespace

Eigen::VectorXd boundary_angle_sums(const AngleTopology& topology, const Eigen::VectorXd& angles) {
  Eigen::VectorXd sums(static_cast<Eigen::Index>(topology.boundary_vertices.size()));
  for (std::size_t b = 0; b < topology.boundary_vertices.size(); ++b) {
    const auto vertex = static_cast<std::size_t>(topology.boundary_vertices[b]);
    double sum = 0.0;
    for (int k = topology.vertex_corner_offsets[vertex];
         k < topology.vertex_corner_offsets[vertex + 1]; ++k)
      sum += angles[topology.vertex_corners[static_cast<std::size_t>(k)]];
    sums[static_cast<Eigen::Index>(b)] = sum;
  }
  return sums;
}

AbfNewtonResult solve_abf_angles(const AngleTopology& topology, const Eigen::VectorXd& targets,
                                 const AbfNewtonSettings& settings, AbfStepSolver& step_solver,
                                 const ProgressCallback& progress) {
  AbfNewtonResult result;
  const Eigen::Index n_boundary = static_cast<Eigen::Index>(topology.boundary_vertices.size());
  const Eigen::Index equality_rows = topology.face_count + 2 * topology.interior_count();
  const double bound = settings.boundary_t * std::numbers::pi;
  const Eigen::VectorXd weights = targets.array().square().inverse();

  // The lower bounds of the angles (see kSmallestAngleFraction).
  const Eigen::VectorXd lower_bounds = kSmallestAngleFraction * targets;
  Eigen::VectorXd x = settings.start.size() == targets.size() ? settings.start : targets;
  // Strictly inside the barrier. Only angles that are not are moved: a warm start (continuation
  // in t) has angles a hair above their bounds, and lifting those to 2 l broke each wheel row
  // (2.11) they appear in by log 2, so every stage began far from feasible.
  for (Eigen::Index i = 0; i < x.size(); ++i)
    if (!(x[i] > lower_bounds[i])) x[i] = 2.0 * lower_bounds[i];
  // The multipliers z of the bounds, kept primal-dual (z (x - l) = mu at the barrier's minimum):
  // Newton on that product rather than on mu / (x - l) lets an angle settle next to its bound
  // in a few steps instead of jamming against the fraction-to-the-bound rule.
  Eigen::VectorXd bound_multipliers = kBarrierWeight * (x - lower_bounds).cwiseInverse();
  Eigen::VectorXd equality_multipliers =
      settings.start_equality_multipliers.size() == equality_rows
          ? settings.start_equality_multipliers
          : Eigen::VectorXd(Eigen::VectorXd::Zero(equality_rows));
  Eigen::VectorXd boundary_multipliers =
      settings.start_boundary_multipliers.size() == n_boundary
          ? settings.start_boundary_multipliers
          : Eigen::VectorXd(Eigen::VectorXd::Zero(n_boundary));
  // A warm start keeps the rows that were active (nonzero multiplier) as candidates.
  std::vector<bool> was_active(static_cast<std::size_t>(n_boundary), false);
  for (Eigen::Index b = 0; b < n_boundary; ++b)
    was_active[static_cast<std::size_t>(b)] = boundary_multipliers[b] != 0.0;

  // Set once a step has been cut short (see reweight_lower below).
  bool steps_cut_short = false;
  for (int step = 0;; ++step) {
    // Active set, constraint values and Jacobian at the current iterate.
    const Eigen::VectorXd boundary_values = boundary_angle_sums(topology, x).array() - bound;
    const std::vector<int> active_positions = choose_active_set(
        boundary_values, boundary_multipliers, was_active, settings.underdetermined);
    std::vector<int> active_vertices;
    for (const int b : active_positions) {
      active_vertices.push_back(topology.boundary_vertices[static_cast<std::size_t>(b)]);
    }
    const AngleConstraints constraints =
        evaluate_angle_constraints(topology, x, active_vertices, settings.boundary_t);
    const Eigen::Index rows = constraints.jacobian.rows();
    Eigen::VectorXd multipliers(rows);
    multipliers.head(equality_rows) = equality_multipliers;
    for (std::size_t k = 0; k < active_positions.size(); ++k)
      multipliers[equality_rows + static_cast<Eigen::Index>(k)] =
          boundary_multipliers[active_positions[k]];

    // Convergence: constraints (every boundary row, active or not), gradient of the Lagrangian,
    // and multipliers of active inequalities of the right sign (a negative one would leave).
    double violation = constraint_violation(constraints);
    if (n_boundary > 0) violation = std::max(violation, boundary_values.maxCoeff());
    const Eigen::VectorXd objective_gradient =
        settings.underdetermined ? Eigen::VectorXd::Zero(x.size())
                                 : Eigen::VectorXd(2.0 * weights.cwiseProduct(x - targets));
    const Eigen::VectorXd constraint_forces = constraints.jacobian.transpose() * multipliers;
    const Eigen::VectorXd lagrangian_gradient = objective_gradient + constraint_forces;
    // Stationarity with the bounds: the gradient of the Lagrangian less the bound multipliers.
    const Eigen::VectorXd slack = x - lower_bounds;
    const Eigen::VectorXd barrier_gradient = lagrangian_gradient - bound_multipliers;
    result.gradient_residual = settings.underdetermined
                                   ? 0.0
                                   : infinity_norm(barrier_gradient) /
                                         std::max({1.0, infinity_norm(objective_gradient),
                                                   infinity_norm(constraint_forces)});
    bool dual_feasible = true;
    for (const int b : active_positions)
      dual_feasible = dual_feasible && boundary_multipliers[b] >= 0.0;
    result.constraint_residual = violation;
    result.angles = x;
    result.active_boundary = active_vertices;
    result.equality_multipliers = equality_multipliers;
    result.boundary_multipliers = boundary_multipliers;
    if (violation <= settings.constraint_tolerance &&
        result.gradient_residual <= settings.gradient_tolerance &&
        (settings.underdetermined || dual_feasible))
      return result;
    if (step >= settings.max_iterations) {
      result.status = Status::not_converged;
      char text[160];
      std::snprintf(text, sizeof text,
                    "abf: no convergence in %d Newton steps (constraint violation %.3g, "
                    "relative gradient %.3g)",
                    step, violation, result.gradient_residual);
      result.message = text;
      return result;
    }
    if (progress) {
      char stage[96];
      std::snprintf(stage, sizeof stage, "newton %d (violation %.2e, %zu boundary rows active)",
                    step + 1, violation, active_positions.size());
      if (!progress(Progress{stage, step, settings.max_iterations})) {
        result.status = Status::cancelled;
        result.message = "cancelled by the progress callback at Newton step " +
                         std::to_string(step + 1);
        return result;
      }
    }

    // The Newton system (2.10) for the step and the change of the multipliers:
    //   H dx + J^T dlambda = -grad L,  J dx = -h.
    // In this increment form both right-hand sides vanish at the solution, so an iterative step
    // solver's relative tolerance becomes an ever smaller absolute error as Newton converges.
    // The underdetermined variant has no objective: its step is the least-norm correction
    // dx = -W J^T (J W J^T)^-1 h in the metric of the objective (W = a^2 / 2), which keeps the
    // iterate close to the start angles.
    Eigen::VectorXd hessian =
        settings.underdetermined ? Eigen::VectorXd(2.0 * weights)
                                 : lagrangian_hessian(topology, x, weights, multipliers);
    const Eigen::VectorXd step_gradient =
        settings.underdetermined
            ? Eigen::VectorXd::Zero(x.size())
            : Eigen::VectorXd(lagrangian_gradient - kBarrierWeight * slack.cwiseInverse());
    if (!settings.underdetermined)
      hessian += bound_multipliers.cwiseQuotient(slack);
    Eigen::VectorXd dx, multiplier_change;
    // Angles whose bound the barrier does not yet show to Newton: its curvature z / (x - l) is
    // below the objective's 2 w. (Where it is above, the angle already sits on its bound and
    // its step only adjusts the slack, which the fraction-to-the-bound rule handles.)
    const Eigen::Array<bool, Eigen::Dynamic, 1> barrier_unseen =
        bound_multipliers.cwiseQuotient(slack).array() < 2.0 * weights.array();
    // Only once the fraction-to-the-bound rule has cut a step short: reweighting costs a solve
    // per attempt, and where steps stay long the barrier and that rule converge on their own.
    const Eigen::Array<bool, Eigen::Dynamic, 1> reweight_lower =
        steps_cut_short
            ? barrier_unseen
            : Eigen::Array<bool, Eigen::Dynamic, 1>::Constant(barrier_unseen.size(), false);
    // Step control (section 2.4.1): a step that takes an angle too close to pi, or past the
    // fraction-to-the-bound margin towards its lower bound, is rejected and solved again with the
    // weights of the offending angles increased, so that the step moves them less; if that does
    // not settle it, the step is shortened to stay inside. On the lower side the barrier alone
    // cannot do this: its curvature mu / (x - l)^2 only shows within about a sqrt(mu) of the
    // bound, so an angle heading for it cut the whole step to a fraction of its remaining
    // distance, one angle after the other (convex ABF, t = 1, on camel_b: dozens of angles end
    // on their bound and the steps shrank to 1e-4).
    for (int attempt = 0;; ++attempt) {
      multiplier_change.resize(0);
      const SolveStats stats = step_solver.solve(constraints.jacobian, hessian, -step_gradient,
                                                 -constraints.values, dx, multiplier_change);
      result.inner_iterations += stats.iterations;
      result.inner_residual = std::max(result.inner_residual, stats.relative_residual);
      if (!usable_step(stats)) {
        result.status = stats.status;
        result.message = "abf: Newton step " + std::to_string(step + 1) + ": " + stats.message;
        return result;
      }
      if (!dx.allFinite() || !multiplier_change.allFinite()) {
        result.status = Status::numerical_failure;
        result.message = "abf: Newton step " + std::to_string(step + 1) + " is not finite";
        return result;
      }
      const Eigen::ArrayXd trial = (x + dx).array();
      const Eigen::Array<bool, Eigen::Dynamic, 1> leaving =
          trial >= std::numbers::pi - kAngleMargin * (std::numbers::pi - x.array()) ||
          (trial <= lower_bounds.array() + (1.0 - kLowerMargin) * slack.array() &&
           reweight_lower);
      if (!leaving.any() || attempt == kMaxReweights) break;
      hessian = leaving.select(kReweightFactor * hessian.array(), hessian.array()).matrix();
    }
    // The longest step (at most 1) that keeps every angle inside both margins.
    double length = 1.0;
    for (Eigen::Index i = 0; i < x.size(); ++i) {
      if (dx[i] < 0.0)
        length = std::min(length, kLowerMargin * (x[i] - lower_bounds[i]) / -dx[i]);
      if (dx[i] > 0.0)
        length = std::min(length, (1.0 - kAngleMargin) * (std::numbers::pi - x[i]) / dx[i]);
    }
    if (!(length > kShortestStep)) {
      result.status = Status::numerical_failure;
      result.message = "abf: Newton step " + std::to_string(step + 1) +
                       " cannot keep the angles inside (0, pi)";
      return result;
    }
    x += length * dx;
    steps_cut_short = steps_cut_short || length < kStallingStepLength;
    if (!settings.underdetermined) {
      // The bound multipliers' own Newton step, kept positive and within a wide band around
      // mu / (x - l) (the usual safeguard of primal-dual barrier methods).
      const Eigen::VectorXd bound_change = kBarrierWeight * slack.cwiseInverse() -
                                           bound_multipliers -
                                           bound_multipliers.cwiseQuotient(slack).cwiseProduct(dx);
      double dual_length = 1.0;
      for (Eigen::Index i = 0; i < x.size(); ++i)
        if (bound_change[i] < 0.0)
          dual_length =
              std::min(dual_length, kLowerMargin * bound_multipliers[i] / -bound_change[i]);
      bound_multipliers += dual_length * bound_change;
      const Eigen::ArrayXd central = kBarrierWeight / (x - lower_bounds).array();
      bound_multipliers = bound_multipliers.array()
                              .max(central / kBoundMultiplierBand)
                              .min(central * kBoundMultiplierBand)
                              .matrix();
    }
    const Eigen::VectorXd multipliers_next = multipliers + length * multiplier_change;
    if (!settings.underdetermined) {
      // An angle whose full step would have crossed the fraction-to-the-bound margin is pressed
      // against its bound. Its multiplier z must grow from about mu / (x - l) to the force
      // pressing it there before Newton stops pushing it, and the primal-dual update above only
      // multiplies z by a modest factor per step (one step per decade, from 1e-8). Stationarity
      // of the Lagrangian with the bound, grad L = z, gives that force directly: z is raised to
      // it (a multiplier estimate; z stays positive, and the next steps refine it as usual).
      const Eigen::VectorXd pressing_force =
          2.0 * weights.cwiseProduct(x - targets) +
          Eigen::VectorXd(constraints.jacobian.transpose() * multipliers_next);
      for (Eigen::Index i = 0; i < x.size(); ++i)
        if (dx[i] < 0.0 && kLowerMargin * slack[i] < -dx[i])
          bound_multipliers[i] = std::max(bound_multipliers[i], pressing_force[i]);
    }
    equality_multipliers = multipliers_next.head(equality_rows);
    boundary_multipliers.setZero();  // Inactive rows have no multiplier.
    for (std::size_t k = 0; k < active_positions.size(); ++k)
      boundary_multipliers[active_positions[k]] =
          multipliers_next[equality_rows + static_cast<Eigen::Index>(k)];
    result.steps = step + 1;
  }
}

}  // namespace harmonia::detail
