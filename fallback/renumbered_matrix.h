#pragma once
// Internal: a symmetric matrix's lower triangle renumbered in an elimination order, so that a
// Cholesky factorization in the natural order reads it as stored (CHOLMOD permutes and transposes
// a matrix given with an ordering on every factorization), with the map that refreshes its values
// from the original's by a gather.

#include <vector>

#include <Eigen/SparseCore>

namespace harmonia::detail {

struct RenumberedLower {
  //! Lower triangle; row and column k are the unknown order[k]; rows sorted in each column.
  Eigen::SparseMatrix<double> matrix;
  //! Per stored entry of the original: its place in `matrix`, or -1 (entries above the diagonal).
  std::vector<int> slot;

  //! The values of `original` (the pattern renumbered) copied into `matrix`.
  void gather(const Eigen::SparseMatrix<double>& original);
};

//! `lower` (lower triangle read) renumbered in `order` (order[k]: the unknown eliminated k-th, a
//! permutation): a counting sort by the new column, then each column's few rows sorted.
[[nodiscard]] RenumberedLower renumber_lower(const Eigen::SparseMatrix<double>& lower,
                                             const std::vector<int>& order);

//! Rows of `b` taken into elimination order (row k: b's row order[k]), and back.
[[nodiscard]] Eigen::MatrixXd rows_in_order(const Eigen::MatrixXd& b, const std::vector<int>& order);
[[nodiscard]] Eigen::MatrixXd rows_from_order(const Eigen::MatrixXd& y,
                                              const std::vector<int>& order);

}  // namespace harmonia::detail
