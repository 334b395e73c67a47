#pragma once
//! \file deformation_metrics.h
//! \brief How well a deformed mesh keeps the local shape of its rest pose (surface editing and
//! deformation transfer): the deviation of each triangle's deformation gradient from a
//! similarity, and the triangles turned over.

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

struct DeformationMetrics {
  int faces = 0;
  //! Per triangle, the relative distance of its deformation gradient J (the linear map of the rest
  //! triangle's plane onto the deformed triangle's) from the nearest similarity (rotation times
  //! uniform scale, no mirror): min |J - s R|_F / |J|_F = |sigma_1 - sigma_2| / sqrt(2 (sigma_1^2 +
  //! sigma_2^2)) with sigma_2 negative for a mirrored triangle. 0: the triangle is only turned and
  //! scaled; 1/sqrt(2): collapsed onto a line. Mean and largest over the triangles of non-zero
  //! rest and deformed area.
  double similarity_deviation_mean = 0.0;
  double similarity_deviation_max = 0.0;
  //! Triangles whose normal makes more than 90 degrees with their rest normal.
  int turned_faces = 0;
  //! Triangles folded onto their neighbours in the deformed pose (unit normal more than 90 degrees
  //! from the sum of the edge neighbours' unit normals, or zero area) that were not at rest:
  //! deformation transfer's count (TransferResult::folded_triangles), here for any deformation.
  int folded_faces = 0;
  //! Triangles of zero area after the deformation (exactly zero cross product).
  int degenerate_faces = 0;
};

//! `deformed`: #V by 3 positions of `rest`'s vertices. Throws harmonia::Error(invalid_input) when
//! the row count differs.
[[nodiscard]] DeformationMetrics deformation_metrics(const Mesh& rest, const Eigen::MatrixX3d& deformed);

}  // namespace harmonia
