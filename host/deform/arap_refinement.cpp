#include "deform/arap_refinement.h"

#include <cmath>

#include "harmonia/laplacian.h"

namespace harmonia::detail {
namespace {

// Steps of the rotation extraction per local step: from a warm start each step sharply reduces the
// remaining angle, so a few reach the accuracy the next global step can use.
constexpr int kExtractionSteps = 4;

// The rotation of `covariance`'s polar decomposition, improved from `rotation`.
void extract_rotation(const Eigen::Matrix3d& covariance, Eigen::Quaterniond& rotation) {
  for (int step = 0; step < kExtractionSteps; ++step) {
    const Eigen::Matrix3d current = rotation.toRotationMatrix();
    const Eigen::Vector3d axis = current.col(0).cross(covariance.col(0)) +
                                 current.col(1).cross(covariance.col(1)) +
                                 current.col(2).cross(covariance.col(2));
    const double alignment = std::abs(current.col(0).dot(covariance.col(0)) +
                                      current.col(1).dot(covariance.col(1)) +
                                      current.col(2).dot(covariance.col(2)));
    if (!(alignment > 0.0)) return;
    const Eigen::Vector3d omega = axis / alignment;
    const double angle = omega.norm();
    if (!(angle > 1e-15) || !std::isfinite(angle)) return;
    rotation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega / angle)) * rotation;
    rotation.normalize();
  }
}

}  // namespace

ArapRefinement::ArapRefinement(const Mesh& rest)
    : faces_(rest.faces), vertex_count_(rest.vertex_count()), weighted_edges_(3, 3 * rest.face_count()) {
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    Eigen::Vector3d position[3];
    for (int k = 0; k < 3; ++k) position[k] = rest.vertices.row(faces_(f, k));
    const Eigen::Vector3d half_cot = cotangent_half_weights(position[0], position[1], position[2]);
    for (int k = 0; k < 3; ++k)
      weighted_edges_.col(3 * f + k) = half_cot[k] * (position[(k + 2) % 3] - position[(k + 1) % 3]);
  }
}

void ArapRefinement::fit_vertex_rotations(const Eigen::MatrixXd& positions,
                                          std::vector<Eigen::Quaterniond>& vertex_rotations) const {
  std::vector<Eigen::Matrix3d> covariance(static_cast<std::size_t>(vertex_count_),
                                          Eigen::Matrix3d::Zero());
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    Eigen::Matrix3d triangle = Eigen::Matrix3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d deformed_edge =
          positions.row(faces_(f, (k + 2) % 3)) - positions.row(faces_(f, (k + 1) % 3));
      triangle += deformed_edge * weighted_edges_.col(3 * f + k).transpose();
    }
    for (int k = 0; k < 3; ++k) covariance[static_cast<std::size_t>(faces_(f, k))] += triangle;
  }
  for (std::size_t v = 0; v < covariance.size(); ++v)
    extract_rotation(covariance[v], vertex_rotations[v]);
}

std::vector<Eigen::Matrix3d> ArapRefinement::triangle_linear_parts(
    const std::vector<Eigen::Quaterniond>& vertex_rotations, const Eigen::VectorXd& scales) const {
  std::vector<Eigen::Matrix3d> linear(static_cast<std::size_t>(faces_.rows()));
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    for (int k = 0; k < 3; ++k)
      sum += vertex_rotations[static_cast<std::size_t>(faces_(f, k))].toRotationMatrix();
    linear[static_cast<std::size_t>(f)] = (scales[f] / 3.0) * sum;
  }
  return linear;
}

}  // namespace harmonia::detail
