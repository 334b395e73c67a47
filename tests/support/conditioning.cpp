#include "support/conditioning.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/SparseCholesky>

namespace harmonia::testing {

SpdSpectrum spd_spectrum(const Eigen::SparseMatrix<double>& matrix) {
  SpdSpectrum spectrum;
  Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(matrix.rows());
  for (Eigen::Index column = 0; column < matrix.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(matrix, column); entry; ++entry)
      row_sums(entry.row()) += std::abs(entry.value());
  spectrum.largest = row_sums.maxCoeff();

  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(matrix);
  if (factor.info() != Eigen::Success || (factor.vectorD().array() <= 0.0).any())
    throw std::runtime_error("spd_spectrum: the matrix is not positive definite");
  // A fixed start that is not orthogonal to any eigenvector in practice.
  Eigen::VectorXd iterate(matrix.rows());
  for (Eigen::Index i = 0; i < iterate.size(); ++i)
    iterate(i) = 1.0 + 0.5 * std::sin(0.7 * static_cast<double>(i));
  iterate.normalize();
  double previous = std::numeric_limits<double>::infinity();
  for (int step = 0; step < 300; ++step) {
    Eigen::VectorXd next = factor.solve(iterate);
    // Rayleigh quotient of the new iterate: x^T A x / x^T x with A x = iterate.
    const double quotient = next.dot(iterate) / next.squaredNorm();
    iterate = next.normalized();
    spectrum.smallest = quotient;
    if (std::abs(previous - quotient) <= 1e-6 * quotient) break;
    previous = quotient;
  }
  return spectrum;
}

Eigen::SparseMatrix<double> without_rows_and_columns(const Eigen::SparseMatrix<double>& matrix,
                                                     const std::vector<int>& removed) {
  std::vector<int> position(static_cast<std::size_t>(matrix.rows()), 0);
  for (const int index : removed) position[static_cast<std::size_t>(index)] = -1;
  int kept = 0;
  for (int& p : position) p = p < 0 ? -1 : kept++;
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index column = 0; column < matrix.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(matrix, column); entry; ++entry) {
      const int row = position[static_cast<std::size_t>(entry.row())];
      const int col = position[static_cast<std::size_t>(entry.col())];
      if (row >= 0 && col >= 0) entries.emplace_back(row, col, entry.value());
    }
  Eigen::SparseMatrix<double> result(kept, kept);
  result.setFromTriplets(entries.begin(), entries.end());
  return result;
}

Eigen::VectorXd without_entries(const Eigen::VectorXd& vector, const std::vector<int>& removed) {
  std::vector<char> drop(static_cast<std::size_t>(vector.size()), 0);
  for (const int index : removed) drop[static_cast<std::size_t>(index)] = 1;
  Eigen::VectorXd result(vector.size() - static_cast<Eigen::Index>(removed.size()));
  Eigen::Index kept = 0;
  for (Eigen::Index i = 0; i < vector.size(); ++i)
    if (!drop[static_cast<std::size_t>(i)]) result(kept++) = vector(i);
  return result;
}

double product_rounding_bound(const Eigen::SparseMatrix<double>& matrix,
                              const Eigen::VectorXd& x) {
  Eigen::VectorXd magnitude = Eigen::VectorXd::Zero(matrix.rows());
  Eigen::VectorXi row_entries = Eigen::VectorXi::Zero(matrix.rows());
  for (Eigen::Index column = 0; column < matrix.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(matrix, column); entry; ++entry) {
      magnitude(entry.row()) += std::abs(entry.value() * x(entry.col()));
      ++row_entries(entry.row());
    }
  const double k = static_cast<double>(std::max(1, row_entries.maxCoeff()));
  return k * std::numeric_limits<double>::epsilon() * magnitude.norm();
}

}  // namespace harmonia::testing
