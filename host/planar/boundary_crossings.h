#pragma once
// Internal: boundary self-intersections of a UV layout whose boundary is already known.

#include <vector>

#include <Eigen/Core>

namespace harmonia::detail {

//! The number of pairs of non-adjacent edges of the closed polygon `loop` (vertex indices into
//! `uv`, the last joined to the first) that share a point: what count_boundary_self_intersections
//! (harmonia/metrics.h) counts for a disk whose boundary loop is `loop`, without searching the
//! faces for the boundary. Edges with a non-finite endpoint are left out.
[[nodiscard]] int count_loop_self_intersections(const Eigen::MatrixX2d& uv,
                                                const std::vector<int>& loop);

}  // namespace harmonia::detail
