// Elimination trees and postorders (fallback/elimination_tree.h) against the pattern of a
// factor computed by Eigen, and postordered_ordering's promise: the same fill, every subtree's
// rows contiguous.
#include <random>
#include <vector>

#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include "fallback/direct_solvers.h"
#include "fallback/elimination_tree.h"

namespace harmonia {
namespace {

// The 5-point Laplacian of a side x side grid plus the identity (SPD), its vertices numbered in
// a random order: a matrix whose elimination tree is neither a path nor trivial.
Eigen::SparseMatrix<double> shuffled_grid(int side, unsigned seed) {
  const int size = side * side;
  std::vector<int> label(static_cast<std::size_t>(size));
  for (int k = 0; k < size; ++k) label[static_cast<std::size_t>(k)] = k;
  std::shuffle(label.begin(), label.end(), std::mt19937(seed));
  std::vector<Eigen::Triplet<double>> entries;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const int here = label[static_cast<std::size_t>(y * side + x)];
      entries.emplace_back(here, here, 5.0);
      if (x + 1 < side) {
        const int right = label[static_cast<std::size_t>(y * side + x + 1)];
        entries.emplace_back(here, right, -1.0);
        entries.emplace_back(right, here, -1.0);
      }
      if (y + 1 < side) {
        const int below = label[static_cast<std::size_t>((y + 1) * side + x)];
        entries.emplace_back(here, below, -1.0);
        entries.emplace_back(below, here, -1.0);
      }
    }
  Eigen::SparseMatrix<double> matrix(size, size);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

// The factor L of `matrix` in its own numbering (Eigen's simplicial LL^T, natural order).
Eigen::SparseMatrix<double> factor_of(const Eigen::SparseMatrix<double>& matrix) {
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower,
                       Eigen::NaturalOrdering<int>> cholesky(matrix);
  EXPECT_EQ(cholesky.info(), Eigen::Success);
  return cholesky.matrixL();
}

// matrix(order, order): row order[k] becomes row k.
Eigen::SparseMatrix<double> renumbered(const Eigen::SparseMatrix<double>& matrix,
                                       const std::vector<int>& order) {
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> permutation(
      static_cast<int>(order.size()));
  for (std::size_t k = 0; k < order.size(); ++k) permutation.indices()[order[k]] = static_cast<int>(k);
  Eigen::SparseMatrix<double> result;
  result = matrix.twistedBy(permutation);
  return result;
}

TEST(EliminationTree, ParentIsTheFirstEntryBelowTheDiagonalOfTheFactor) {
  const Eigen::SparseMatrix<double> matrix = shuffled_grid(9, 7u);
  const Eigen::SparseMatrix<double> lower = matrix.triangularView<Eigen::Lower>();
  const std::vector<int> parent = detail::elimination_tree(lower);
  const Eigen::SparseMatrix<double> factor = factor_of(matrix);
  int roots = 0;
  for (int column = 0; column < factor.cols(); ++column) {
    int first_below = -1;
    for (Eigen::SparseMatrix<double>::InnerIterator it(factor, column); it; ++it)
      if (it.row() > column && (first_below < 0 || it.row() < first_below))
        first_below = static_cast<int>(it.row());
    EXPECT_EQ(parent[static_cast<std::size_t>(column)], first_below) << "column " << column;
    if (first_below < 0) ++roots;
  }
  EXPECT_EQ(roots, 1);  // A connected grid: one tree.
  // Renumbered through `position`, the tree is that of the renumbered matrix.
  std::vector<int> order(static_cast<std::size_t>(matrix.rows()));
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(order.size() - 1 - k);
  std::vector<int> position(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) position[static_cast<std::size_t>(order[k])] = static_cast<int>(k);
  const Eigen::SparseMatrix<double> reversed = renumbered(matrix, order);
  EXPECT_EQ(detail::elimination_tree(lower, position),
            detail::elimination_tree(Eigen::SparseMatrix<double>(reversed.triangularView<Eigen::Lower>())));
}

TEST(EliminationTree, PostorderVisitsEverySubtreeAsOneRangeEndingAtItsRoot) {
  // A forest: 0 and 1 under 4, 2 under 3, 3 under 4, 5 alone, 6 under 7.
  const std::vector<int> parent = {4, 4, 3, 4, -1, -1, 7, -1};
  const std::vector<int> post = detail::postorder(parent);
  EXPECT_EQ(post, (std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}));
  // Any forest, parents numbered before their children or not: 2 -> 0 -> 3 -> 4, 5 -> 3, 7 -> 4,
  // 1 and 6 alone. Roots and children in increasing order.
  const std::vector<int> shuffled = {3, -1, 0, 4, -1, 3, -1, 4};
  EXPECT_EQ(detail::postorder(shuffled), (std::vector<int>{1, 2, 0, 5, 3, 7, 4, 6}));
}

TEST(EliminationTree, PostorderedOrderingKeepsTheFillAndIsItsOwnPostorder) {
  const Eigen::SparseMatrix<double> matrix = shuffled_grid(12, 3u);
  const Eigen::SparseMatrix<double> lower = matrix.triangularView<Eigen::Lower>();
  std::vector<int> order(static_cast<std::size_t>(matrix.rows()));
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::shuffle(order.begin(), order.end(), std::mt19937(11u));
  const std::vector<int> postordered = detail::postordered_ordering(lower, order);
  ASSERT_EQ(postordered.size(), order.size());
  EXPECT_EQ(factor_of(renumbered(matrix, postordered)).nonZeros(),
            factor_of(renumbered(matrix, order)).nonZeros());
  const Eigen::SparseMatrix<double> in_order = renumbered(matrix, postordered);
  const std::vector<int> parent =
      detail::elimination_tree(Eigen::SparseMatrix<double>(in_order.triangularView<Eigen::Lower>()));
  std::vector<int> identity(parent.size());
  for (std::size_t k = 0; k < identity.size(); ++k) identity[k] = static_cast<int>(k);
  EXPECT_EQ(detail::postorder(parent), identity);
  // Not a permutation: returned as it is.
  std::vector<int> repeated = order;
  repeated[1] = repeated[0];
  EXPECT_EQ(detail::postordered_ordering(lower, repeated), repeated);
}

}  // namespace
}  // namespace harmonia
