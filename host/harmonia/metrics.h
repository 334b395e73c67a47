#pragma once
//! \file metrics.h
//! \brief Quality of a parameterization: validity (flips, boundary self-intersections) and
//! distortion (angles, conformality, area, stretch). Used by `harmonia eval` and by every map's report.

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

struct DistortionMetrics {
  int faces = 0;
  int flipped_triangles = 0;        //!< Negative signed UV area (faces should be counter-clockwise).
  int zero_area_triangles = 0;      //!< |UV area| <= 1e-14 * total UV area (or exactly zero).
  int boundary_self_intersections = 0;  //!< Pairs of non-adjacent UV boundary edges that cross.
  double angle_error_mean_squared = 0;  //!< mean over corners of (uv angle - 3D angle)^2, radians^2.
  double abf_energy = 0;            //!< sum (x - a)^2 / a^2 over corners, divided by 3*#F
                                    //!< (x: UV angle, a: 3D angle).
  double conformal_distortion_mean = 0;  //!< Area-weighted mean of sigma1/sigma2 (1 = conformal).
  double conformal_distortion_max = 0;
  double area_distortion_mean = 0;  //!< Area-weighted mean |log(uv area / 3D area)| after scaling
                                    //!< UV to the 3D total area (0 = authalic).
  double area_distortion_max = 0;
  double l2_stretch = 0;            //!< Sander et al. L2 stretch, normalized by total areas (1 = best).
  Eigen::VectorXd face_conformal_distortion;  //!< #F sigma1/sigma2 (inf for degenerate faces).
  Eigen::VectorXd face_area_log_ratio;        //!< #F log(normalized uv area / 3D area).
};

//! Metrics of the map given per corner: uv_faces (#F by 3) indexes uv (#UV by 2); for a seamless
//! map pass mesh3d.faces. \pre uv_faces.rows() == mesh3d.faces.rows().
[[nodiscard]] DistortionMetrics evaluate_map(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                                             const Eigen::MatrixX3i& uv_faces);

//! Flipped (negative area) and zero-area triangles of a layout.
struct FlipCount {
  int flipped = 0;
  int zero_area = 0;
};
[[nodiscard]] FlipCount count_flips(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& uv_faces);

//! Number of crossing pairs among the UV boundary edges (edges used by one face of uv_faces).
//! Edges that share a vertex are not counted. O(B log B) on average (uniform grid).
[[nodiscard]] int count_boundary_self_intersections(const Eigen::MatrixX2d& uv,
                                                    const Eigen::MatrixX3i& uv_faces);

}  // namespace harmonia
