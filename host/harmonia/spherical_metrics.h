#pragma once
//! \file spherical_metrics.h
//! \brief Quality of a spherical map: validity on the sphere (orientation of every triangle
//! against the outward normal, degree) and distortion against the input triangles. Used by
//! `harmonia eval --sphere` and by every spherical map's report.

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

//! Quality of a map of a closed mesh onto the unit sphere. The points are first scaled to unit
//! length. Each input triangle is compared with its chord triangle, the flat triangle spanned by
//! its three sphere points (so figures agree with ../shared/tools/sphereval.py):
//!   - flips use the exact sign of det[a, b, c] of each triangle's points: negative = turned over
//!     against the outward normal (faces as in the input, counter-clockwise seen from outside),
//!     zero = degenerate (a triangle counts once, degenerate before flipped);
//!   - a face whose 3D triangle has (near) zero area has no frame and is left out of the
//!     distortion figures, as are degenerate chord triangles.
struct SphericalMetrics {
  int faces = 0;
  int flipped_triangles = 0;     //!< det[a, b, c] < 0.
  int degenerate_triangles = 0;  //!< det[a, b, c] = 0 (exact), or non-finite points.
  //! Signed spherical area of all triangles over 4 pi (Van Oosterom-Strackee areas): 1 for a
  //! bijective map, whatever its distortion.
  double degree = 0;
  //! Mean over corners of (chord angle - 3D angle)^2, in radians^2.
  double angle_error_mean_squared = 0;
  //! 3D-area-weighted mean and max of sigma1/sigma2 of the affine map from each 3D triangle to its
  //! chord triangle (1 = conformal).
  double conformal_distortion_mean = 0;
  double conformal_distortion_max = 0;
  //! 3D-area-weighted mean and max of |log((chord area / total chord area) / (3D area / total 3D
  //! area))| (0 = authalic).
  double area_distortion_mean = 0;
  double area_distortion_max = 0;
  //! Largest | |p| - 1 | over the points before scaling (0 for points on the unit sphere).
  double max_radius_deviation = 0;
  //! #F log of the normalized area ratio above (NaN where not measured).
  Eigen::VectorXd face_area_log_ratio;
  //! #F per-face orientation: +1, -1 (flipped) or 0 (degenerate).
  Eigen::VectorXi face_orientation;
};

//! Metrics of `sphere_points` (#V by 3, rows in the mesh's vertex order) as a map of `mesh`.
//! A row count other than #V throws harmonia::Error(invalid_input).
[[nodiscard]] SphericalMetrics spherical_metrics(const Mesh& mesh,
                                                 const Eigen::MatrixX3d& sphere_points);

}  // namespace harmonia
