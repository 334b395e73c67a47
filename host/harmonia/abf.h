#pragma once
//! \file abf.h
//! \brief Angle based flattening (thesis chapter 2): the planar corner angles closest to the 3D
//! ones under the angle validity constraints, found by Newton/Lagrange iterations; then UVs.
//!
//! Unknowns: the 3F corner angles x. Objective (2.8): sum w (x - a)^2 with w = 1/a^2, a = the 3D
//! angles rescaled to sum 2 pi around interior vertices (kept at boundary vertices).
//! Constraints: triangle (2.2), vertex (2.1), wheel in log-sine form (2.11) -- which makes the
//! Hessian of the Lagrangian diagonal -- and the boundary inequality (2.6), sum of the angles at a
//! boundary vertex <= t pi, handled by an active set. Every angle is also kept above 1 % of its
//! target by a logarithmic barrier (weight 1e-10, far below every tolerance where no angle comes
//! near its bound): on meshes whose cut leaves long protrusions closed, the objective's infimum
//! has zero angles, and the bound gives Newton a minimum to converge to.

#include <Eigen/Core>

#include "harmonia/angles_to_uv.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"
#include "harmonia/types.h"

namespace harmonia {

//! The linear solver of every Newton step (section 2.4).
enum class AbfSolver {
  //! Best available: the reduced system of ABF++ (triangle rows eliminated face by face), factorized
  //! by CHOLMOD on the CPU and solved by PCG on devices.
  automatic,
  //! Decoupled system M lambda = B A^-1 f - g, M = B A^-1 B^T (2.12-2.13), solved by MINRES.
  schur_minres,
  //! Modified Uzawa iterations with conjugate directions on the saddle-point system.
  uzawa,
  //! MINRES on the full symmetric indefinite system (2.10).
  full_minres,
  //! CGNR (conjugate gradients on the normal equations S^2) on the full system (2.10).
  full_cgnr,
  //! Direct sparse factorization of M (CPU backend only; Status::unsupported elsewhere).
  schur_direct,
};

struct AbfOptions {
  //! Boundary control coefficient t of (2.6): sum of a boundary vertex's angles <= t pi.
  //! t >= 2: classic ABF; t = 1: convex boundary (no boundary self-intersection for any valid
  //! input); 1 - 2/n < t < 1: concave boundary (n boundary vertices). t <= 1 - 2/n is rejected
  //! (Status::invalid_input naming the bound).
  double boundary_t = 2.0;
  //! When the result's boundary crosses itself (possible for t > 1 on boundary-heavy meshes,
  //! thesis 2.2), solve again with a smaller t (continuation from the current angles: 1.5, 1.25,
  //! 1) until it does not; t = 1 guarantees it. AngleMapResult::boundary_t says which t was used.
  bool avoid_boundary_crossings = true;
  AbfSolver solver = AbfSolver::automatic;
  //! Section 2.4.3: objective zero, i.e. just a feasible point close to the start angles.
  bool underdetermined = false;
  int max_newton_iterations = 100;
  //! Stop when the largest constraint violation is below this (radians / log-sine units) ...
  double constraint_tolerance = 1e-10;
  //! ... and the gradient of the Lagrangian, relative to that of the objective at the start, too.
  double gradient_tolerance = 1e-8;
  AnglesToUvOptions reconstruction;  //!< How angles become UVs; its `solver` is ignored.
  //! Backend, progress (one step per Newton iteration), tolerances of the inner linear solves.
  SolverOptions solver_options;
};

//! Result of the angle-based methods: UVs plus the planar angles they came from.
struct AngleMapResult {
  Eigen::MatrixX2d uv;      //!< #V by 2 (see MapResult::uv).
  Eigen::MatrixX3d angles;  //!< #F by 3 planar angles, angles(f, k) at vertex faces(f, k).
  //! The ABF objective (2.8) of `angles` against the ABF target angles a (same for ABF and
  //! linear ABF, so they compare).
  double abf_energy = 0.0;
  //! The boundary control coefficient in effect for the result (AbfOptions::boundary_t, or the
  //! smaller one avoid_boundary_crossings moved to); 0 when no boundary rows were used at all
  //! (linear ABF without crossings).
  double boundary_t = 0.0;
  SolveReport report;  //!< rounds = Newton steps; constraint_residual = final violation.
};

//! Nonlinear ABF of a disk mesh (non-disks: Status::not_a_disk pointing at `harmonia cut`).
[[nodiscard]] AngleMapResult abf(const Mesh& mesh, const AbfOptions& options = {});

//! The ABF target angles a (#F x 3): 3D angles rescaled to 2 pi around interior vertices.
[[nodiscard]] Eigen::MatrixX3d abf_target_angles(const Mesh& mesh);

//! The ABF objective (2.8) of `angles` (#F x 3) against abf_target_angles(mesh).
[[nodiscard]] double abf_energy(const Mesh& mesh, const Eigen::MatrixX3d& angles);

}  // namespace harmonia
