#pragma once
// Internal: the initial angle estimate of linear ABF (thesis section 3.2.2).

#include <Eigen/Core>

#include "abf/angle_constraints.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

//! Estimates are kept this far (radians) from 0 and pi: the weights alpha^2 of (3.8) must not
//! vanish, and cot of the wheel rows must stay finite.
inline constexpr double kLinearAbfAngleMargin = 1e-3;

//! The 3D corner angles `angles` (3F), except around interior vertices whose angular deficit
//! |2 pi - sum| exceeds `exponential_map_deficit`: there the vertex ring is replaced by its
//! exponential map (central angles rescaled to sum 2 pi, spoke lengths kept), which also gives the
//! two other angles of each ring triangle. A face on several such rings takes the rescaled central
//! angles and keeps its other 3D angles (the linear solve restores its angle sum). Finally every
//! angle is clamped into [margin, pi - margin]. `switched` (optional) receives the number of
//! rings replaced.
[[nodiscard]] Eigen::VectorXd linear_abf_estimate(const Mesh& mesh, const AngleTopology& topology,
                                                  const Eigen::VectorXd& angles,
                                                  double exponential_map_deficit,
                                                  int* switched = nullptr);

//! `angles` clamped into [margin, pi - margin] (the next round's estimate).
[[nodiscard]] Eigen::VectorXd clamp_angles(const Eigen::VectorXd& angles);

}  // namespace harmonia::detail
