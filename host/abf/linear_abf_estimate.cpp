// Linear ABF's initial estimate (thesis 3.2.2): the 3D angles, except on vertex rings far from
// flat, where the ring's exponential map gives angles that a single linearization can reach.

#include "abf/linear_abf_estimate.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace harmonia::detail {
namespace {

constexpr double kPi = std::numbers::pi;

}  // namespace

Eigen::VectorXd clamp_angles(const Eigen::VectorXd& angles) {
  return angles.cwiseMax(kLinearAbfAngleMargin).cwiseMin(kPi - kLinearAbfAngleMargin);
}

Eigen::VectorXd linear_abf_estimate(const Mesh& mesh, const AngleTopology& topology,
                                    const Eigen::VectorXd& angles, double exponential_map_deficit,
                                    int* switched) {
  Eigen::VectorXd estimate = angles;
  // Rings to replace, and how many replaced rings each face lies on.
  std::vector<double> ring_scale(static_cast<std::size_t>(topology.vertex_count), 0.0);
  std::vector<unsigned char> face_rings(static_cast<std::size_t>(topology.face_count), 0);
  int replaced = 0;
  for (const int v : topology.interior_vertices) {
    double sum = 0.0;
    for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1]; ++k)
      sum += angles[topology.vertex_corners[k]];
    if (!(std::abs(2.0 * kPi - sum) > exponential_map_deficit) || !(sum > 0.0)) continue;
    ring_scale[static_cast<std::size_t>(v)] = 2.0 * kPi / sum;
    ++replaced;
    for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1]; ++k)
      ++face_rings[static_cast<std::size_t>(topology.vertex_corners[k] / 3)];
  }
  if (switched != nullptr) *switched = replaced;
  for (const int v : topology.interior_vertices) {
    const double scale = ring_scale[static_cast<std::size_t>(v)];
    if (scale == 0.0) continue;
    const Eigen::Vector3d center = mesh.vertices.row(v);
    for (int k = topology.vertex_corner_offsets[v]; k < topology.vertex_corner_offsets[v + 1]; ++k) {
      const int central = topology.vertex_corners[k];
      const int f = central / 3, local = central % 3;
      const double opening = angles[central] * scale;
      estimate[central] = opening;
      if (face_rings[static_cast<std::size_t>(f)] != 1) continue;
      // The flattened ring triangle: spokes of the 3D lengths to the next (left) and previous
      // (right) vertex, `opening` between them; its other angles from the two sides and the
      // included angle.
      const double left_spoke =
          (Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, (local + 1) % 3))) - center).norm();
      const double right_spoke =
          (Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, (local + 2) % 3))) - center).norm();
      const double left_angle = std::atan2(right_spoke * std::sin(opening),
                                           left_spoke - right_spoke * std::cos(opening));
      estimate[3 * f + (local + 1) % 3] = left_angle;
      estimate[3 * f + (local + 2) % 3] = kPi - opening - left_angle;
    }
  }
  return clamp_angles(estimate);
}

}  // namespace harmonia::detail
