#pragma once
// Internal: the deformation gradient of every source triangle from its rest pose to a new pose,
// as Sumner and Popovic (2004) define it: each triangle gets a fourth vertex along its normal,
// v4 = v1 + (e1 x e2) / sqrt(|e1 x e2|), so that the 3x3 map Q with Q [e1 e2 e3] = [e1' e2' e3']
// (e3 = v4 - v1) is defined and carries the normal's change too.

#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia::detail {

class DeformationGradients {
 public:
  explicit DeformationGradients(const Mesh& rest);

  // Q of every triangle (#F) for `pose` (#V by 3, the rest mesh's connectivity). A triangle of
  // zero rest area gets the identity.
  [[nodiscard]] std::vector<Eigen::Matrix3d> of(const Eigen::MatrixX3d& pose) const;

  // The rest-area-weighted mean of `gradients` over the triangles around `vertex`.
  [[nodiscard]] Eigen::Matrix3d mean_around(int vertex,
                                            const std::vector<Eigen::Matrix3d>& gradients) const;

 private:
  Eigen::MatrixX3i faces_;
  std::vector<Eigen::Matrix3d> rest_frame_inverse_;  // [e1 e2 e3]^-1 per face (zero: degenerate)
  Eigen::VectorXd rest_areas_;
  std::vector<int> incident_offsets_;  // CSR: the faces around each vertex
  std::vector<int> incident_faces_;
};

}  // namespace harmonia::detail
