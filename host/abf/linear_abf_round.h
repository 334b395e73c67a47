#pragma once
// Internal: the pieces of one linear ABF round (thesis chapter 3) that linear_abf() and the batched
// first round (abf/linear_abf_batch.h) share, so that both linearize, accept a solve and finish a
// result the same way: the linearized problem of a round, the acceptance of its solve, the angles'
// summary and the finished AngleMapResult.

#include <vector>

#include <Eigen/Core>

#include "abf/angle_constraints.h"
#include "backend/backend.h"
#include "harmonia/linear_abf.h"
#include "harmonia/map_result.h"

namespace harmonia::detail {

//! A device solve that stalled just above the requested tolerance (fp32 kernels refined in
//! double) is still far more accurate than the linearization itself (its error is quadratic in
//! e, 1e-3 and more on curved meshes): accepted up to this relative residual.
inline constexpr double kLinearAbfAcceptedSolveResidual = 1e-8;

//! Whether a round's solve is good enough to use: ok, or not converged within
//! kLinearAbfAcceptedSolveResidual.
[[nodiscard]] bool linear_abf_solve_accepted(Status status, double relative_residual);

//! Checks LinearAbfOptions (rounds, exponential_map_deficit); false with invalid_input in
//! `report` when they are not usable.
[[nodiscard]] bool validate_linear_abf_options(const LinearAbfOptions& options,
                                               SolveReport& report);

//! Corner vector (3F) -> the #F x 3 layout of AngleMapResult::angles.
[[nodiscard]] Eigen::MatrixX3d corner_rows(const Eigen::VectorXd& corners);

//! The first corner whose angle lies outside (0, pi) or is not finite, or -1.
[[nodiscard]] int first_invalid_corner(const Eigen::VectorXd& angles);

//! One round's least-norm problem around `estimate` (ReducedAngleSystem's notation): the
//! linearized constraints at the estimate (3.2, 3.3, 3.7), A = J(alpha), b = -h(alpha), with the
//! boundary rows (2.6) of `boundary_rows` at `boundary_t` (a boundary row reads sum of the errors
//! = t pi - sum of the angles), and the objective sum ((estimate + e - centre) / centre)^2:
//! W = D_centre^2 (3.10) and r = W^-1 (centre - estimate), the pull back to the centre (0 when
//! the centre is the estimate, the thesis' problem (3.9)). The error is then
//! e = W (r - A^T x) with (A W A^T) x = A W r - b.
struct LinearizedRound {
  AngleConstraints constraints;
  Eigen::VectorXd weights;  // W
  Eigen::VectorXd pull;     // r
};
[[nodiscard]] LinearizedRound linearize_round(const AngleTopology& topology,
                                              const Eigen::VectorXd& estimate,
                                              const Eigen::VectorXd& centre,
                                              const std::vector<int>& boundary_rows = {},
                                              double boundary_t = 2.0);

//! What the report says of the final angles: the largest violation of the exact constraints and
//! the ABF objective (2.8) against the ABF target angles of the 3D corner angles `spatial`.
struct LinearAbfAngleSummary {
  double constraint_residual = 0.0;
  double abf_energy = 0.0;
};
[[nodiscard]] LinearAbfAngleSummary summarize_linear_abf_angles(const AngleTopology& topology,
                                                                const Eigen::VectorXd& spatial,
                                                                const Eigen::VectorXd& angles);

//! Finishes `result` from the final angles (3F) and their layout: angles, UVs (in the unit-scaled
//! mesh's units), energy, constraint residual, the layout's counts and residual, the largest
//! cross-check error, and the layout's status and message. `invalid`: the corner that lay outside
//! (0, pi) before the angles were clamped (a note says so), or -1.
void finish_linear_abf_result(const Eigen::VectorXd& angles, MapResult layout,
                              const LinearAbfAngleSummary& summary, int invalid,
                              double backend_cross_check_error, AngleMapResult& result);

}  // namespace harmonia::detail
