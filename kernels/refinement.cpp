#include "kernels/refinement.h"
#include "mesh/number_text.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace harmonia::vulkan::detail {
namespace {

// A safety net only: with the gain test each round at least halves the residual.
constexpr int maximum_rounds = 60;

}  // namespace

harmonia::detail::SolveStats refine_in_double(const VulkanMatrix& a, const VulkanVectors& b,
                                              VulkanVectors& x, VulkanVectors& residual,
                                              VulkanVectors& correction,
                                              const harmonia::detail::IterativeSettings& settings,
                                              const char* method,
                                              const CorrectionSolver& solve_correction) {
  harmonia::detail::SolveStats stats;
  const Eigen::MatrixXd rhs = b.download();
  Eigen::MatrixXd solution = x.download();
  const Eigen::VectorXd b_norms = rhs.colwise().norm().transpose();
  for (Eigen::Index c = 0; c < rhs.cols(); ++c)
    if (b_norms[c] == 0.0) solution.col(c).setZero();  // Its solution is exactly zero.
  const double tolerance = settings.relative_tolerance;
  // fp64 kernels reach the final tolerance themselves: one round, its residual checked in double.
  const double correction_floor =
      a.precision() == DevicePrecision::float64 ? 0.0 : correction_relative_tolerance;

  double previous = std::numeric_limits<double>::infinity();
  for (int round = 0;; ++round) {
    const Eigen::MatrixXd r = rhs - a.host() * solution;
    const Eigen::VectorXd r_norms = r.colwise().norm().transpose();
    double worst = 0.0;
    for (Eigen::Index c = 0; c < r.cols(); ++c) {
      const double relative = b_norms[c] > 0.0 ? r_norms[c] / b_norms[c] : r_norms[c];
      worst = std::max(
          worst, std::isfinite(relative) ? relative : std::numeric_limits<double>::infinity());
    }
    stats.relative_residual = worst;
    if (!std::isfinite(worst) || worst <= tolerance) break;
    if (round > 0 && worst > refinement_minimum_gain * previous) break;  // No longer gaining.
    if (stats.iterations >= settings.max_iterations || round == maximum_rounds) break;
    previous = worst;

    Eigen::VectorXd tolerances = Eigen::VectorXd::Ones(r.cols());  // 1: nothing to do.
    for (Eigen::Index c = 0; c < r.cols(); ++c) {
      if (b_norms[c] > 0.0 && r_norms[c] > tolerance * b_norms[c])
        tolerances[c] = std::max(tolerance * b_norms[c] / r_norms[c], correction_floor);
    }
    // The correction equation is solved for each residual column scaled to unit norm: a residual
    // of 1e-20 would underflow fp32 (its squares in the dot products are below fp32's range), and
    // the scaling leaves the relative tolerance unchanged.
    Eigen::VectorXd column_scale = r_norms;
    for (Eigen::Index c = 0; c < r.cols(); ++c)
      if (!(column_scale[c] > 0.0)) column_scale[c] = 1.0;
    residual.upload(r * column_scale.cwiseInverse().asDiagonal());
    correction.upload(Eigen::MatrixXd::Zero(r.rows(), r.cols()));
    const harmonia::detail::SolveStats inner =
        solve_correction(residual, correction, tolerances,
                         settings.max_iterations - stats.iterations, stats.iterations);
    stats.iterations += inner.iterations;
    if (inner.status == Status::cancelled || inner.status == Status::numerical_failure) {
      stats.status = inner.status;
      stats.message = inner.message;
      break;
    }
    solution += correction.download() * column_scale.asDiagonal();
  }
  x.set_refined(solution);
  if (stats.status != Status::ok) return stats;
  const std::string name =
      std::string(method) + (a.precision() == DevicePrecision::float64
                                 ? " (fp64 on the device)"
                                 : " (fp32 on the device, refined in double)");
  if (!std::isfinite(stats.relative_residual)) {
    stats.status = Status::numerical_failure;
    stats.message = name + ": the residual is not finite";
  } else if (stats.relative_residual > tolerance) {
    stats.status = Status::not_converged;
    stats.message = name + " stopped after " + std::to_string(stats.iterations) +
                    " iterations at relative residual " + harmonia::detail::scientific_text(stats.relative_residual) +
                    " (tolerance " + harmonia::detail::scientific_text(tolerance) + ")";
  }
  return stats;
}

}  // namespace harmonia::vulkan::detail
