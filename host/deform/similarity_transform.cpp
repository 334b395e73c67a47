// harmonia::SimilarityTransform (harmonia/surface_editor.h).

#include "harmonia/surface_editor.h"

namespace harmonia {

Eigen::Vector3d SimilarityTransform::apply(const Eigen::Vector3d& point) const {
  return center + rotation.normalized() * (scale * (point - center)) + translation;
}

SimilarityTransform SimilarityTransform::partial(double t) const {
  Eigen::Quaterniond unit = rotation.normalized();
  if (unit.w() < 0.0) unit.coeffs() = -unit.coeffs();  // the shorter way from the identity
  SimilarityTransform part;
  part.rotation = Eigen::Quaterniond::Identity().slerp(t, unit);
  part.center = center;
  part.scale = 1.0 + t * (scale - 1.0);
  part.translation = t * translation;
  return part;
}

}  // namespace harmonia
