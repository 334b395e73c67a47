#include "fallback/renumbered_matrix.h"

#include <algorithm>
#include <tuple>
#include <utility>

namespace harmonia::detail {

void RenumberedLower::gather(const Eigen::SparseMatrix<double>& original) {
  const double* values = original.valuePtr();
  double* target = matrix.valuePtr();
  for (std::size_t k = 0; k < slot.size(); ++k)
    if (slot[k] >= 0) target[slot[k]] = values[k];
}

RenumberedLower renumber_lower(const Eigen::SparseMatrix<double>& lower,
                               const std::vector<int>& order) {
  const auto size = static_cast<int>(lower.rows());
  std::vector<int> position(static_cast<std::size_t>(size));
  for (int k = 0; k < size; ++k) position[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = k;
  const int* outer = lower.outerIndexPtr();
  const int* inner = lower.innerIndexPtr();
  // Calls visit(new column, new row, source) for each entry of the lower triangle.
  const auto for_each_entry = [&](auto&& visit) {
    for (int column = 0; column < size; ++column) {
      const int b = position[static_cast<std::size_t>(column)];
      for (int k = outer[column]; k < outer[column + 1]; ++k) {
        if (inner[k] < column) continue;
        const int a = position[static_cast<std::size_t>(inner[k])];
        visit(std::min(a, b), std::max(a, b), k);
      }
    }
  };
  RenumberedLower result;
  result.matrix.resize(size, size);
  int* result_outer = result.matrix.outerIndexPtr();
  std::fill(result_outer, result_outer + size + 1, 0);
  // One counting sort by the new column; a column's rows (a few for a mesh) are then sorted in
  // place, carrying their sources along.
  for_each_entry([&](int column, int, int) { ++result_outer[column + 1]; });
  for (int k = 0; k < size; ++k) result_outer[k + 1] += result_outer[k];
  result.matrix.resizeNonZeros(result_outer[size]);
  int* result_inner = result.matrix.innerIndexPtr();
  std::vector<int> source(static_cast<std::size_t>(result_outer[size]));
  std::vector<int> next(result_outer, result_outer + size);
  for_each_entry([&](int column, int row, int k) {
    const int slot = next[static_cast<std::size_t>(column)]++;
    result_inner[slot] = row;
    source[static_cast<std::size_t>(slot)] = k;
  });
  std::vector<std::pair<int, int>> column_entries;
  for (int column = 0; column < size; ++column) {
    const int begin = result_outer[column], end = result_outer[column + 1];
    if (std::is_sorted(result_inner + begin, result_inner + end)) continue;
    column_entries.clear();
    for (int slot = begin; slot < end; ++slot)
      column_entries.emplace_back(result_inner[slot], source[static_cast<std::size_t>(slot)]);
    std::sort(column_entries.begin(), column_entries.end());
    for (int slot = begin; slot < end; ++slot)
      std::tie(result_inner[slot], source[static_cast<std::size_t>(slot)]) =
          column_entries[static_cast<std::size_t>(slot - begin)];
  }
  result.slot.assign(static_cast<std::size_t>(lower.nonZeros()), -1);
  for (std::size_t slot = 0; slot < source.size(); ++slot)
    result.slot[static_cast<std::size_t>(source[slot])] = static_cast<int>(slot);
  result.gather(lower);
  return result;
}

Eigen::MatrixXd rows_in_order(const Eigen::MatrixXd& b, const std::vector<int>& order) {
  Eigen::MatrixXd y(b.rows(), b.cols());
  for (std::size_t k = 0; k < order.size(); ++k)
    y.row(static_cast<Eigen::Index>(k)) = b.row(order[k]);
  return y;
}

Eigen::MatrixXd rows_from_order(const Eigen::MatrixXd& y, const std::vector<int>& order) {
  Eigen::MatrixXd b(y.rows(), y.cols());
  for (std::size_t k = 0; k < order.size(); ++k)
    b.row(order[k]) = y.row(static_cast<Eigen::Index>(k));
  return b;
}

}  // namespace harmonia::detail
