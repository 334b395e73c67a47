#pragma once
//! \file metrics.h
//! \brief Quality of a parameterization: validity (flips, boundary self-intersections) and
//! distortion (angles, conformality, area, stretch). Used by `harmonia eval` and by every map's
//! report.

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

//! Quality of a map. Which faces each figure covers:
//!   - flips and zero-area counts use the exact orientation of every UV triangle; a triangle counts
//!     once, zero-area before flipped;
//!   - a face whose 3D triangle has (near) zero area has no frame: it is counted in
//!     degenerate_input_triangles and left out of every other figure;
//!   - the angle figures cover the remaining faces with finite UVs, flipped and zero-area ones
//!     included (their angle errors are real);
//!   - the Jacobian figures (conformal, area, stretch) cover the faces that are neither zero-area
//!     in UV nor degenerate in 3D. Flipped faces are included with their unsigned singular values
//!     (a mirrored isometry scores 1); flips are reported by flipped_triangles instead.
//! So a few bad triangles never turn a mean into NaN or infinity.
//! sigma1 >= sigma2 are the singular values of the Jacobian of the map from a 3D triangle (in its
//! own orthonormal frame) to its UV triangle.
struct DistortionMetrics {
  int faces = 0;
  //! Negative signed UV area (faces should be counter-clockwise).
  int flipped_triangles = 0;
  //! UV area zero (exact orientation test) or within what rounding the corners could change
  //! (|area| <= 8 eps * largest |coordinate| * perimeter), or non-finite UV coordinates.
  int zero_area_triangles = 0;
  //! 3D faces with area <= 1e-14 * total 3D area (or non-finite vertices).
  int degenerate_input_triangles = 0;
  //! Pairs of non-adjacent UV boundary edges that meet (see count_boundary_self_intersections).
  int boundary_self_intersections = 0;
  //! Mean over corners of (UV angle - 3D angle)^2, in radians^2.
  double angle_error_mean_squared = 0;
  //! Sum over corners of (x - a)^2 / a^2 (x: UV angle, a: 3D angle), divided by 3 * #F (#F of the
  //! faces measured): the measure F / 3nt of thesis table 3.1.
  double abf_energy = 0;
  //! 3D-area-weighted mean of sigma1/sigma2 (1 = conformal).
  double conformal_distortion_mean = 0;
  double conformal_distortion_max = 0;
  //! 3D-area-weighted mean |log(uv area / 3D area)| after scaling UV to the 3D total area
  //! (0 = authalic).
  double area_distortion_mean = 0;
  double area_distortion_max = 0;
  //! Sander et al. (2001) L2 stretch of the UV -> surface map, sqrt(sum A (1/sigma1^2 +
  //! 1/sigma2^2)/2 / sum A) with A the 3D areas, times sqrt(total UV area / total 3D area):
  //! 1 for an isometry up to scale, larger is worse.
  double l2_stretch = 0;
  //! #F sigma1/sigma2 (inf for zero-area and degenerate faces).
  Eigen::VectorXd face_conformal_distortion;
  //! #F log(normalized UV area / 3D area) (-inf for zero UV area; NaN where the 3D triangle is
  //! degenerate or the UVs are not finite).
  Eigen::VectorXd face_area_log_ratio;
  //! #F each triangle's own L2 stretch, sqrt((1/sigma1^2 + 1/sigma2^2) / 2) times the same
  //! normalization as l2_stretch (1 for an isometry up to the layout's one scale; inf for a
  //! zero-area UV triangle; NaN where the 3D triangle is degenerate or the UVs are not finite).
  Eigen::VectorXd face_l2_stretch;
};

//! Metrics of the map given per corner: uv_faces (#F by 3) indexes uv (#UV by 2); for a seamless
//! map pass mesh3d.faces. Throws Error(invalid_input) when uv_faces.rows() != mesh3d.faces.rows()
//! or an index is out of range (the message names the face and corner).
[[nodiscard]] DistortionMetrics evaluate_map(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                                             const Eigen::MatrixX3i& uv_faces);

//! Flipped (negative area) and zero-area triangles of a layout (same rules as DistortionMetrics).
//! Throws Error(invalid_input) naming the first uv_faces entry that is not a row of uv.
struct FlipCount {
  int flipped = 0;    //!< Clockwise triangles (exact orientation test).
  int zero_area = 0;  //!< Zero area within the rounding of their corners, or non-finite.
  //! Valid (counter-clockwise, resolvable) triangles below 1e-14 of the total UV area: a map
  //! that shrinks part of the surface that much (e.g. a protrusion the cut left closed).
  int tiny = 0;
};
[[nodiscard]] FlipCount count_flips(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces);

//! Number of crossing pairs among the UV boundary edges (edges used by one face of uv_faces).
//! Edges that share a vertex are not counted; others count when the closed segments have a point
//! in common (crossing, touching or overlapping), decided with exact orientation predicates.
//! Edges with a non-finite endpoint are skipped. O(B log B) on average (uniform grid).
[[nodiscard]] int count_boundary_self_intersections(const Eigen::MatrixX2d& uv,
                                                    const Eigen::MatrixX3i& uv_faces);

}  // namespace harmonia
