#pragma once
// Internal: iterative refinement in double around an fp32 device solver (Wilkinson's classic
// mixed-precision scheme). Each round forms r = b - A x in double on the host, solves A d = r on
// the device in fp32 to a modest relative accuracy, and adds d to x in double. The true residual
// in double decides convergence, so the requested tolerance is reported honestly and can lie
// below fp32's reach (about 1e-6 relative). With fp64 kernels the same loop runs with no floor on
// the correction's tolerance: the first round solves to the requested tolerance and the double
// residual on the host only confirms it (or runs another round when the device stopped short).

#include <functional>

#include "backend/backend.h"
#include "kernels/device_arrays.h"

namespace harmonia::vulkan::detail {

// Relative accuracy asked of the fp32 correction solve in each round (when the final tolerance
// does not need less). The recursive fp32 residual reaches it; the true residual of a round
// typically stalls near u * cond(A) (3e-5 on an 11k-vertex corpus mesh), which the next round
// corrects. Measured on camelhead at tolerance 1e-10: 1e-6 -> 1241 iterations in 3 rounds, 1e-5
// -> 1254, 1e-4 -> 1392.
constexpr double correction_relative_tolerance = 1e-6;
// Refinement stops when a round fails to halve the residual (the fp32 solve no longer helps).
constexpr double refinement_minimum_gain = 0.5;

// Solves A d = r on the device: r and d are device blocks (d holds zeros on entry), column c to
// the relative tolerance tolerances[c], with at most max_iterations iterations, reporting
// progress from step progress_offset. Returns the iterations taken and the status.
using CorrectionSolver = std::function<harmonia::detail::SolveStats(
    const VulkanVectors& r, VulkanVectors& d, const Eigen::VectorXd& tolerances, int max_iterations,
    int progress_offset)>;

// Refines x (warm start on entry) until ||b - A x|| <= tolerance ||b|| per column in double.
// Columns with b = 0 get x = 0. `method` names the solver in messages ("pcg", "minres").
[[nodiscard]] harmonia::detail::SolveStats refine_in_double(
    const VulkanMatrix& a, const VulkanVectors& b, VulkanVectors& x, VulkanVectors& residual,
    VulkanVectors& correction, const harmonia::detail::IterativeSettings& settings,
    const char* method, const CorrectionSolver& solve_correction);

}  // namespace harmonia::vulkan::detail
