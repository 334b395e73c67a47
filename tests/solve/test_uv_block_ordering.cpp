// The elimination order of [u; v] systems coupled only at a few unknowns (solve/uv_block_ordering.h).
#include <gtest/gtest.h>

#include <vector>

#include <Eigen/SparseCore>

#include "solve/uv_block_ordering.h"

namespace harmonia {
namespace {

// Four vertices, all free: u rows 0-3, v rows 4-7, each block a path; u of vertex 1 meets v of
// vertex 2 (stored in the lower triangle only).
Eigen::SparseMatrix<double> coupled_paths() {
  std::vector<Eigen::Triplet<double>> entries;
  for (int block : {0, 4}) {
    for (int k = 0; k < 4; ++k) entries.emplace_back(block + k, block + k, 2.0);
    for (int k = 0; k < 3; ++k) entries.emplace_back(block + k + 1, block + k, -1.0);
  }
  entries.emplace_back(6, 1, 0.5);
  Eigen::SparseMatrix<double> matrix(8, 8);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

TEST(UvBlockOrdering, UFirstThenTheVThatNoUTouchesThenTheOthers) {
  const std::vector<int> free_index = {0, 1, 2, 3, 4, 5, 6, 7};
  const std::vector<int> ordering =
      detail::uv_block_ordering({3, 1, 0, 2}, free_index, coupled_paths());
  EXPECT_EQ(ordering, (std::vector<int>{3, 1, 0, 2, 7, 5, 4, 6}));
}

TEST(UvBlockOrdering, UpperStorageAndPinnedVerticesAreHandled) {
  // Vertex 0 pinned: rows renumbered, u of 1-3 are rows 0-2 and v of 1-3 rows 3-5; u of
  // vertex 3 meets v of vertex 1, stored above the diagonal this time.
  const std::vector<int> free_index = {-1, 0, 1, 2, -1, 3, 4, 5};
  std::vector<Eigen::Triplet<double>> entries;
  for (int k = 0; k < 6; ++k) entries.emplace_back(k, k, 2.0);
  entries.emplace_back(2, 3, 0.5);
  Eigen::SparseMatrix<double> matrix(6, 6);
  matrix.setFromTriplets(entries.begin(), entries.end());
  const std::vector<int> ordering = detail::uv_block_ordering({2, 0, 3, 1}, free_index, matrix);
  EXPECT_EQ(ordering, (std::vector<int>{1, 2, 0, 4, 5, 3}));
}

TEST(UvBlockOrdering, AnOrderingOfTheWrongSizeGivesNone) {
  const std::vector<int> free_index = {0, 1, 2, 3, 4, 5, 6, 7};
  EXPECT_TRUE(detail::uv_block_ordering({0, 1, 2}, free_index, coupled_paths()).empty());
}

}  // namespace
}  // namespace harmonia
