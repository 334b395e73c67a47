#pragma once
//! \file ring_weights.h
//! \brief Weights of the ring-based schemes of thesis chapter 4 for ONE flattened 1-ring: the centre
//! is the origin and `ring` lists the neighbours' planar positions in counter-clockwise order (see
//! flatten_ring). Each function returns one weight per neighbour, in ring order, such that the
//! discrete Laplacian at the centre is sum_k w_k (u_k - u_0). Exposed for the tests; laplacian()
//! calls them for every vertex.

#include <optional>
#include <span>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "harmonia/laplacian.h"
#include "harmonia/mesh.h"
#include "mesh/adjacency_pattern.h"

namespace harmonia::detail {

//! Mean value weights (4.25) on a planar ring: (tan(g_{k-1}/2) + tan(g_k/2)) / r_k with g_k the
//! angle at the origin between neighbours k and k+1 (open fans: only the wedges that exist).
[[nodiscard]] Eigen::VectorXd planar_mean_value_weights(std::span<const Eigen::Vector2d> ring, bool closed);

//! Holmes-Connell linearity-preserving weights (4.42-4.52): w = 1 + eps, with sum eps^2 minimal
//! subject to sum w_k x_k = 0 and sum w_k y_k = 0. A singular moment matrix (all neighbours on one
//! line) is inverted in the least-squares sense (pseudo-inverse), so the result is always finite.
[[nodiscard]] Eigen::VectorXd linear_precision_weights(std::span<const Eigen::Vector2d> ring);

//! Least squares weights: the five Taylor conditions (4.56-4.60) solved by a complete orthogonal
//! decomposition, i.e. the minimum-norm least-squares solution. For valence >= 6 (generic ring) the
//! conditions hold exactly and the weights are the least-norm ones; at valence 5 the solution is
//! unique; below 5 the conditions cannot all hold and the residual is minimized.
[[nodiscard]] Eigen::VectorXd least_squares_weights(std::span<const Eigen::Vector2d> ring);

//! Positive least squares weights: the program after (4.61), minimize the second-order residuals
//! (4.58-4.60) subject to the first-order conditions (4.56, 4.57) and w_k >= floor > 0, solved by a
//! primal active-set method (see the .cpp). Empty when no positive weights can satisfy the
//! first-order conditions (the origin is not strictly inside the ring: some angular gap >= pi).
[[nodiscard]] std::optional<Eigen::VectorXd> least_squares_positive_weights(
    std::span<const Eigen::Vector2d> ring);

//! Floater's shape-preserving weights on a closed ring: for each neighbour k the triangle
//! (q_k, q_l, q_{l+1}) containing the origin, the origin's barycentric coordinates in it, averaged
//! over k (weights sum to 1). Empty when some k has no such triangle (origin not inside the ring).
[[nodiscard]] std::optional<Eigen::VectorXd> shape_preserving_weights(std::span<const Eigen::Vector2d> ring);

//! True when every angular gap between consecutive neighbours of the closed ring is below pi, i.e.
//! the origin is strictly inside the convex hull and positive linear-precision weights exist.
[[nodiscard]] bool origin_strictly_inside(std::span<const Eigen::Vector2d> ring);

//! Adds the off-diagonal entries -w_ij of the ring scheme `scheme` (one of linear_precision,
//! least_squares, least_squares_positive, shape_preserving) into `pattern` for every vertex whose
//! row the scheme defines, and returns a flag per vertex for the rows it left to the caller (to be
//! filled with mean value weights): boundary rows of the positive schemes, rows where no positive
//! solution exists, and non-manifold vertices.
[[nodiscard]] std::vector<bool> assemble_ring_scheme(const Mesh& mesh, WeightScheme scheme,
                                                     AdjacencyPattern& pattern);

}  // namespace harmonia::detail
