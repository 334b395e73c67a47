#include "host/detail/adjacency_pattern.h"

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
  offsets_.assign(static_cast<std::size_t>(vertex_count) + 1, 0);
  rows_.reserve(static_cast<std::size_t>(incidence_offsets.back()) + static_cast<std::size_t>(vertex_count));
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
    rows_.insert(rows_.end(), column.begin(), column.end());
    offsets_[static_cast<std::size_t>(c) + 1] = static_cast<int>(rows_.size());
  }
  values_.assign(rows_.size(), 0.0);
}

int AdjacencyPattern::position(int row, int col) const {
  const int* begin = column_begin(col);
  const int* end = column_end(col);
  const int* found = std::lower_bound(begin, end, row);
  // Callers only add entries of a shared face, so the entry always exists.
  return static_cast<int>(found - rows_.data());
}

void AdjacencyPattern::set_diagonal_from_rows() {
  std::vector<double> off_diagonal_sum(static_cast<std::size_t>(vertex_count_), 0.0);
  for (int c = 0; c < vertex_count_; ++c)
    for (int slot = offsets_[c]; slot < offsets_[c + 1]; ++slot)
      if (rows_[static_cast<std::size_t>(slot)] != c)
        off_diagonal_sum[static_cast<std::size_t>(rows_[static_cast<std::size_t>(slot)])] +=
            values_[static_cast<std::size_t>(slot)];
  for (int c = 0; c < vertex_count_; ++c) values_[position(c, c)] = -off_diagonal_sum[c];
}

void AdjacencyPattern::clear_values() { std::fill(values_.begin(), values_.end(), 0.0); }

Eigen::SparseMatrix<double> AdjacencyPattern::matrix() const {
  const Eigen::Map<const Eigen::SparseMatrix<double>> view(
      vertex_count_, vertex_count_, static_cast<Eigen::Index>(rows_.size()), offsets_.data(),
      rows_.data(), values_.data());
  return Eigen::SparseMatrix<double>(view);
}

}  // namespace harmonia::detail
