#pragma once
// Internal: the per-triangle transformations of a frame, blended from the handles' along their
// harmonic fields (thesis 8.3 for one handle, 8.5 for several; harmonia/surface_editor.h).

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "harmonia/surface_editor.h"

namespace harmonia::detail {

// The linear part of each triangle's transformation: a rotation and a uniform scale.
struct TriangleSimilarities {
  std::vector<Eigen::Quaterniond> rotation;  // #F unit quaternions
  Eigen::VectorXd scale;                     // #F, > 0
};

// `face_fields`: #F by #handles, each handle's harmonic field averaged over the triangle's corners
// (its value at the barycentre), clamped to [0, 1]. One handle: slerp from the identity by the field
// value and the scale 1 + h (s - 1). Several: the quaternion components and the scale blended
// linearly with the identity taking the rest of the weight (1 - sum h_i), then renormalized; each
// handle's quaternion is taken with a non-negative real part. A blend whose quaternion vanishes
// (opposite half-turns cancelling) keeps the identity rotation.
void blend_triangle_transforms(const Eigen::MatrixXd& face_fields,
                               const std::vector<SimilarityTransform>& handle_transforms,
                               TriangleSimilarities& similarities);

}  // namespace harmonia::detail
