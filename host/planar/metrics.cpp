// Distortion of a parameterization, triangle by triangle: the Jacobian of the affine map from each
// 3D triangle (in its own orthonormal frame) to its UV triangle gives the singular values sigma1 >=
// sigma2, from which conformality, area change and stretch follow; corner angles give the angle
// error and the ABF energy (the measure F / 3nt of thesis table 3.1).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "harmonia/metrics.h"
#include "harmonia/types.h"
#include "mesh/power_of_two_scale.h"
#include "planar/uv_layout_checks.h"

namespace harmonia {
namespace {

// A 3D triangle laid flat in its own orthonormal frame: corner 0 at the origin, corner 1 on the
// positive x axis, corner 2 above it (so the flat copy is counter-clockwise).
struct FlatTriangle {
  Eigen::Vector2d edge1;  // corner1 - corner0
  Eigen::Vector2d edge2;  // corner2 - corner0
  double area = 0.0;
};

FlatTriangle flatten(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                     const Eigen::Vector3d& p2) {
  const Eigen::Vector3d e1 = p1 - p0, e2 = p2 - p0;
  const double length1 = e1.norm();
  const Eigen::Vector3d normal = e1.cross(e2);
  FlatTriangle flat;
  flat.area = 0.5 * normal.norm();
  const double height = normal.norm() / length1;  // Distance of corner 2 from the line of edge 1.
  flat.edge1 = Eigen::Vector2d(length1, 0.0);
  flat.edge2 = Eigen::Vector2d(e1.dot(e2) / length1, height);
  return flat;
}

// Singular values of a 2x2 matrix in closed form: writing it as a similarity plus an
// anti-similarity, sigma1 = |similarity| + |anti-similarity| and sigma2 = their difference.
struct SingularValues {
  double largest = 0.0;
  double smallest = 0.0;
};

SingularValues singular_values(const Eigen::Matrix2d& m) {
  const double similar = std::hypot(0.5 * (m(0, 0) + m(1, 1)), 0.5 * (m(1, 0) - m(0, 1)));
  const double anti = std::hypot(0.5 * (m(0, 0) - m(1, 1)), 0.5 * (m(1, 0) + m(0, 1)));
  return {similar + anti, std::abs(similar - anti)};
}

// Interior angle at corner `at` of a triangle (atan2 of |cross| and dot: accurate near 0 and pi).
template <typename Vector>
double corner_angle(const Vector& at, const Vector& next, const Vector& previous) {
  const Vector u = next - at, v = previous - at;
  double cross = 0.0;
  if constexpr (Vector::RowsAtCompileTime == 2) {
    cross = std::abs(u.x() * v.y() - u.y() * v.x());
  } else {
    cross = u.cross(v).norm();
  }
  return std::atan2(cross, u.dot(v));
}

void check_inputs(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                  const Eigen::MatrixX3i& uv_faces) {
  if (uv_faces.rows() != mesh3d.faces.rows()) {
    throw Error(Status::invalid_input,
                "evaluate_map: uv_faces has " + std::to_string(uv_faces.rows()) +
                    " rows but the mesh has " + std::to_string(mesh3d.faces.rows()) + " faces");
  }
  for (Eigen::Index f = 0; f < mesh3d.faces.rows(); ++f) {
    for (int corner = 0; corner < 3; ++corner) {
      const int vertex = mesh3d.faces(f, corner);
      if (vertex < 0 || vertex >= mesh3d.vertices.rows()) {
        throw Error(Status::invalid_input, "evaluate_map: face " + std::to_string(f) + " corner " +
                                               std::to_string(corner) + " refers to vertex " +
                                               std::to_string(vertex) + ", but the mesh has " +
                                               std::to_string(mesh3d.vertices.rows()) +
                                               " vertices");
      }
    }
  }
  detail::check_uv_faces(uv, uv_faces, "evaluate_map");
}

DistortionMetrics evaluate_map_in_safe_range(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                               const Eigen::MatrixX3i& uv_faces) {
  check_inputs(mesh3d, uv, uv_faces);
  const Eigen::Index face_count = mesh3d.faces.rows();
  DistortionMetrics metrics;
  metrics.faces = static_cast<int>(face_count);
  metrics.face_conformal_distortion.setConstant(face_count, INFINITY);
  metrics.face_area_log_ratio.setConstant(face_count, NAN);
  metrics.face_l2_stretch.setConstant(face_count, NAN);
  if (face_count == 0) return metrics;

  // Areas first: the UV layout is scaled to the 3D total before area ratios are taken.
  const std::vector<double> uv_areas = detail::signed_uv_areas(uv, uv_faces);
  std::vector<FlatTriangle> flat(static_cast<std::size_t>(face_count));
  double total_area_3d = 0.0;
  for (Eigen::Index f = 0; f < face_count; ++f) {
    flat[f] =
        flatten(mesh3d.vertices.row(mesh3d.faces(f, 0)), mesh3d.vertices.row(mesh3d.faces(f, 1)),
                mesh3d.vertices.row(mesh3d.faces(f, 2)));
    if (std::isfinite(flat[f].area)) total_area_3d += flat[f].area;
  }
  const double total_area_uv = detail::total_finite_area(uv_areas);
  const double uv_to_3d_area = total_area_uv > 0.0 ? total_area_3d / total_area_uv : 1.0;

  double measured_area_3d = 0.0, conformal_sum = 0.0, area_sum = 0.0, stretch_sum = 0.0;
  double angle_error_sum = 0.0, abf_sum = 0.0;
  int angle_faces = 0;
  for (Eigen::Index f = 0; f < face_count; ++f) {
    const std::size_t face = static_cast<std::size_t>(f);
    const detail::TriangleState state =
        detail::classify_uv_triangle(uv, uv_faces, f, uv_areas[face]);
    if (state == detail::TriangleState::flipped) ++metrics.flipped_triangles;
    if (state == detail::TriangleState::degenerate) ++metrics.zero_area_triangles;

    // A 3D triangle without area has no frame and no angles: it is counted and left out.
    const double area_3d = flat[face].area;
    if (!std::isfinite(area_3d) || area_3d <= detail::kZeroAreaFraction * total_area_3d) {
      ++metrics.degenerate_input_triangles;
      continue;
    }
    const Eigen::Vector2d u0 = uv.row(uv_faces(f, 0)), u1 = uv.row(uv_faces(f, 1)),
                          u2 = uv.row(uv_faces(f, 2));
    if (!u0.allFinite() || !u1.allFinite() || !u2.allFinite()) continue;

    // Angles: every corner of a face with a proper 3D triangle, flipped or squashed UVs included.
    const Eigen::Vector3d p0 = mesh3d.vertices.row(mesh3d.faces(f, 0)),
                          p1 = mesh3d.vertices.row(mesh3d.faces(f, 1)),
                          p2 = mesh3d.vertices.row(mesh3d.faces(f, 2));
    const double angles_3d[3] = {corner_angle(p0, p1, p2), corner_angle(p1, p2, p0),
                                 corner_angle(p2, p0, p1)};
    const double angles_uv[3] = {corner_angle(u0, u1, u2), corner_angle(u1, u2, u0),
                                 corner_angle(u2, u0, u1)};
    for (int corner = 0; corner < 3; ++corner) {
      const double error = angles_uv[corner] - angles_3d[corner];
      angle_error_sum += error * error;
      abf_sum += error * error / (angles_3d[corner] * angles_3d[corner]);
    }
    ++angle_faces;

    metrics.face_area_log_ratio[f] = std::log(uv_to_3d_area * std::abs(uv_areas[face]) / area_3d);
    if (state == detail::TriangleState::degenerate) {  // Ratios below are unbounded.
      metrics.face_l2_stretch[f] = INFINITY;
      continue;
    }

    // Jacobian of the affine map flat 3D triangle -> UV triangle: J [e1 e2] = [u1-u0 u2-u0].
    Eigen::Matrix2d flat_edges, uv_edges;
    flat_edges << flat[face].edge1, flat[face].edge2;
    uv_edges << u1 - u0, u2 - u0;
    const Eigen::Matrix2d jacobian = uv_edges * flat_edges.inverse();
    const SingularValues sigma = singular_values(jacobian);
    const double conformal = sigma.largest / sigma.smallest;
    metrics.face_conformal_distortion[f] = conformal;
    // Sander et al.: stretch of the inverse map (UV -> surface), whose singular values are
    // 1/sigma2 and 1/sigma1; its mean square is (1/sigma1^2 + 1/sigma2^2) / 2.
    const double stretch_squared =
        0.5 * (1.0 / (sigma.largest * sigma.largest) + 1.0 / (sigma.smallest * sigma.smallest));
    const double log_ratio = std::abs(metrics.face_area_log_ratio[f]);
    metrics.face_l2_stretch[f] = std::sqrt(stretch_squared / uv_to_3d_area);

    measured_area_3d += area_3d;
    conformal_sum += area_3d * conformal;
    area_sum += area_3d * log_ratio;
    stretch_sum += area_3d * stretch_squared;
    metrics.conformal_distortion_max = std::max(metrics.conformal_distortion_max, conformal);
    metrics.area_distortion_max = std::max(metrics.area_distortion_max, log_ratio);
  }

  if (angle_faces > 0) {
    metrics.angle_error_mean_squared = angle_error_sum / (3.0 * angle_faces);
    metrics.abf_energy = abf_sum / (3.0 * angle_faces);
  }
  if (measured_area_3d > 0.0) {
    metrics.conformal_distortion_mean = conformal_sum / measured_area_3d;
    metrics.area_distortion_mean = area_sum / measured_area_3d;
    // Normalized so that any uniform scaling of an isometry scores 1.
    metrics.l2_stretch =
        std::sqrt(stretch_sum / measured_area_3d) * std::sqrt(total_area_uv / total_area_3d);
  }
  metrics.boundary_self_intersections = count_boundary_self_intersections(uv, uv_faces);
  return metrics;
}

}  // namespace

DistortionMetrics evaluate_map(const Mesh& mesh3d, const Eigen::MatrixX2d& uv,
                               const Eigen::MatrixX3i& uv_faces) {
  // Every metric is a count or a ratio, so the surface and the layout are first rescaled, each by
  // its own power of two where needed (exact; mesh/power_of_two_scale.h): their areas and squared
  // lengths then neither overflow nor underflow, at 1e-100 or at 1e200 units.
  Mesh surface;
  surface.vertices = detail::scaled_into_safe_range(mesh3d.vertices);
  surface.faces = mesh3d.faces;
  return evaluate_map_in_safe_range(surface, detail::scaled_into_safe_range(uv), uv_faces);
}

}  // namespace harmonia
