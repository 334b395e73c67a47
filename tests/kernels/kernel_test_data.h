#pragma once
// Test data for the Vulkan kernel tests: random sparse matrices (with empty rows, odd sizes,
// short or long rows) and mesh Laplacians from procedural meshes, plus the CPU reference (the
// Eigen twin of every kernel is CpuBackend).

#include <Eigen/SparseCore>
#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

#include "backend/backend.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"

namespace harmonia::testing {

using detail::RowMajorSparse;

//! rows x cols with row lengths uniform in [0, 2 * mean_row_length] (so some rows are empty),
//! values uniform in [-1, 1]; fixed seed.
inline RowMajorSparse random_sparse(int rows, int cols, int mean_row_length, std::uint32_t seed) {
  std::mt19937 generator(seed);
  std::uniform_int_distribution<int> length(0, 2 * mean_row_length);
  std::uniform_int_distribution<int> column(0, cols - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> entries;
  for (int row = 0; row < rows; ++row) {
    const int count = std::min(length(generator), cols);
    for (int k = 0; k < count; ++k) entries.emplace_back(row, column(generator), value(generator));
  }
  RowMajorSparse matrix(rows, cols);
  matrix.setFromTriplets(entries.begin(), entries.end());
  matrix.makeCompressed();
  return matrix;
}

//! The cotangent Laplacian of hemisphere(rings) (PSD) made positive definite: L + shift I.
inline RowMajorSparse hemisphere_laplacian(int rings, double shift = 1e-3) {
  Eigen::SparseMatrix<double> l = laplacian(hemisphere(rings), WeightScheme::cotangent);
  Eigen::SparseMatrix<double> identity(l.rows(), l.cols());
  identity.setIdentity();
  RowMajorSparse result = l + shift * identity;
  result.makeCompressed();
  return result;
}

//! rows x cols values uniform in [-1, 1]; fixed seed.
inline Eigen::MatrixXd random_block(int rows, int cols, std::uint32_t seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Eigen::MatrixXd block(rows, cols);
  for (Eigen::Index k = 0; k < block.size(); ++k) block.data()[k] = value(generator);
  return block;
}

}  // namespace harmonia::testing
