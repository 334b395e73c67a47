// The pieces of a linear ABF round shared by linear_abf() and the batched first round
// (abf/linear_abf_round.h).

#include "abf/linear_abf_round.h"

#include <algorithm>
#include <numbers>
#include <string>
#include <utility>

namespace harmonia::detail {
namespace {

bool reject(SolveReport& report, const std::string& message) {
  report.status = Status::invalid_input;
  report.message = "linear_abf: " + message;
  return false;
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

bool linear_abf_solve_accepted(Status status, double relative_residual) {
  return status == Status::ok ||
         (status == Status::not_converged && relative_residual <= kLinearAbfAcceptedSolveResidual);
}

bool validate_linear_abf_options(const LinearAbfOptions& options, SolveReport& report) {
  if (options.rounds < 0)
    return reject(report, "rounds must be 0 (automatic) or positive, got " +
                              std::to_string(options.rounds));
  if (!(options.exponential_map_deficit >= 0.0))
    return reject(report, "exponential_map_deficit must be a non-negative number");
  return true;
}

Eigen::MatrixX3d corner_rows(const Eigen::VectorXd& corners) {
  Eigen::MatrixX3d rows(corners.size() / 3, 3);
  for (Eigen::Index f = 0; f < rows.rows(); ++f)
    rows.row(f) << corners[3 * f], corners[3 * f + 1], corners[3 * f + 2];
  return rows;
}

int first_invalid_corner(const Eigen::VectorXd& angles) {
  for (Eigen::Index c = 0; c < angles.size(); ++c)
    if (!(angles[c] > 0.0 && angles[c] < std::numbers::pi)) return static_cast<int>(c);
  return -1;
}

LinearizedRound linearize_round(const AngleTopology& topology, const Eigen::VectorXd& estimate,
                                const Eigen::VectorXd& centre,
                                const std::vector<int>& boundary_rows, double boundary_t) {
  LinearizedRound round;
  round.constraints = evaluate_angle_constraints(topology, estimate, boundary_rows, boundary_t);
  round.weights = centre.cwiseAbs2();
  round.pull = (centre - estimate).cwiseQuotient(round.weights);
  return round;
}

LinearAbfAngleSummary summarize_linear_abf_angles(const AngleTopology& topology,
                                                  const Eigen::VectorXd& spatial,
                                                  const Eigen::VectorXd& angles) {
  return {angle_constraint_values(topology, angles).lpNorm<Eigen::Infinity>(),
          objective(angles, rescaled_angles(topology, spatial))};
}

void finish_linear_abf_result(const Eigen::VectorXd& angles, MapResult layout,
                              const LinearAbfAngleSummary& summary, int invalid,
                              double backend_cross_check_error, AngleMapResult& result) {
  SolveReport& report = result.report;
  report.constraint_residual = summary.constraint_residual;
  report.cross_check_error = std::max(backend_cross_check_error, layout.report.cross_check_error);
  result.angles = corner_rows(angles);
  result.abf_energy = summary.abf_energy;
  result.uv = std::move(layout.uv);
  report.flipped_triangles = layout.report.flipped_triangles;
  report.degenerate_triangles = layout.report.degenerate_triangles;
  report.boundary_self_intersections = layout.report.boundary_self_intersections;
  report.residual = std::max(report.residual, layout.report.residual);
  report.fallbacks.insert(report.fallbacks.end(), layout.report.fallbacks.begin(), layout.report.fallbacks.end());
  // A failed layout sets the status; a valid one may still carry a note (tiny triangles).
  if (!layout.report.message.empty()) {
    report.status = layout.report.status;
    report.message = "linear_abf: " + layout.report.message;
  }
  if (invalid >= 0) {
    const std::string note = "after " + std::to_string(report.rounds) +
                             " round(s) the angle of face " + std::to_string(invalid / 3) +
                             " corner " + std::to_string(invalid % 3) +
                             " lay outside (0, pi); the layout uses the angles clamped into it "
                             "(more rounds, LinearAbfOptions::rounds, or abf() may help)";
    report.message += (report.message.empty() ? "linear_abf: " : "; ") + note;
  }
}

}  // namespace harmonia::detail
