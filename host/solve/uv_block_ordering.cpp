#include "solve/uv_block_ordering.h"

#include <algorithm>

namespace harmonia::detail {

std::vector<int> uv_block_ordering(const std::vector<int>& vertex_ordering,
                                   const std::vector<int>& free_index,
                                   const Eigen::SparseMatrix<double>& matrix) {
  const auto vertex_count = static_cast<int>(free_index.size() / 2);
  if (vertex_ordering.size() != static_cast<std::size_t>(vertex_count)) return {};
  const auto free_u = static_cast<int>(std::count_if(
      free_index.begin(), free_index.begin() + vertex_count, [](int row) { return row >= 0; }));

  // The v rows that share an entry with a u row (either triangle of the matrix may be stored).
  std::vector<bool> touched(static_cast<std::size_t>(matrix.rows()), false);
  for (int column = 0; column < matrix.outerSize(); ++column) {
    for (Eigen::SparseMatrix<double>::InnerIterator entry(matrix, column); entry; ++entry) {
      const auto row = static_cast<int>(entry.row());
      if ((row < free_u) == (column < free_u)) continue;
      touched[static_cast<std::size_t>(std::max(row, column))] = true;
    }
  }

  std::vector<int> ordering;
  ordering.reserve(static_cast<std::size_t>(matrix.rows()));
  for (const int vertex : vertex_ordering)
    if (free_index[static_cast<std::size_t>(vertex)] >= 0)
      ordering.push_back(free_index[static_cast<std::size_t>(vertex)]);
  for (const bool last : {false, true}) {
    for (const int vertex : vertex_ordering) {
      const int row = free_index[static_cast<std::size_t>(vertex_count + vertex)];
      if (row >= 0 && touched[static_cast<std::size_t>(row)] == last) ordering.push_back(row);
    }
  }
  return ordering;
}

}  // namespace harmonia::detail
