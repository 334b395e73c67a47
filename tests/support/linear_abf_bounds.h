#pragma once
// The bound within which two solutions of linear ABF's first round agree in their angles when
// their reduced systems were solved to different residuals (the batched block PCG against
// linear_abf()'s direct solve, or a device's against the CPU's): shared by
// tests/abf/test_linear_abf_batch.cpp and tests/kernels/test_vulkan_linear_abf_batch.cpp.

#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "abf/angle_constraints.h"
#include "abf/linear_abf_estimate.h"
#include "abf/linear_abf_round.h"
#include "abf/reduced_angle_system.h"
#include "fallback/cpu_backend.h"
#include "harmonia/mesh.h"
#include "harmonia/topology.h"
#include "mesh/power_of_two_scale.h"
#include "support/conditioning.h"

namespace harmonia::testing {

//! The reduced system A nu = b of a mesh's first round, as linear ABF assembles it.
struct ReducedSystem {
  Eigen::SparseMatrix<double> matrix;
  Eigen::VectorXd rhs;
};

inline ReducedSystem first_round_system(const Mesh& input) {
  const detail::ScaledMesh unit = detail::unit_scaled(input);
  const Mesh& mesh = unit.mesh;
  const detail::AngleTopology topology =
      detail::build_angle_topology(mesh, boundary_loops(mesh).at(0));
  const Eigen::VectorXd estimate =
      detail::linear_abf_estimate(mesh, topology, detail::corner_angles(mesh), 1.0);
  const detail::LinearizedRound round = detail::linearize_round(topology, estimate, estimate);
  detail::CpuBackend cpu;
  detail::ReducedAngleSystem system(cpu, topology, {}, nullptr);
  system.assemble(round.constraints.jacobian, round.weights);
  return {Eigen::SparseMatrix<double>(system.reduced_matrix()),
          system.reduced_right_hand_side(round.pull, -round.constraints.values)};
}

//! How far two solutions of one mesh's first round may lie apart in their angles (2-norm over the
// corners), when one solved the reduced system A nu = b (A = B' B'^T, B' = R Q) by PCG to a
// relative residual `pcg_residual` and the other directly (CHOLMOD). For two PCG solutions, pass
// the sum of their residuals.
//
// The back-substitution gives dx_f = P_f (r_f - (R^T nu)_f) + a term without nu, with
// P_f = Q_f Q_f^T (reduced_angle_system.cpp), so two multipliers nu, nu' = nu + d give angles
// apart by |Q Q^T R^T d| <= max_f |Q_f| |B'^T d|, and
//   |B'^T d|^2 = d^T A d = (A d)^T A^-1 (A d) <= |A d|^2 / lambda_min(A),
// where A d is the difference of the two residuals b - A nu. |Q_f|^2 = lambda_max(P_f) <=
// max W_f = max alpha^2 <= pi^2. So the angles differ by at most
//   pi (|res| + |res'|) / sqrt(lambda_min(A)),
// with |res| <= pcg_residual |b| (the PCG's stopping test, itself computed in double: plus the
// rounding of a residual, residual_rounding) and the direct solve's residual at the rounding
// level of that product too (a backward-stable Cholesky; a factor 8 for its triangular solves).
// lambda_min is estimated from above (SpdSpectrum::kEstimateMargin). Each angle then adds the
// rounding of the back-substitution and of alpha + e, a few eps pi.
inline double first_round_angle_bound(const Mesh& mesh, double pcg_residual) {
  const ReducedSystem system = first_round_system(mesh);
  constexpr double eps = std::numeric_limits<double>::epsilon();
  constexpr double kPi = std::numbers::pi;
  const double roundoff = 16 * eps * kPi * std::sqrt(3.0 * static_cast<double>(mesh.faces.rows()));
  if (system.rhs.size() == 0 || system.rhs.norm() == 0.0) return roundoff;
  const SpdSpectrum spectrum = spd_spectrum(system.matrix);
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(system.matrix);
  const Eigen::MatrixXd nu = factor.solve(system.rhs);
  const double rounding = residual_rounding(system.matrix, nu, system.rhs);
  const double residuals = (pcg_residual + rounding) + 8 * rounding;
  return kPi * residuals * system.rhs.norm() /
             std::sqrt(spectrum.smallest / SpdSpectrum::kEstimateMargin) +
         roundoff;
}

}  // namespace harmonia::testing
