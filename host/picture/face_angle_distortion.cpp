// The per-triangle angle distortion that `harmonia compare` and the distortion plot show: the mean
// relative error of a triangle's three corner angles. The faces it leaves out (NaN) are those that
// evaluate_map leaves out of its angle figures, by the same rule on the same rescaled coordinates.
#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "harmonia/distortion_plot.h"
#include "harmonia/types.h"
#include "mesh/power_of_two_scale.h"
#include "planar/uv_layout_checks.h"

namespace harmonia {
namespace {

// Interior angle at corner `at` (atan2 of |cross| and dot: accurate near 0 and pi). UV corners
// come here as 3D points with z = 0, so that a layout equal to a planar mesh's own coordinates
// goes through the very same arithmetic as the mesh and scores exactly 0.
double corner_angle(const Eigen::Vector3d& at, const Eigen::Vector3d& next,
                    const Eigen::Vector3d& previous) {
  const Eigen::Vector3d u = next - at, v = previous - at;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

void check_inputs(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                  const Eigen::MatrixX3i& uv_faces) {
  if (uv_faces.rows() != mesh3d.faces.rows()) {
    throw Error(Status::invalid_input,
                "face_angle_distortion: uv_faces has " + std::to_string(uv_faces.rows()) +
                    " rows but the mesh has " + std::to_string(mesh3d.faces.rows()) + " faces");
  }
  for (Eigen::Index f = 0; f < mesh3d.faces.rows(); ++f) {
    for (int corner = 0; corner < 3; ++corner) {
      const int vertex = mesh3d.faces(f, corner);
      if (vertex < 0 || vertex >= mesh3d.vertices.rows()) {
        throw Error(Status::invalid_input,
                    "face_angle_distortion: face " + std::to_string(f) + " corner " +
                        std::to_string(corner) + " refers to vertex " + std::to_string(vertex) +
                        ", but the mesh has " + std::to_string(mesh3d.vertices.rows()) +
                        " vertices");
      }
    }
  }
  detail::check_uv_faces(uv, uv_faces, "face_angle_distortion");
}

}  // namespace

Eigen::VectorXd face_angle_distortion(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                                      const Eigen::MatrixX3i& uv_faces) {
  check_inputs(mesh3d, uv, uv_faces);
  // As evaluate_map: each side rescaled by its own power of two where needed (exact), so that
  // areas neither overflow nor underflow and the degenerate faces are the same ones.
  const Eigen::MatrixX3d points = detail::scaled_into_safe_range(mesh3d.vertices);
  const Eigen::MatrixX2d layout = detail::scaled_into_safe_range(uv);
  const Eigen::Index face_count = mesh3d.faces.rows();

  const auto corner_point = [&](Eigen::Index face, int corner) -> Eigen::Vector3d {
    return points.row(mesh3d.faces(face, corner));
  };
  const auto corner_uv = [&](Eigen::Index face, int corner) -> Eigen::Vector3d {
    const Eigen::Vector2d point = layout.row(uv_faces(face, corner));
    return {point.x(), point.y(), 0.0};
  };
  Eigen::VectorXd areas(face_count);
  double total_area = 0.0;
  for (Eigen::Index f = 0; f < face_count; ++f) {
    const Eigen::Vector3d p0 = corner_point(f, 0);
    areas[f] = 0.5 * (corner_point(f, 1) - p0).cross(corner_point(f, 2) - p0).norm();
    if (std::isfinite(areas[f])) total_area += areas[f];
  }

  Eigen::VectorXd distortion = Eigen::VectorXd::Constant(face_count, NAN);
  for (Eigen::Index f = 0; f < face_count; ++f) {
    if (!std::isfinite(areas[f]) || areas[f] <= detail::kZeroAreaFraction * total_area) continue;
    const Eigen::Vector3d u0 = corner_uv(f, 0), u1 = corner_uv(f, 1), u2 = corner_uv(f, 2);
    if (!u0.allFinite() || !u1.allFinite() || !u2.allFinite()) continue;
    const Eigen::Vector3d p0 = corner_point(f, 0), p1 = corner_point(f, 1), p2 = corner_point(f, 2);
    const double angles_3d[3] = {corner_angle(p0, p1, p2), corner_angle(p1, p2, p0),
                                 corner_angle(p2, p0, p1)};
    const double angles_uv[3] = {corner_angle(u0, u1, u2), corner_angle(u1, u2, u0),
                                 corner_angle(u2, u0, u1)};
    double relative_error_sum = 0.0;
    for (int corner = 0; corner < 3; ++corner) {
      relative_error_sum += std::abs(angles_uv[corner] - angles_3d[corner]) / angles_3d[corner];
    }
    distortion[f] = relative_error_sum / 3.0;
  }
  return distortion;
}

}  // namespace harmonia
