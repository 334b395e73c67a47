#pragma once
//! \file angles_to_uv.h
//! \brief From planar corner angles to UV coordinates (thesis section 3.3): the angle-based least
//! squares reconstruction (default) or the greedy one.
//!
//! Angles are given per face corner: angles(f, k) is the planar angle at vertex faces(f, k), in
//! radians. They need not be exactly consistent: least squares balances the error over the mesh,
//! greedy lays triangles one by one and accumulates it.

#include <optional>

#include <Eigen/Core>

#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia {

enum class AngleReconstruction {
  //! Each triangle's edge (i->k) is its edge (i->j) rotated by the angle at i and scaled by the
  //! sine law; all these relations solved together in the least-squares sense with two pinned
  //! vertices (sparse normal equations). Balances the error over the whole mesh.
  least_squares,
  //! Breadth-first over the faces: the first triangle laid out from its angles, every further one
  //! from an edge already placed. Cheap, exact for consistent angles, accumulates error otherwise.
  //! (The thesis walks depth-first; breadth-first keeps the construction tree shallow, which
  //! keeps rounding and angle errors from growing along it: see angle_reconstruction_greedy.cpp.)
  greedy,
};

struct AnglesToUvOptions {
  AngleReconstruction method = AngleReconstruction::least_squares;
  //! The two pinned vertices (least squares; greedy starts from the first one's face); by default
  //! a deterministic choice documented in angles_to_uv.cpp. Irrelevant after normalization.
  std::optional<int> pin_first;
  std::optional<int> pin_second;
  SolverOptions solver;
  UvNormalization normalization = UvNormalization::match_surface_area;
};

//! UVs of a disk mesh from its planar corner angles (#F x 3, see above). The report carries the
//! flips and boundary self-intersections of the result like every map.
[[nodiscard]] MapResult angles_to_uv(const Mesh& mesh, const Eigen::MatrixX3d& angles,
                                     const AnglesToUvOptions& options = {});

}  // namespace harmonia
