// Linear angle based flattening (thesis chapter 3). Around an estimate alpha of the planar angles,
// the angle constraints are linear in the error e = alpha* - alpha up to terms quadratic in e
// (3.2, 3.3, 3.7): A e = b with A = J(alpha), the Jacobian of the constraints in their log-sine
// form, and b = -h(alpha). The error of least weighted norm, min sum (e / alpha)^2 (3.9), is
// e = W A^T (A W A^T)^-1 b with W = diag(alpha^2) (3.12-3.13, with C = A D_alpha): one
// saddle-point solve, done with the triangle rows eliminated (detail/reduced_angle_system.h).
// The angles alpha + e become UVs through angles_to_uv().

#include "harmonia/linear_abf.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "detail/angle_constraints.h"
#include "detail/linear_abf_estimate.h"
#include "detail/map_pipeline.h"
#include "detail/reduced_angle_system.h"

namespace harmonia {
namespace {

constexpr double kAcceptedSolveResidual = 1e-8;

// Corner vector (3F) <-> the #F x 3 layout of AngleMapResult::angles.
Eigen::MatrixX3d as_face_rows(const Eigen::VectorXd& corners) {
  Eigen::MatrixX3d rows(corners.size() / 3, 3);
  for (Eigen::Index f = 0; f < rows.rows(); ++f)
    rows.row(f) << corners[3 * f], corners[3 * f + 1], corners[3 * f + 2];
  return rows;
}

// The first corner whose angle lies outside (0, pi) or is not finite, or -1.
int first_invalid_corner(const Eigen::VectorXd& angles) {
  for (Eigen::Index c = 0; c < angles.size(); ++c)
    if (!(angles[c] > 0.0 && angles[c] < std::numbers::pi)) return static_cast<int>(c);
  return -1;
}

bool reject(SolveReport& report, const std::string& message) {
  report.status = Status::invalid_input;
  report.message = "linear_abf: " + message;
  return false;
}

bool validate_options(const LinearAbfOptions& options, SolveReport& report) {
  if (options.rounds < 0)
    return reject(report, "rounds must be 0 (automatic) or positive, got " +
                              std::to_string(options.rounds));
  if (!(options.exponential_map_deficit >= 0.0))
    return reject(report, "exponential_map_deficit must be a non-negative number");
  return true;
}

// The ABF objective (2.8) of `angles` against `targets` (zero targets carry no weight, as in
// abf_energy()).
double objective(const Eigen::VectorXd& angles, const Eigen::VectorXd& targets) {
  double energy = 0.0;
  for (Eigen::Index c = 0; c < angles.size(); ++c) {
    if (!(targets[c] > 0.0)) continue;
    const double relative = (angles[c] - targets[c]) / targets[c];
    energy += relative * relative;
  }
  return energy;
}

}  // namespace

AngleMapResult linear_abf(const Mesh& mesh, const LinearAbfOptions& options) {
  AngleMapResult result;
  SolveReport& report = result.report;
  const ProgressCallback& progress = options.solver_options.progress;
  detail::PhaseClock clock(report, progress);
  if (!clock.start("validation")) return result;
  if (!validate_options(options, report)) return result;
  const std::vector<int> loop = detail::validate_disk_input(mesh, report);
  if (!report.ok()) return result;
  const std::unique_ptr<detail::Backend> backend =
      detail::choose_backend(options.solver_options, report);
  if (!backend) return result;

  if (!clock.start("estimate")) return result;
  const detail::AngleTopology topology = detail::build_angle_topology(mesh, loop);
  const Eigen::VectorXd spatial = detail::corner_angles(mesh);
  Eigen::VectorXd estimate =
      detail::linear_abf_estimate(mesh, topology, spatial, options.exponential_map_deficit);

  detail::IterativeSettings settings;
  settings.relative_tolerance = options.solver_options.tolerance;
  settings.max_iterations = options.solver_options.max_iterations;
  // Created per round and released before the reconstruction, which needs memory of the same
  // order for its own factorization.
  std::unique_ptr<detail::ReducedAngleSystem> system;
  const int max_rounds = options.rounds > 0 ? options.rounds : 2;
  Eigen::VectorXd angles;
  MapResult layout;
  AnglesToUvOptions reconstruction = options.reconstruction;
  reconstruction.solver = options.solver_options;
  for (int round = 0; round < max_rounds; ++round) {
    if (!clock.start("assembly", round, max_rounds)) return result;
    // Linearized constraints at the estimate (3.2, 3.3, 3.7): A = J(alpha), b = -h(alpha).
    const detail::AngleConstraints constraints =
        detail::evaluate_angle_constraints(topology, estimate);
    // Each round is the thesis' least-norm problem around its own estimate (3.4.: "the angles
    // computed at one iteration are constrained in [0, pi] and define the alphas of the next").
    const Eigen::VectorXd weights = estimate.cwiseAbs2();  // W = D_alpha^2 (3.10)
    system = std::make_unique<detail::ReducedAngleSystem>(*backend, topology, settings, progress);
    system->assemble(constraints.jacobian, weights);
    if (!clock.start("factorization", round, max_rounds)) return result;
    detail::SolveStats stats = system->factorize();
    if (stats.status == Status::ok) {
      if (!clock.start("solve", round, max_rounds)) return result;
      Eigen::VectorXd error, multipliers;
      stats = system->solve_assembled(Eigen::VectorXd::Zero(estimate.size()), -constraints.values,
                                     error, multipliers);  // e = W A^T (A W A^T)^-1 b (3.12)
      angles = estimate + error;  // (3.1)
    }
    report.rounds = round + 1;
    report.iterations += stats.iterations;
    report.residual = std::max(report.residual, stats.relative_residual);
    report.solver = system->solver_name();
    system.reset();
    // A device solve that stalled just above the requested tolerance (fp32 kernels refined in
    // double) is still far more accurate than the linearization itself (its error is quadratic
    // in e, 1e-3 and more on curved meshes): accepted, with the residual reached in the report.
    const bool accurate_enough = stats.status == Status::not_converged &&
                                 stats.relative_residual <= kAcceptedSolveResidual;
    if (stats.status != Status::ok && !accurate_enough) {
      report.status = stats.status;
      report.message = "linear_abf: round " + std::to_string(round + 1) + ": " + stats.message;
      report.cross_check_error = backend->cross_check_error();
      return result;
    }
    const bool valid_angles = first_invalid_corner(angles) < 0;
    if (valid_angles) {
      if (!clock.start("reconstruction", round, max_rounds)) return result;
      layout = angles_to_uv(mesh, as_face_rows(angles), reconstruction);
    }
    const bool last = round + 1 == max_rounds;
    // Automatic mode: a second round only when the first is not a valid map.
    const bool good = valid_angles && layout.report.ok();
    if (last || (options.rounds == 0 && good)) break;
    estimate = detail::clamp_angles(angles);  // The next round's estimate.
  }

  const int invalid = first_invalid_corner(angles);
  if (invalid >= 0) {
    // Still invalid after the last round: lay out the angles clamped into (0, pi), and say so.
    angles = detail::clamp_angles(angles);
    if (!clock.start("reconstruction")) return result;
    layout = angles_to_uv(mesh, as_face_rows(angles), reconstruction);
  }
  clock.stop();
  report.constraint_residual =
      detail::constraint_violation(detail::evaluate_angle_constraints(topology, angles));
  report.cross_check_error = std::max(backend->cross_check_error(),
                                      layout.report.cross_check_error);
  result.angles = as_face_rows(angles);
  result.abf_energy = objective(angles, detail::rescaled_angles(topology, spatial));
  result.uv = std::move(layout.uv);
  report.flipped_triangles = layout.report.flipped_triangles;
  report.degenerate_triangles = layout.report.degenerate_triangles;
  report.boundary_self_intersections = layout.report.boundary_self_intersections;
  report.residual = std::max(report.residual, layout.report.residual);
  if (!layout.report.ok()) {
    report.status = layout.report.status;
    report.message = "linear_abf: " + layout.report.message;
  }
  if (invalid >= 0) {
    const std::string note = "after " + std::to_string(report.rounds) +
                             " round(s) the angle of face " + std::to_string(invalid / 3) +
                             " corner " + std::to_string(invalid % 3) +
                             " lay outside (0, pi); the layout uses the angles clamped into it "
                             "(more rounds, LinearAbfOptions::rounds, or abf() may help)";
    // Only a failed map carries the note (the message of an ok report stays empty).
    if (!report.ok()) report.message += "; " + note;
  }
  return result;
}

}  // namespace harmonia
