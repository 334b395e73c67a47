#pragma once
// Internal: the elimination order of a [u; v] system in which u and v meet only at a few unknowns
// (LSCM and the least-squares reconstruction from angles, where the area term couples them at
// boundary vertices, and LSCM around zero-area triangles).

#include <vector>

#include <Eigen/SparseCore>

namespace harmonia::detail {

// `free_index` has 2V entries, u of every vertex then v of every vertex, each the row of that
// unknown in `matrix` or -1 where it is pinned; the free u come first in `matrix`. Returns the
// rows of `matrix` in elimination order: every free u along `vertex_ordering`, then the free v
// that no u touches, then the v that some u touches, each along `vertex_ordering`. Eliminating
// the u's couples those last v's all with one another (through the inverse of the u block), so
// they must close the order: scattered among the others they would fill the whole v factor
// (LSCM on a 96K-face outline with 1,732 boundary vertices: 4.1 s instead of 0.3 s). Empty when
// `vertex_ordering` does not cover the V vertices.
[[nodiscard]] std::vector<int> uv_block_ordering(const std::vector<int>& vertex_ordering,
                                                 const std::vector<int>& free_index,
                                                 const Eigen::SparseMatrix<double>& matrix);

}  // namespace harmonia::detail
