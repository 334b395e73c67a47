#pragma once
//! \file metrics.h
//! \brief Quality of a parameterization: validity (flips, boundary self-intersections) and
//! distortion (angles, conformality, area, stretch). Used by `harmonia eval` and by every map's report.

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

//! Quality of a map. Which faces each figure covers:
//!   - flips and zero-area counts use the exact orientation of every UV triangle;
//!   - a face whose 3D triangle has (near) zero area has no frame: it is counted in
//!     degenerate_input_triangles and left out of every other figure;
//!   - the angle figures cover the remaining faces with finite UVs, flipped and zero-area ones
//!     included (their angle errors are real);
//!   - the Jacobian figures (conformal, area, stretch) cover the faces that are neither zero-area
//!     in UV nor degenerate in 3D. Flipped faces are included with their unsigned singular values
//!     (a mirrored isometry scores 1); flips are reported by flipped_triangles instead.
//! So a few bad triangles never turn a mean into NaN or infinity.
struct DistortionMetrics {
  int faces = 0;
  int flipped_triangles = 0;        //!< Negative signed UV area (faces should be counter-clockwise).
  int zero_area_triangles = 0;      //!< |UV area| <= 1e-14 * total UV area (or exactly zero), or
                                    //!< non-finite UV coordinates.
  int degenerate_input_triangles = 0;  //!< 3D faces with |area| <= 1e-14 * total 3D area.
  int boundary_self_intersections = 0;  //!< Pairs of non-adjacent UV boundary edges that meet.
  double angle_error_mean_squared = 0;  //!< mean over corners of (uv angle - 3D angle)^2, radians^2.
  double abf_energy = 0;            //!< sum (x - a)^2 / a^2 over corners, divided by 3*#F (#F of the
                                    //!< faces measured; x: UV angle, a: 3D angle; the measure
                                    //!< F / 3nt of thesis table 3.1).
  double conformal_distortion_mean = 0;  //!< 3D-area-weighted mean of sigma1/sigma2 (1 = conformal).
  double conformal_distortion_max = 0;
  double area_distortion_mean = 0;  //!< 3D-area-weighted mean |log(uv area / 3D area)| after scaling
                                    //!< UV to the 3D total area (0 = authalic).
  double area_distortion_max = 0;
  double l2_stretch = 0;            //!< Sander et al. (2001) L2 stretch of the UV -> surface map,
                                    //!< times sqrt(total UV area / total 3D area) (1 = isometry up
                                    //!< to scale; larger is worse).
  Eigen::VectorXd face_conformal_distortion;  //!< #F sigma1/sigma2 (inf for degenerate faces).
  Eigen::VectorXd face_area_log_ratio;        //!< #F log(normalized uv area / 3D area) (-inf for
                                              //!< zero UV area, NaN where 3D area or UV is bad).
};

//! Metrics of the map given per corner: uv_faces (#F by 3) indexes uv (#UV by 2); for a seamless
//! map pass mesh3d.faces. Throws Error(invalid_input) when uv_faces.rows() != mesh3d.faces.rows()
//! or an index is out of range (the message names the face and corner).
[[nodiscard]] DistortionMetrics evaluate_map(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                                             const Eigen::MatrixX3i& uv_faces);

//! Flipped (negative area) and zero-area triangles of a layout (same rules as DistortionMetrics).
//! Throws Error(invalid_input) naming the first uv_faces entry that is not a row of uv.
struct FlipCount {
  int flipped = 0;
  int zero_area = 0;
};
[[nodiscard]] FlipCount count_flips(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces);

//! Number of crossing pairs among the UV boundary edges (edges used by one face of uv_faces).
//! Edges that share a vertex are not counted; others count when the closed segments have a point
//! in common (crossing, touching or overlapping), decided with exact orientation predicates.
//! Edges with a non-finite endpoint are skipped. O(B log B) on average (uniform grid).
[[nodiscard]] int count_boundary_self_intersections(const Eigen::MatrixX2d& uv,
                                                    const Eigen::MatrixX3i& uv_faces);

}  // namespace harmonia
