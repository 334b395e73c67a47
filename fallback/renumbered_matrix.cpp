#include "fallback/renumbered_matrix.h"

#include <algorithm>

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
  struct Entry {
    int row, column, source;
  };
  std::vector<Entry> entries;
  entries.reserve(static_cast<std::size_t>(lower.nonZeros()));
  for (int column = 0; column < size; ++column)
    for (int k = outer[column]; k < outer[column + 1]; ++k) {
      if (inner[k] < column) continue;
      const int a = position[static_cast<std::size_t>(inner[k])];
      const int b = position[static_cast<std::size_t>(column)];
      entries.push_back({std::max(a, b), std::min(a, b), k});
    }
  const auto bucket = [size](const std::vector<Entry>& input, bool by_column) {
    std::vector<int> start(static_cast<std::size_t>(size) + 1, 0);
    for (const Entry& e : input) ++start[static_cast<std::size_t>(by_column ? e.column : e.row) + 1];
    for (int k = 0; k < size; ++k)
      start[static_cast<std::size_t>(k) + 1] += start[static_cast<std::size_t>(k)];
    std::vector<Entry> output(input.size());
    for (const Entry& e : input)
      output[static_cast<std::size_t>(
          start[static_cast<std::size_t>(by_column ? e.column : e.row)]++)] = e;
    return output;
  };
  entries = bucket(bucket(entries, false), true);
  RenumberedLower result;
  result.matrix.resize(size, size);
  result.matrix.resizeNonZeros(static_cast<Eigen::Index>(entries.size()));
  int* result_outer = result.matrix.outerIndexPtr();
  int* result_inner = result.matrix.innerIndexPtr();
  std::fill(result_outer, result_outer + size + 1, 0);
  result.slot.assign(static_cast<std::size_t>(lower.nonZeros()), -1);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    ++result_outer[entries[k].column + 1];
    result_inner[k] = entries[k].row;
    result.slot[static_cast<std::size_t>(entries[k].source)] = static_cast<int>(k);
  }
  for (int k = 0; k < size; ++k) result_outer[k + 1] += result_outer[k];
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
