#include "mesh/adjacency_pattern.h"

#include <algorithm>
#include <string>

#include "harmonia/types.h"

namespace harmonia::detail {

void check_face_indices(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count, const char* who) {
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int index = faces(f, k);
      if (index < 0 || index >= vertex_count) {
        throw Error(Status::invalid_input,
                    std::string(who) + ": face " + std::to_string(f) + " references vertex " +
                        std::to_string(index) + " but there are only " +
                        std::to_string(vertex_count) + " vertices");
      }
    }
  }
}

AdjacencyPattern::AdjacencyPattern(const Eigen::MatrixX3i& faces, int vertex_count)
    : vertex_count_(vertex_count) {
  check_face_indices(faces, vertex_count, "sparse assembly");
  const auto face_count = static_cast<int>(faces.rows());

  // Vertex -> incident faces (counting sort, so faces stay in increasing order per vertex).
  std::vector<int> incidence_offsets(static_cast<std::size_t>(vertex_count) + 1, 0);
  for (int f = 0; f < face_count; ++f)
    for (int k = 0; k < 3; ++k) ++incidence_offsets[static_cast<std::size_t>(faces(f, k)) + 1];
  for (int v = 0; v < vertex_count; ++v) incidence_offsets[v + 1] += incidence_offsets[v];
  std::vector<int> incident(static_cast<std::size_t>(incidence_offsets.back()));
  {
    std::vector<int> cursor(incidence_offsets.begin(), incidence_offsets.end() - 1);
    for (int f = 0; f < face_count; ++f)
      for (int k = 0; k < 3; ++k) incident[static_cast<std::size_t>(cursor[faces(f, k)]++)] = f;
  }

  // Column c: c itself and the other corners of its faces, sorted and made unique.
  std::vector<int> offsets(static_cast<std::size_t>(vertex_count) + 1, 0);
  std::vector<int> rows;
  rows.reserve(static_cast<std::size_t>(incidence_offsets.back()) + static_cast<std::size_t>(vertex_count));
  std::vector<int> column;
  for (int c = 0; c < vertex_count; ++c) {
    column.clear();
    column.push_back(c);
    for (int slot = incidence_offsets[c]; slot < incidence_offsets[c + 1]; ++slot) {
      const int f = incident[static_cast<std::size_t>(slot)];
      for (int k = 0; k < 3; ++k)
        if (faces(f, k) != c) column.push_back(faces(f, k));
    }
    std::sort(column.begin(), column.end());
    column.erase(std::unique(column.begin(), column.end()), column.end());
    rows.insert(rows.end(), column.begin(), column.end());
    offsets[static_cast<std::size_t>(c) + 1] = static_cast<int>(rows.size());
  }

  matrix_.resize(vertex_count, vertex_count);
  matrix_.resizeNonZeros(static_cast<Eigen::Index>(rows.size()));
  std::copy(offsets.begin(), offsets.end(), matrix_.outerIndexPtr());
  std::copy(rows.begin(), rows.end(), matrix_.innerIndexPtr());
  std::fill(matrix_.valuePtr(), matrix_.valuePtr() + rows.size(), 0.0);
  offsets_ = matrix_.outerIndexPtr();
  rows_ = matrix_.innerIndexPtr();
  values_ = matrix_.valuePtr();
}

Eigen::Index AdjacencyPattern::position(int row, int col) const {
  const int* found = std::lower_bound(column_begin(col), column_end(col), row);
  // Callers only add entries of a shared face, so the entry always exists.
  return found - rows_;
}

void AdjacencyPattern::set_diagonal_from_rows() {
  std::vector<double> off_diagonal_sum(static_cast<std::size_t>(vertex_count_), 0.0);
  for (int c = 0; c < vertex_count_; ++c)
    for (int slot = offsets_[c]; slot < offsets_[c + 1]; ++slot)
      if (rows_[slot] != c) off_diagonal_sum[static_cast<std::size_t>(rows_[slot])] += values_[slot];
  for (int c = 0; c < vertex_count_; ++c) values_[position(c, c)] = -off_diagonal_sum[static_cast<std::size_t>(c)];
}

void AdjacencyPattern::clear_values() {
  std::fill(values_, values_ + matrix_.nonZeros(), 0.0);
}

Eigen::SparseMatrix<double> AdjacencyPattern::take_matrix() {
  offsets_ = rows_ = nullptr;
  values_ = nullptr;
  vertex_count_ = 0;
  return std::move(matrix_);
}

}  // namespace harmonia::detail
