// Quality of a spherical map (harmonia/spherical_metrics.h).

#include "harmonia/spherical_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <Eigen/Dense>

#include "harmonia/types.h"
#include "sphere/sphere_orientation.h"

namespace harmonia {
namespace {

// A flat triangle in its own orthonormal frame: the first edge along x. Columns: the two edges.
Eigen::Matrix2d in_own_frame(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  const Eigen::Vector3d first = b - a, second = c - a;
  const Eigen::Vector3d x = first.normalized();
  const Eigen::Vector3d y = (second - second.dot(x) * x).normalized();
  Eigen::Matrix2d edges;
  edges << first.norm(), second.dot(x), 0.0, second.dot(y);
  return edges;
}

double corner_angle(const Eigen::Vector3d& at, const Eigen::Vector3d& to, const Eigen::Vector3d& other) {
  const Eigen::Vector3d u = to - at, v = other - at;
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

}  // namespace

SphericalMetrics spherical_metrics(const Mesh& mesh, const Eigen::MatrixX3d& sphere_points) {
  if (sphere_points.rows() != mesh.vertices.rows())
    throw Error(Status::invalid_input, "spherical_metrics: " + std::to_string(sphere_points.rows()) +
                                           " sphere points for " +
                                           std::to_string(mesh.vertices.rows()) + " vertices");
  SphericalMetrics metrics;
  const Eigen::Index face_count = mesh.faces.rows();
  metrics.faces = static_cast<int>(face_count);
  metrics.face_area_log_ratio = Eigen::VectorXd::Constant(face_count, std::numeric_limits<double>::quiet_NaN());
  metrics.face_orientation = Eigen::VectorXi::Zero(face_count);
  Eigen::MatrixX3d points = sphere_points;
  for (Eigen::Index v = 0; v < points.rows(); ++v) {
    const double radius = points.row(v).norm();
    if (std::isfinite(radius))
      metrics.max_radius_deviation = std::max(metrics.max_radius_deviation, std::abs(radius - 1.0));
    if (radius > 0.0) points.row(v) /= radius;
  }

  Eigen::VectorXd surface_area(face_count), chord_area(face_count);
  double total_surface = 0.0, total_chord = 0.0, signed_sphere_area = 0.0;
  std::vector<char> measured(static_cast<std::size_t>(face_count), 0);
  for (Eigen::Index f = 0; f < face_count; ++f) {
    const Eigen::Vector3d a = points.row(mesh.faces(f, 0)), b = points.row(mesh.faces(f, 1)),
                          c = points.row(mesh.faces(f, 2));
    const Eigen::Vector3d p = mesh.vertices.row(mesh.faces(f, 0)), q = mesh.vertices.row(mesh.faces(f, 1)),
                          r = mesh.vertices.row(mesh.faces(f, 2));
    surface_area[f] = 0.5 * (q - p).cross(r - p).norm();
    total_surface += surface_area[f];
    if (!a.allFinite() || !b.allFinite() || !c.allFinite()) {
      ++metrics.degenerate_triangles;
      chord_area[f] = 0.0;
      continue;
    }
    const int sign = detail::sphere_orientation_sign(a, b, c);
    metrics.face_orientation[f] = sign;
    if (sign == 0) ++metrics.degenerate_triangles;
    if (sign < 0) ++metrics.flipped_triangles;
    signed_sphere_area += detail::signed_spherical_area(a, b, c);
    chord_area[f] = 0.5 * (b - a).cross(c - a).norm();
    total_chord += chord_area[f];
    measured[static_cast<std::size_t>(f)] = sign != 0 ? 1 : 0;
  }
  metrics.degree = signed_sphere_area / (4.0 * std::numbers::pi);

  // Distortion over the faces with a 3D frame and a chord triangle.
  const double degenerate_surface = 1e-14 * total_surface;
  double weight_sum = 0.0, conformal_sum = 0.0, area_sum = 0.0, angle_sum = 0.0;
  int angle_count = 0;
  for (Eigen::Index f = 0; f < face_count; ++f) {
    if (!measured[static_cast<std::size_t>(f)] || !(surface_area[f] > degenerate_surface) ||
        !(chord_area[f] > 0.0))
      continue;
    const Eigen::Vector3d a = points.row(mesh.faces(f, 0)), b = points.row(mesh.faces(f, 1)),
                          c = points.row(mesh.faces(f, 2));
    const Eigen::Vector3d p = mesh.vertices.row(mesh.faces(f, 0)), q = mesh.vertices.row(mesh.faces(f, 1)),
                          r = mesh.vertices.row(mesh.faces(f, 2));
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d* sphere_corner[3] = {&a, &b, &c};
      const Eigen::Vector3d* surface_corner[3] = {&p, &q, &r};
      const double error = corner_angle(*sphere_corner[k], *sphere_corner[(k + 1) % 3], *sphere_corner[(k + 2) % 3]) -
                           corner_angle(*surface_corner[k], *surface_corner[(k + 1) % 3], *surface_corner[(k + 2) % 3]);
      angle_sum += error * error;
      ++angle_count;
    }
    // The affine map surface triangle -> chord triangle, both in their own frames.
    const Eigen::Matrix2d jacobian = in_own_frame(a, b, c) * in_own_frame(p, q, r).inverse();
    const Eigen::Vector2d singular = jacobian.jacobiSvd().singularValues();
    const double conformal = singular[1] > 0.0 ? singular[0] / singular[1] : std::numeric_limits<double>::infinity();
    const double log_ratio =
        std::log((chord_area[f] / total_chord) / (surface_area[f] / total_surface));
    metrics.face_area_log_ratio[f] = log_ratio;
    weight_sum += surface_area[f];
    conformal_sum += surface_area[f] * conformal;
    area_sum += surface_area[f] * std::abs(log_ratio);
    metrics.conformal_distortion_max = std::max(metrics.conformal_distortion_max, conformal);
    metrics.area_distortion_max = std::max(metrics.area_distortion_max, std::abs(log_ratio));
  }
  if (weight_sum > 0.0) {
    metrics.conformal_distortion_mean = conformal_sum / weight_sum;
    metrics.area_distortion_mean = area_sum / weight_sum;
  }
  if (angle_count > 0) metrics.angle_error_mean_squared = angle_sum / angle_count;
  return metrics;
}

}  // namespace harmonia
