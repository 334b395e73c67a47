#pragma once
//! \file adjacency_pattern.h
//! \brief The sparsity pattern shared by every vertex operator (thesis chapter 9: sparse matrices
//! assembled straight from the vertex and face lists): column c holds the diagonal and the vertices
//! that share a face with c, sorted. Values are accumulated in place by a binary search inside the
//! short column, so assembly is O(F) with no triplet sort and the summation order is the order of
//! the calls (deterministic).

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace harmonia::detail {

class AdjacencyPattern {
 public:
  //! Builds the pattern of the #V by #V vertex adjacency (plus diagonal). Throws harmonia::Error
  //! (invalid_input) naming the face when an index is outside [0, vertex_count).
  AdjacencyPattern(const Eigen::MatrixX3i& faces, int vertex_count);
  AdjacencyPattern(const AdjacencyPattern&) = delete;  // holds pointers into its own storage
  AdjacencyPattern& operator=(const AdjacencyPattern&) = delete;

  [[nodiscard]] int vertex_count() const { return vertex_count_; }

  //! Adds `value` to entry (row, col); (row, col) must be in the pattern (a shared face or row == col).
  void add(int row, int col, double value) { values_[position(row, col)] += value; }

  //! Sets every diagonal entry to minus the sum of the off-diagonal entries of its row: the PSD
  //! convention L(i,i) = sum_j w_ij when off-diagonals hold -w_ij. Exact zero row sums in the sense
  //! that the diagonal is computed from the very numbers stored in the row.
  void set_diagonal_from_rows();

  //! Zeroes all values, keeping the pattern (to assemble another operator of the same mesh).
  void clear_values();

  //! The assembled #V by #V column-major compressed matrix; the pattern is left empty (moved out).
  [[nodiscard]] Eigen::SparseMatrix<double> take_matrix();

  //! Sorted row indices of column `col` (the diagonal and the neighbours) as a [begin, end) range.
  [[nodiscard]] const int* column_begin(int col) const { return rows_ + offsets_[col]; }
  [[nodiscard]] const int* column_end(int col) const { return rows_ + offsets_[col + 1]; }

 private:
  [[nodiscard]] Eigen::Index position(int row, int col) const;

  int vertex_count_ = 0;
  // The pattern lives in the compressed storage of the result itself, so nothing is copied at the
  // end; the raw pointers below point into it.
  Eigen::SparseMatrix<double> matrix_;
  const int* offsets_ = nullptr;  // #V + 1 column starts
  const int* rows_ = nullptr;     // sorted row indices of each column, diagonal included
  double* values_ = nullptr;
};

//! Throws harmonia::Error(invalid_input) naming the first face with an index outside
//! [0, vertex_count); `who` names the calling function in the message.
void check_face_indices(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count, const char* who);

}  // namespace harmonia::detail
