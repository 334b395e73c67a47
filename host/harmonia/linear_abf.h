#pragma once
//! \file linear_abf.h
//! \brief Linear angle based flattening (thesis chapter 3): the angle constraints linearized in
//! the angle error e around an initial estimate alpha and solved as one weighted least-norm
//! problem, min sum (e/alpha)^2 subject to A e = b (3.9), through the normal equations
//! (C C^T) x = b with C = A D_alpha (3.13); then UVs.

#include "harmonia/abf.h"

namespace harmonia {

struct LinearAbfOptions {
  //! Rounds of linearization. 0 (default): one round when it gives a valid map; when it leaves
  //! angles outside (0, pi) or flipped triangles, further rounds (at most 8 in all) until the
  //! angles are a valid map that meets the exact constraints within 1e-6 (each round after valid
  //! angles is a Newton projection onto them). n > 0: exactly n rounds, each
  //! linearized at the previous result clamped into (0, pi); a round after one that left angles
  //! outside (0, pi) keeps the first round's objective, the distance to the initial estimate,
  //! instead of measuring the distance to the clamped angles. Either way, the boundary rounds of
  //! avoid_boundary_crossings come on top when the boundary crosses itself (report.rounds counts
  //! them all).
  int rounds = 0;
  //! Initial estimate (3.2.2): the 3D angles, but the rescaled (exponential map) angles around an
  //! interior vertex whose angular deficit |2 pi - sum| exceeds this.
  double exponential_map_deficit = 1.0;
  //! When the result's boundary crosses itself, further rounds add the linearized boundary
  //! condition (2.6), sum of the angle errors at a boundary vertex <= t pi - sum of its angles,
  //! at the vertices that exceed it, for t = 1.5, then 1.25, then 1, until the boundary is
  //! simple (t = 1: convex). AngleMapResult::boundary_t says which t was used.
  bool avoid_boundary_crossings = true;
  AnglesToUvOptions reconstruction;  //!< How angles become UVs; its `solver` is ignored.
  SolverOptions solver_options;      //!< Backend (CPU: direct factorization; Vulkan: PCG).
};

//! Linear ABF of a disk mesh. report.rounds = linearization rounds done;
//! report.constraint_residual = the largest violation of the exact (nonlinear) constraints.
[[nodiscard]] AngleMapResult linear_abf(const Mesh& mesh, const LinearAbfOptions& options = {});

}  // namespace harmonia
