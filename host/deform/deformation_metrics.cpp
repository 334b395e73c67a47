// harmonia/deformation_metrics.h.

#include "harmonia/deformation_metrics.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "deform/surface_folds.h"
#include "harmonia/types.h"

namespace harmonia {
namespace {

// The in-plane deformation gradient's deviation from a similarity, from the triangle's rest edges
// (a, b from corner 0) and deformed edges (a', b'). In an orthonormal frame of the rest plane the
// rest edges are the columns of E (2x2) and J = [a' b'] E^-1 (3x2); its signed singular values
// come from J^T J and the orientation of the deformed triangle relative to the rest one.
double similarity_deviation(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const Eigen::Vector3d& deformed_a, const Eigen::Vector3d& deformed_b,
                            const Eigen::Vector3d& deformed_normal, const Eigen::Vector3d& rest_normal) {
  const Eigen::Vector3d u = a.normalized();
  const Eigen::Vector3d v = rest_normal.normalized().cross(u);
  Eigen::Matrix2d rest_edges;
  rest_edges << a.dot(u), b.dot(u), a.dot(v), b.dot(v);
  Eigen::Matrix<double, 3, 2> deformed_edges;
  deformed_edges << deformed_a, deformed_b;
  const Eigen::Matrix<double, 3, 2> gradient = deformed_edges * rest_edges.inverse();
  const Eigen::Matrix2d metric = gradient.transpose() * gradient;
  const double trace = metric.trace(), determinant = metric.determinant();
  const double root = std::sqrt(std::max(0.0, trace * trace / 4.0 - determinant));
  const double sigma_1 = std::sqrt(std::max(0.0, trace / 2.0 + root));
  double sigma_2 = std::sqrt(std::max(0.0, trace / 2.0 - root));
  if (deformed_normal.dot(rest_normal) < 0.0) sigma_2 = -sigma_2;  // mirrored
  const double norm = std::sqrt(2.0 * (sigma_1 * sigma_1 + sigma_2 * sigma_2));
  return norm > 0.0 ? std::abs(sigma_1 - sigma_2) / norm : 0.0;
}

}  // namespace

DeformationMetrics deformation_metrics(const Mesh& rest, const Eigen::MatrixX3d& deformed) {
  if (deformed.rows() != rest.vertices.rows())
    throw Error(Status::invalid_input, "deformation metrics: " + std::to_string(deformed.rows()) +
                                           " deformed positions for a mesh of " +
                                           std::to_string(rest.vertices.rows()) + " vertices");
  DeformationMetrics metrics;
  metrics.faces = rest.face_count();
  double sum = 0.0;
  int measured = 0;
  for (Eigen::Index f = 0; f < rest.faces.rows(); ++f) {
    const int i = rest.faces(f, 0), j = rest.faces(f, 1), k = rest.faces(f, 2);
    const Eigen::Vector3d a = rest.vertices.row(j) - rest.vertices.row(i);
    const Eigen::Vector3d b = rest.vertices.row(k) - rest.vertices.row(i);
    const Eigen::Vector3d deformed_a = deformed.row(j) - deformed.row(i);
    const Eigen::Vector3d deformed_b = deformed.row(k) - deformed.row(i);
    const Eigen::Vector3d rest_normal = a.cross(b), deformed_normal = deformed_a.cross(deformed_b);
    if (deformed_normal.squaredNorm() == 0.0) {
      ++metrics.degenerate_faces;
      continue;
    }
    if (deformed_normal.dot(rest_normal) < 0.0) ++metrics.turned_faces;
    if (rest_normal.squaredNorm() == 0.0) continue;
    const double deviation =
        similarity_deviation(a, b, deformed_a, deformed_b, deformed_normal, rest_normal);
    sum += deviation;
    metrics.similarity_deviation_max = std::max(metrics.similarity_deviation_max, deviation);
    ++measured;
  }
  if (measured > 0) metrics.similarity_deviation_mean = sum / measured;
  metrics.folded_faces = detail::triangles_folded_by_pose(rest.faces, detail::edge_neighbours(rest.faces),
                                                         rest.vertices, deformed);
  return metrics;
}

}  // namespace harmonia
