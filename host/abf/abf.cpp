// Nonlinear angle based flattening (thesis chapter 2): validation, the ABF target angles, the
// Newton/Lagrange iteration with the boundary control (2.6) (abf/abf_newton.h) and one of the
// step solvers of section 2.4 (abf/abf_step_solvers.h), then UVs from the angles
// (angles_to_uv) with the validity counts of every map.

#include "harmonia/abf.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "abf/abf_newton.h"
#include "abf/abf_step_solvers.h"
#include "abf/angle_constraints.h"
#include "abf/validated_angles_to_uv.h"
#include "mesh/power_of_two_scale.h"
#include "planar/map_pipeline.h"

namespace harmonia {
namespace {

bool fail(SolveReport& report, Status status, std::string message) {
  report.status = status;
  report.message = std::move(message);
  return false;
}

// The options that do not depend on the mesh, and t against the lower bound t0 = 1 - 2/n of
// (2.7): below it the boundary angle sums cannot add up to pi (n - 2).
bool validate_options(const AbfOptions& options, int boundary_count, SolveReport& report) {
  if (!(options.constraint_tolerance > 0.0) || !std::isfinite(options.constraint_tolerance))
    return fail(report, Status::invalid_input, "abf: constraint_tolerance must be positive");
  if (!(options.gradient_tolerance > 0.0) || !std::isfinite(options.gradient_tolerance))
    return fail(report, Status::invalid_input, "abf: gradient_tolerance must be positive");
  if (options.max_newton_iterations < 1)
    return fail(report, Status::invalid_input, "abf: max_newton_iterations must be at least 1");
  const double lower_bound = 1.0 - 2.0 / boundary_count;
  if (!std::isfinite(options.boundary_t) || options.boundary_t <= lower_bound) {
    char text[240];
    std::snprintf(text, sizeof text,
                  "abf: boundary_t = %.6g must be greater than the lower bound 1 - 2/n = %.6g "
                  "(n = %d boundary vertices; thesis (2.6)-(2.7))",
                  options.boundary_t, lower_bound, boundary_count);
    return fail(report, Status::invalid_input, text);
  }
  return true;
}

Eigen::MatrixX3d angles_per_face(const Eigen::VectorXd& corners, int face_count) {
  Eigen::MatrixX3d angles(face_count, 3);
  for (int f = 0; f < face_count; ++f)
    for (int k = 0; k < 3; ++k) angles(f, k) = corners[3 * f + k];
  return angles;
}

// The largest decrease of t between two warm-started Newton solves of a continuation.
constexpr double kContinuationStep = 0.25;
// A stage that does not converge is retried with half the decrease, down to this one.
constexpr double kSmallestContinuationStep = 1.0 / 64.0;

// The ladder of boundary controls tried when a layout's boundary crosses itself (2.6): the next
// one below `t`, or 0 when t = 1 (convex: no crossing is possible) has been reached.
double next_boundary_t(double t) {
  for (const double rung : {1.5, 1.25, 1.0})
    if (rung < t) return rung;
  return 0.0;
}

// ABF of a mesh already scaled to unit size (abf() below scales it).
AngleMapResult abf_at_unit_size(const Mesh& mesh, const AbfOptions& options) {
  AngleMapResult result;
  SolveReport& report = result.report;
  const SolverOptions& solver_options = options.solver_options;
  detail::PhaseClock clock(report, solver_options.progress);
  if (!clock.start("validation")) return result;
  const std::vector<int> loop = detail::validate_disk_input(mesh, report);
  if (!report.ok()) return result;
  if (!validate_options(options, static_cast<int>(loop.size()), report)) return result;
  const auto backend = detail::choose_backend(solver_options, report);
  if (!backend) return result;

  if (!clock.start("setup")) return result;
  const detail::AngleTopology topology = detail::build_angle_topology(mesh, loop);
  const Eigen::VectorXd targets =
      detail::rescaled_angles(topology, detail::corner_angles(mesh));
  detail::IterativeSettings settings;
  settings.relative_tolerance = solver_options.tolerance;
  settings.max_iterations = solver_options.max_iterations;
  std::string error;
  // With a direct factorization, one nested dissection ordering of the vertices serves the
  // reduced system of every Newton step and the reconstruction: it costs about two AMD
  // factorizations' time once and saves about a third of every factorization (2 x 2 blocks).
  const std::vector<int> vertex_ordering =
      backend->supports(detail::Feature::direct_factorization)
          ? detail::operator_pattern(mesh, true).vertex_ordering
          : std::vector<int>{};
  const auto step_solver =
      detail::make_abf_step_solver(options.solver, *backend, topology, settings,
                                   solver_options.progress, &error, vertex_ordering,
                                   solver_options.backend == BackendChoice::automatic);
  if (!step_solver) {
    fail(report, Status::unsupported, error);
    return result;
  }
  report.solver = step_solver->name();

  if (!clock.start("newton")) return result;
  detail::AbfNewtonSettings newton;
  newton.underdetermined = options.underdetermined;
  newton.max_iterations = options.max_newton_iterations;
  newton.constraint_tolerance = options.constraint_tolerance;
  newton.gradient_tolerance = options.gradient_tolerance;
  detail::AbfNewtonResult angles;
  // Continuation from the current solution (or from classic ABF, t = 2, when there is none) down
  // to `t`, at most kContinuationStep at a time, each Newton solve warm-started from the last
  // angles and multipliers. A direct solve at a small t starts with most boundary rows badly
  // violated, and the step control then shortens the steps until Newton stalls (measured at
  // t = 1 on boundary-heavy meshes); each small decrease of t starts close to its solution.
  // Stages before the last need not converge fully: they only provide the next start.
  double solved_t = 0.0;  // 0: nothing solved yet.
  int steps = 0;
  const auto solve_down_to = [&](double t) {
    // The last converged state: a stage that fails is retried from it with half the decrease.
    detail::AbfNewtonResult converged = angles;
    double converged_t = solved_t;
    double decrease = kContinuationStep;
    for (;;) {
      const double stage_t =
          converged_t > 0.0 ? std::max(t, converged_t - decrease) : std::max(t, 2.0);
      newton.boundary_t = stage_t;
      newton.start = converged.angles;
      newton.start_equality_multipliers = converged.equality_multipliers;
      newton.start_boundary_multipliers = converged.boundary_multipliers;
      angles = detail::solve_abf_angles(topology, targets, newton, *step_solver,
                                        solver_options.progress);
      steps += angles.steps;
      report.iterations += angles.inner_iterations;
      if (std::string notice = step_solver->take_cpu_retry_notice(); !notice.empty())
        report.fallbacks.push_back(notice);
      report.residual = std::max(report.residual, angles.inner_residual);
      solved_t = stage_t;
      if (angles.status == Status::ok) {
        converged = angles;
        converged_t = stage_t;
        if (stage_t <= t) return;
        continue;
      }
      const bool retry = angles.status != Status::cancelled && converged_t > 0.0 &&
                         decrease > kSmallestContinuationStep;
      if (!retry) return;
      decrease /= 2.0;
    }
  };
  const auto lay_out = [&]() {
    result.angles = angles_per_face(angles.angles, mesh.face_count());
    AnglesToUvOptions reconstruction = options.reconstruction;
    reconstruction.solver = solver_options;
    // The Newton iterate's angles are finite and inside (0, pi) by the step control.
    return detail::angles_to_uv_validated(mesh, result.angles, reconstruction,
                                          {loop, vertex_ordering});
  };

  solve_down_to(options.boundary_t);
  MapResult map;
  for (;;) {
    clock.stop();
    report.solver = step_solver->name();  // The reduced system names its solver once it has one.
    report.rounds = steps;
    report.constraint_residual = angles.constraint_residual;
    report.cross_check_error = backend->cross_check_error();
    // Not converged: the angles are still the best iterate and become UVs (the status says so);
    // cancelled or failed steps end here.
    if (angles.status != Status::ok) {
      report.status = angles.status;
      report.message = angles.message;
      if (angles.status != Status::not_converged || angles.angles.size() == 0) return result;
    } else {
      report.status = Status::ok;
      report.message.clear();
    }
    if (!clock.start("angles to uv")) return result;
    map = lay_out();
    clock.stop();
    for (const PhaseTiming& timing : map.report.timings)
      report.timings.push_back({"uv " + timing.phase, timing.seconds});
    result.boundary_t = solved_t;
    // Boundary control (2.6) when the boundary crosses itself: the next smaller t of the ladder.
    if (!options.avoid_boundary_crossings || map.report.boundary_self_intersections == 0) break;
    const double next_t = next_boundary_t(solved_t);
    if (next_t <= 0.0) break;
    if (!clock.start("newton")) return result;
    solve_down_to(next_t);
  }
  result.abf_energy = abf_energy(mesh, result.angles);
  result.uv = std::move(map.uv);
  report.flipped_triangles = map.report.flipped_triangles;
  report.degenerate_triangles = map.report.degenerate_triangles;
  report.boundary_self_intersections = map.report.boundary_self_intersections;
  report.iterations += map.report.iterations;
  report.fallbacks.insert(report.fallbacks.end(), map.report.fallbacks.begin(), map.report.fallbacks.end());
  // A failed layout sets the status; a valid one may still carry a note (tiny triangles).
  if (report.ok() && !map.report.message.empty()) {
    report.status = map.report.status;
    report.message = "abf: " + map.report.message;
  }
  report.cross_check_error = backend->cross_check_error();
  return result;
}

}  // namespace

AngleMapResult abf(const Mesh& mesh, const AbfOptions& options) {
  // Computed on the mesh scaled to unit size (mesh/power_of_two_scale.h): its 3D angles, areas and
  // tolerances do not depend on the model's units; the layout comes back in them.
  const detail::ScaledMesh unit = detail::unit_scaled(mesh);
  AngleMapResult result = abf_at_unit_size(unit.mesh, options);
  detail::to_model_units(result.uv, unit.scale, options.reconstruction.normalization, true);
  return result;
}

}  // namespace harmonia
