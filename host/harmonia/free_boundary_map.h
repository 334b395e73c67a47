#pragma once
//! \file free_boundary_map.h
//! \brief Free-boundary quasi-harmonic maps (thesis chapter 6): a planar map with no pinned
//! vertices from a few linear solves and no iteration.
//!
//!   P0  a fixed-boundary map on a circle (6.1): cotangent weights, or mean-value weights (positive,
//!       so valid by Tutte's theorem) chosen or as the fall-back where the cotangent map folds;
//!   P1  boundary-free conformal map (6.2): every triangle of P0 cut loose, reshaped by its stretch
//!       toward its 3D triangle (the fragmented mesh, figure 6.1), and glued back by the Poisson
//!       equation L u = div F over all vertices, boundary ones included;
//!   P2  boundary-free quasi-harmonic map (6.4): div(C grad u) = div(C grad F) with the tensor C and
//!       the fragments of P1;
//!   P3  optional polish: a fixed-boundary quasi-harmonic map with P2's boundary (5.x, 7.1).
//!
//! A start map of the caller's (FreeBoundaryOptions::start_uv, e.g. linear ABF's layout) may take
//! P0's place. P1 may be repeated, each round's fragments cut from the map of the round before:
//! with the fragments in the frame of their own triangles (FragmentRotation::start_map_frame)
//! every fragment is its 3D triangle turned by the rotation nearest to the map's Jacobian there,
//! and the rounds are the local/global iteration of Liu et al. (2008), whose energy
//! sum_T |T| |J_T - R_T|^2 falls with each round: a map relaxed toward an isometry, less
//! stretched than a conformal one on a curved chart.
//!
//! Validity first: a step whose map would have a flipped or zero-area triangle or a boundary that
//! crosses itself is not taken in full. The step toward the 3D shapes is shortened (the fragments
//! reshaped by K^s, s < 1, instead of K) by bisection until the map is valid, each try one
//! back-substitution; SolveReport::fallbacks says what was shortened and why. Details, and how the
//! fragments are rotated, in host/planar/fragment_targets.h and docs/methods.md
//! ("Free-boundary maps").

#include <memory>
#include <string>
#include <vector>

#include "harmonia/boundary.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/quasi_harmonic_map.h"
#include "harmonia/solver_options.h"

namespace harmonia {

//! The last step to compute.
enum class FreeBoundaryStop {
  conformal,       //!< P1, the boundary-free conformal map.
  quasi_harmonic,  //!< P2, the boundary-free quasi-harmonic map (default).
};

//! How each fragment is turned before the fragments are glued (fragment_targets.h).
enum class FragmentRotation {
  //! The rotation field that fits neighbouring fragments together best (least squares over the
  //! interior edges): exact on developable disks, independent of the start map. Default.
  least_squares_field,
  //! The thesis' construction: each fragment in the frame of its start-map triangle.
  start_map_frame,
};

struct FreeBoundaryOptions {
  //! P0's Laplacian and P3's tensor discretization. tensor_cotangent (default): cotangent weights
  //! (a Cholesky factorization), with the mean-value ones as the fall-back where the cotangent map
  //! folds; tensor_mean_value: mean-value weights for both (positive: P0 is valid on its circle by
  //! Tutte's theorem; LU, slower). P1 and P2 are symmetric Poisson problems and always use the
  //! cotangent-type operator.
  QuasiHarmonicWeights weights = QuasiHarmonicWeights::tensor_cotangent;
  FreeBoundaryStop stop_after = FreeBoundaryStop::quasi_harmonic;
  bool polish = false;  //!< Add P3 (needs stop_after == quasi_harmonic).
  FragmentRotation rotation = FragmentRotation::least_squares_field;
  //! P0's boundary: the unit circle, spaced by edge and triangle size (BoundarySpacing): with
  //! arc-length spacing a long cut through little area takes a large part of the circle, P0
  //! crushes its triangles, and the shortened steps of the later maps inherit that (6.5).
  BoundaryOptions start_boundary{BoundaryShape::circle, BoundarySpacing::edge_and_triangle_size,
                                 {}, {}};
  //! Bisection steps when a step must be shortened (the step is then known within 2^-n).
  int step_bisections = 6;
  //! The start map instead of P0 (#V by 2, valid: no flipped triangle, a simple boundary; any
  //! scale and placement); empty: P0 on the circle.
  Eigen::MatrixX2d start_uv;
  //! How many times P1 is taken, each from the map of the one before (1..1000). More than one
  //! changes the map only with FragmentRotation::start_map_frame (the least-squares field does not
  //! depend on the start map); rounds stop early where no part of a step keeps the map valid.
  int conformal_rounds = 1;
  SolverOptions solver;
  UvNormalization normalization = UvNormalization::match_surface_area;
};

//! What one step of the pipeline did.
struct FreeBoundaryStep {
  std::string name;      //!< "P0 circle", "P1 conformal", "P2 quasi-harmonic", "P3 polish".
  double step = 1.0;     //!< The fraction of the step taken (1 = full; P0 always 1).
  int tries = 1;         //!< Back-substitutions tried (1 when the full step was valid).
  int full_step_flips = 0;                  //!< Flipped + zero-area triangles of the full step.
  int full_step_boundary_intersections = 0; //!< Boundary crossings of the full step.
  double seconds = 0.0;
};

struct FreeBoundaryResult {
  Eigen::MatrixX2d uv;  //!< #V by 2; see MapResult::uv.
  SolveReport report;   //!< report.fallbacks lists every shortened step.
  std::vector<FreeBoundaryStep> steps;
};

[[nodiscard]] FreeBoundaryResult free_boundary_map(const Mesh& mesh,
                                                   const FreeBoundaryOptions& options = {});

//! Reusable solver: topology, the operator pattern and its symbolic analysis, and the rotation
//! field's factorization are computed once; update_geometry takes new vertex positions (same
//! connectivity); solve() runs the pipeline.
class FreeBoundaryMapper {
 public:
  FreeBoundaryMapper(const Mesh& mesh, const FreeBoundaryOptions& options = {});
  ~FreeBoundaryMapper();
  FreeBoundaryMapper(FreeBoundaryMapper&&) noexcept;
  FreeBoundaryMapper& operator=(FreeBoundaryMapper&&) noexcept;
  [[nodiscard]] const SolveReport& setup_report() const;
  void update_geometry(const Eigen::MatrixX3d& vertices);
  [[nodiscard]] FreeBoundaryResult solve();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace harmonia
