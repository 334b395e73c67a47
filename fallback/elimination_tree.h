#pragma once
// Internal: the elimination tree of a symmetric sparse matrix and its postorders, for the
// orderings handed to the supernodal factorizations (which need every subtree's columns
// contiguous) and the split of a factorization on two threads (subtree_parallel_cholesky.h).

#include <vector>

#include <Eigen/SparseCore>

namespace harmonia::detail {

//! The elimination tree of the symmetric matrix whose lower triangle is `lower`, renumbered by
//! `position` (row r of `lower` is row position[r]; identity when empty): parent[k] > k, or -1
//! for a root.
[[nodiscard]] std::vector<int> elimination_tree(const Eigen::SparseMatrix<double>& lower,
                                                const std::vector<int>& position = {});

//! A postorder of the forest `parent` (the parent of each node, or -1 for a root; an elimination
//! tree or any other): post[k] is the node
//! visited k-th, every subtree a contiguous range ending at its root; the children of a node and
//! the roots in increasing order.
[[nodiscard]] std::vector<int> postorder(const std::vector<int>& parent);

}  // namespace harmonia::detail
