#pragma once
// Internal: the vertices of a mesh that lie at one point. Exporters split a vertex wherever its
// attributes change (a texture seam, a hard edge) and writers repeat every corner (STL): the
// surface is continuous there, its file is not. Cleanup's repair merges such vertices, and the
// texture atlas charts the surface they describe (harmonia/texture_atlas.h).

#include <vector>

#include <Eigen/Core>

namespace harmonia::detail {

// For each vertex, the smallest vertex within `tolerance` of it, transitively (0: equal positions
// only). Grid cells, found by sorting, keep it O(V log V): of size `tolerance`, but no finer than
// 2^-40 of the points' extent, so that a cell index always fits (a pair within the tolerance still
// lies in neighbouring cells). `vertices` are expected in the safe range (power_of_two_scale.h),
// so that the squared distances neither overflow nor underflow.
[[nodiscard]] std::vector<int> coincident_vertex_representatives(const Eigen::MatrixX3d& vertices,
                                                                 double tolerance);

}  // namespace harmonia::detail
