#include "deform/triangle_transforms.h"

#include "deform/two_way_split.h"

#include <cmath>

#include <Eigen/Geometry>

namespace harmonia::detail {
namespace {

// The quaternion of the same rotation with a non-negative real part: q and -q are one rotation, and
// blending from the identity should take the shorter way.
Eigen::Quaterniond shorter_way(const Eigen::Quaterniond& rotation) {
  const Eigen::Quaterniond unit = rotation.normalized();
  return unit.w() < 0.0 ? Eigen::Quaterniond(-unit.coeffs()) : unit;
}

// One handle: the rotation by the fraction h of the handle's angle about its axis (slerp from the
// identity), written as axis and angle so that a triangle costs one sine and one cosine.
void blend_one_handle(const Eigen::Ref<const Eigen::VectorXd>& field,
                      const SimilarityTransform& handle, TriangleSimilarities& similarities) {
  const Eigen::Quaterniond rotation = shorter_way(handle.rotation);
  const double half_angle = std::atan2(rotation.vec().norm(), rotation.w());  // in [0, pi/2]
  const Eigen::Vector3d axis =
      half_angle > 0.0 ? Eigen::Vector3d(rotation.vec().normalized()) : Eigen::Vector3d::UnitZ();
  split_two_ways(field.size(), [&](int, Eigen::Index begin, Eigen::Index end) {
  for (Eigen::Index f = begin; f < end; ++f) {
    const double h = field[f];
    const double sine = std::sin(h * half_angle);
    similarities.rotation[static_cast<std::size_t>(f)] =
        Eigen::Quaterniond(std::cos(h * half_angle), sine * axis.x(), sine * axis.y(), sine * axis.z());
    similarities.scale[f] = 1.0 + h * (handle.scale - 1.0);
  }
  });
}

// Several handles: harmonic interpolation of the quaternion components and of the scale (8.5).
void blend_components(const Eigen::MatrixXd& face_fields,
                      const std::vector<SimilarityTransform>& handles,
                      TriangleSimilarities& similarities) {
  const auto handle_count = static_cast<Eigen::Index>(handles.size());
  Eigen::Matrix4Xd quaternions(4, handle_count);  // columns (x, y, z, w)
  Eigen::VectorXd scales(handle_count);
  for (Eigen::Index i = 0; i < handle_count; ++i) {
    quaternions.col(i) = shorter_way(handles[static_cast<std::size_t>(i)].rotation).coeffs();
    scales[i] = handles[static_cast<std::size_t>(i)].scale;
  }
  const Eigen::Vector4d identity = Eigen::Quaterniond::Identity().coeffs();
  split_two_ways(face_fields.rows(), [&](int, Eigen::Index begin, Eigen::Index end) {
  for (Eigen::Index f = begin; f < end; ++f) {
    Eigen::Vector4d components = Eigen::Vector4d::Zero();
    double weight_sum = 0.0, scale = 0.0;
    for (Eigen::Index i = 0; i < handle_count; ++i) {
      const double weight = face_fields(f, i);
      components += weight * quaternions.col(i);
      scale += weight * scales[i];
      weight_sum += weight;
    }
    const double rest = 1.0 - weight_sum;  // the identity's share: fixed set and outside
    components += rest * identity;
    const double length = components.norm();
    similarities.rotation[static_cast<std::size_t>(f)] =
        length > 0.0 ? Eigen::Quaterniond(Eigen::Vector4d(components / length))
                     : Eigen::Quaterniond::Identity();
    similarities.scale[f] = scale + rest;
  }
  });
}

}  // namespace

void blend_triangle_transforms(const Eigen::MatrixXd& face_fields,
                               const std::vector<SimilarityTransform>& handle_transforms,
                               TriangleSimilarities& similarities) {
  similarities.rotation.resize(static_cast<std::size_t>(face_fields.rows()));
  similarities.scale.resize(face_fields.rows());
  if (handle_transforms.size() == 1) {
    blend_one_handle(face_fields.col(0), handle_transforms[0], similarities);
  } else {
    blend_components(face_fields, handle_transforms, similarities);
  }
}

}  // namespace harmonia::detail
