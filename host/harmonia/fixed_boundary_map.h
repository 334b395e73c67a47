#pragma once
//! \file fixed_boundary_map.h
//! \brief Discrete harmonic / conformal maps with a fixed boundary (thesis chapter 4, eq. 6.1):
//! solve L_II u_I = -L_IB u_B for any weight scheme of laplacian.h with the boundary placed by
//! boundary.h. With positive weights and a convex boundary the map has no flips (Tutte).

#include <memory>

#include "harmonia/boundary.h"
#include "harmonia/laplacian.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia {

struct FixedBoundaryOptions {
  WeightScheme weights = WeightScheme::cotangent;  //!< Discretization of the Laplacian.
  BoundaryOptions boundary;                         //!< Where the boundary goes (circle by default).
  SolverOptions solver;                             //!< Backend, tolerances, progress.
  UvNormalization normalization = UvNormalization::match_surface_area;  //!< Output normalization.
};

//! One-shot: build a FixedBoundaryMapper and solve once.
//! \pre mesh is a disk (check_disk); otherwise report.status = not_a_disk with the reason.
[[nodiscard]] MapResult fixed_boundary_map(const Mesh& mesh, const FixedBoundaryOptions& options = {});

//! Reusable solver: the constructor analyses topology, the boundary and the sparsity pattern;
//! update_geometry re-assembles and re-factorizes; solve() back-substitutes (u and v at once), and
//! solve(boundary_uv) reuses the factorization for new boundary positions.
class FixedBoundaryMapper {
 public:
  FixedBoundaryMapper(const Mesh& mesh, const FixedBoundaryOptions& options = {});
  ~FixedBoundaryMapper();
  FixedBoundaryMapper(FixedBoundaryMapper&&) noexcept;
  FixedBoundaryMapper& operator=(FixedBoundaryMapper&&) noexcept;

  //! Status of the setup (ok, not_a_disk, invalid_input, numerical_failure) and its message.
  [[nodiscard]] const SolveReport& setup_report() const;
  //! New vertex positions (same connectivity): weights re-assembled, matrix re-factorized.
  void update_geometry(const Eigen::MatrixX3d& vertices);
  //! Solves with the boundary placement from the options.
  [[nodiscard]] MapResult solve();
  //! Solves with new positions for the fixed vertices (same vertices, same order as placement()).
  [[nodiscard]] MapResult solve(const Eigen::MatrixX2d& boundary_uv);
  //! The fixed vertices and their positions.
  [[nodiscard]] const BoundaryPlacement& placement() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace harmonia
