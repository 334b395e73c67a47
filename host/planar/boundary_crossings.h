#pragma once
// Internal: boundary self-intersections of a UV layout whose boundary is already known.

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace harmonia::detail {

//! The number of pairs of non-adjacent edges of the closed polygon `loop` (vertex indices into
//! `uv`, the last joined to the first) that share a point: what count_boundary_self_intersections
//! (harmonia/metrics.h) counts for a disk whose boundary loop is `loop`, without searching the
//! faces for the boundary. Edges with a non-finite endpoint are left out.
[[nodiscard]] int count_loop_self_intersections(const Eigen::MatrixX2d& uv,
                                                const std::vector<int>& loop);

//! Two boundary edges of a layout that share a point (each as its two uv rows).
struct BoundaryCrossing {
  std::array<int, 2> first;
  std::array<int, 2> second;
};

//! The first pair of non-adjacent UV boundary edges (edges used by one face of uv_faces) that
//! share a point, in the order count_boundary_self_intersections examines them (deterministic),
//! or nothing when they count none.
[[nodiscard]] std::optional<BoundaryCrossing> first_boundary_crossing(const Eigen::MatrixX2d& uv,
                                                                      const Eigen::MatrixX3i& uv_faces);

//! The same, also counting two non-adjacent boundary edges as touching when they come within
//! `relative_clearance` times the diagonal of the boundary's bounding box of each other (but at
//! most a quarter of the shortest boundary edge): a layout whose boundary runs along itself at a
//! distance that rounding can close (the two sides of a slit laid on top of each other) is not
//! safe to move, scale or write (texture_atlas.cpp).
[[nodiscard]] std::optional<BoundaryCrossing> first_boundary_contact(const Eigen::MatrixX2d& uv,
                                                                     const Eigen::MatrixX3i& uv_faces,
                                                                     double relative_clearance);

}  // namespace harmonia::detail
