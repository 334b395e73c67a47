#include "deform/deformation_gradients.h"

#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/LU>

namespace harmonia::detail {
namespace {

// [e1 e2 e3] of a triangle (Sumner and Popovic's fourth vertex along the normal).
Eigen::Matrix3d frame(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d first = b - a, second = c - a;
  const Eigen::Vector3d normal = first.cross(second);
  const double length = normal.norm();
  Eigen::Matrix3d columns;
  columns.col(0) = first;
  columns.col(1) = second;
  columns.col(2) = length > 0.0 ? Eigen::Vector3d(normal / std::sqrt(length)) : Eigen::Vector3d::Zero();
  return columns;
}

}  // namespace

DeformationGradients::DeformationGradients(const Mesh& rest)
    : faces_(rest.faces), rest_frame_inverse_(static_cast<std::size_t>(rest.face_count())),
      rest_areas_(rest.face_count()) {
  std::vector<int> counts(static_cast<std::size_t>(rest.vertex_count()) + 1, 0);
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    const Eigen::Matrix3d columns = frame(rest.vertices.row(faces_(f, 0)), rest.vertices.row(faces_(f, 1)),
                                          rest.vertices.row(faces_(f, 2)));
    const double determinant = columns.determinant();
    rest_frame_inverse_[static_cast<std::size_t>(f)] =
        determinant != 0.0 && std::isfinite(determinant) ? Eigen::Matrix3d(columns.inverse())
                                                         : Eigen::Matrix3d::Zero();
    rest_areas_[f] = 0.5 * columns.col(0).cross(columns.col(1)).norm();
    for (int k = 0; k < 3; ++k) ++counts[static_cast<std::size_t>(faces_(f, k)) + 1];
  }
  for (std::size_t v = 1; v < counts.size(); ++v) counts[v] += counts[v - 1];
  incident_offsets_ = counts;
  incident_faces_.resize(static_cast<std::size_t>(counts.back()));
  for (Eigen::Index f = 0; f < faces_.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      incident_faces_[static_cast<std::size_t>(counts[static_cast<std::size_t>(faces_(f, k))]++)] =
          static_cast<int>(f);
}

std::vector<Eigen::Matrix3d> DeformationGradients::of(const Eigen::MatrixX3d& pose) const {
  std::vector<Eigen::Matrix3d> gradients(rest_frame_inverse_.size());
  for (Eigen::Index f = 0; f < faces_.rows(); ++f) {
    const Eigen::Matrix3d& inverse = rest_frame_inverse_[static_cast<std::size_t>(f)];
    gradients[static_cast<std::size_t>(f)] =
        inverse.isZero(0.0) ? Eigen::Matrix3d::Identity()
                            : Eigen::Matrix3d(frame(pose.row(faces_(f, 0)), pose.row(faces_(f, 1)),
                                                    pose.row(faces_(f, 2))) *
                                              inverse);
  }
  return gradients;
}

Eigen::Matrix3d DeformationGradients::mean_around(int vertex,
                                                  const std::vector<Eigen::Matrix3d>& gradients) const {
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  double total = 0.0;
  for (int k = incident_offsets_[static_cast<std::size_t>(vertex)];
       k < incident_offsets_[static_cast<std::size_t>(vertex) + 1]; ++k) {
    const int f = incident_faces_[static_cast<std::size_t>(k)];
    sum += rest_areas_[f] * gradients[static_cast<std::size_t>(f)];
    total += rest_areas_[f];
  }
  return total > 0.0 ? Eigen::Matrix3d(sum / total) : Eigen::Matrix3d::Identity();
}

}  // namespace harmonia::detail
