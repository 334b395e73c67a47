#pragma once
// Internal: the triangles of a posed surface that are folded onto their neighbours, the count of
// "flipped" triangles that deformation transfer and the deformation metrics report. A pose of a
// closed surface has no reference orientation per triangle, so a triangle counts as folded when
// its normal points away from its surroundings: its unit normal makes more than 90 degrees with
// the sum of its edge neighbours' unit normals. A sharp tip can be folded at rest already; what a
// deformation adds is the count folded in the pose that were not folded at rest.

#include <vector>

#include <Eigen/Core>

namespace harmonia::detail {

// The triangles sharing an edge with each triangle, in increasing order.
[[nodiscard]] std::vector<std::vector<int>> edge_neighbours(const Eigen::MatrixX3i& faces);

// Per triangle: folded (1) or not (0) at `positions`. A triangle of zero area counts as folded; one
// without neighbours, or whose neighbours' normals cancel, does not.
[[nodiscard]] std::vector<char> folded_triangles(const Eigen::MatrixX3i& faces,
                                                 const std::vector<std::vector<int>>& neighbours,
                                                 const Eigen::MatrixX3d& positions);

// The triangles folded at `posed` that are not folded at `rest`.
[[nodiscard]] int triangles_folded_by_pose(const Eigen::MatrixX3i& faces,
                                           const std::vector<std::vector<int>>& neighbours,
                                           const Eigen::MatrixX3d& rest, const Eigen::MatrixX3d& posed);

}  // namespace harmonia::detail
