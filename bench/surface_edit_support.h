#pragma once
// Shared by bench_surface_editor and corpus_edit_benchmark: the edit both of them time. It is
// chosen from the geometry alone, so that it applies to any closed mesh, and midpoint subdivision
// (bench_support.h, scaled_mesh) leaves its regions where they are: every size of a mesh gets the
// same edit.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <numbers>
#include <vector>

#include "harmonia/edit_file.h"
#include "harmonia/mesh.h"
#include "harmonia/surface_editor.h"

namespace harmonia::bench {

//! Share of the height range taken by the fixed slab (at the bottom) and by the handle (at the
//! top).
constexpr double kEditSlabShare = 0.10;
//! The handle's turn about the horizontal x axis through its centroid.
constexpr double kEditRotationDegrees = 45.0;
//! The handle's lift, as a share of the height range.
constexpr double kEditLiftShare = 0.05;

//! The benchmark edit of `mesh`, with y as the height (the corpus meshes are y up): the vertices in
//! the lowest 10 % of the height range stay fixed, those in the highest 10 % are one handle, turned
//! 45 degrees about the x axis through the handle's centroid and lifted by 5 % of the height range.
//! The region of interest is the whole mesh.
inline EditDescription geometric_edit(const Mesh& mesh) {
  const Eigen::VectorXd height = mesh.vertices.col(1);
  const double lowest = height.minCoeff();
  const double highest = height.maxCoeff();
  const double range = highest - lowest;

  EditDescription edit;
  edit.description =
      "lowest 10% of the height fixed; highest 10% turned 45 degrees about x "
      "through its centroid and lifted by 5% of the height";
  std::vector<int> handle;
  Eigen::Vector3d handle_centroid = Eigen::Vector3d::Zero();
  for (int vertex = 0; vertex < mesh.vertex_count(); ++vertex) {
    if (height(vertex) <= lowest + kEditSlabShare * range) {
      edit.regions.fixed.push_back(vertex);
    } else if (height(vertex) >= highest - kEditSlabShare * range) {
      handle.push_back(vertex);
      handle_centroid += mesh.vertices.row(vertex).transpose();
    }
  }
  if (!handle.empty()) handle_centroid /= static_cast<double>(handle.size());

  SimilarityTransform turn_and_lift;
  turn_and_lift.rotation =
      Eigen::AngleAxisd(kEditRotationDegrees * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX());
  turn_and_lift.center = handle_centroid;
  turn_and_lift.translation = Eigen::Vector3d(0.0, kEditLiftShare * range, 0.0);
  edit.regions.handles.push_back(std::move(handle));
  edit.transforms.push_back(turn_and_lift);
  return edit;
}

//! Frame `frame` (1 .. frames) of the edit played from the rest pose, as `harmonia deform
//! --frames` plays it: each handle's transformation partial(frame / frames).
inline std::vector<SimilarityTransform> frame_transforms(
    const std::vector<SimilarityTransform>& transforms, int frame, int frames) {
  const double fraction = static_cast<double>(frame) / static_cast<double>(frames);
  std::vector<SimilarityTransform> partial;
  partial.reserve(transforms.size());
  for (const SimilarityTransform& transform : transforms) {
    partial.push_back(transform.partial(fraction));
  }
  return partial;
}

}  // namespace harmonia::bench
