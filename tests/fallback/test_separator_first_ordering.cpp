// SeparatorFirstOrdering: a large mesh graph is split by a vertex separator into two sides with no
// edge between them, each side's order holds exactly its vertices, and the whole order is a
// permutation with the separator last; a small graph is ordered whole.
#include <algorithm>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "fallback/separator_first_ordering.h"
#include "harmonia/procedural.h"
#include "mesh/adjacency_pattern.h"

namespace harmonia {
namespace {

using detail::SeparatorFirstOrdering;

bool is_permutation_of_range(std::vector<int> order, int size) {
  std::sort(order.begin(), order.end());
  std::vector<int> range(static_cast<std::size_t>(size));
  std::iota(range.begin(), range.end(), 0);
  return order == range;
}

TEST(SeparatorFirstOrdering, SplitsALargeMeshGraphIntoTwoSidesWithNoEdgeBetween) {
#ifndef HARMONIA_HAVE_METIS
  GTEST_SKIP() << "built without METIS: no separator-first ordering";
#endif
  const Mesh mesh = planar_disk(60, 0.2);  // 10981 vertices.
  const Eigen::SparseMatrix<double> pattern =
      detail::AdjacencyPattern(mesh.faces, mesh.vertex_count()).take_matrix();
  SeparatorFirstOrdering ordering;
  ordering.compute(pattern);
  const std::vector<SeparatorFirstOrdering::Part>& parts = ordering.parts();
  ASSERT_EQ(parts.size(), static_cast<std::size_t>(mesh.vertex_count()));
  std::array<int, 3> counts = {0, 0, 0};
  for (const auto part : parts) ++counts[static_cast<std::size_t>(part)];
  EXPECT_GT(counts[0], mesh.vertex_count() / 4);
  EXPECT_GT(counts[1], mesh.vertex_count() / 4);
  EXPECT_GT(counts[2], 0);
  EXPECT_GE(counts[0], counts[1]);  // The larger side first.
  EXPECT_LT(counts[2], mesh.vertex_count() / 20);  // About the square root of the size.
  for (int column = 0; column < pattern.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(pattern, column); entry; ++entry) {
      const auto a = parts[static_cast<std::size_t>(entry.row())];
      const auto b = parts[static_cast<std::size_t>(column)];
      EXPECT_FALSE((a == SeparatorFirstOrdering::side0 && b == SeparatorFirstOrdering::side1) ||
                   (a == SeparatorFirstOrdering::side1 && b == SeparatorFirstOrdering::side0))
          << "edge " << entry.row() << "-" << column << " joins the sides";
    }
  for (int side = 0; side < 2; ++side) {
    const std::vector<int>& order = ordering.side_order(side);
    EXPECT_EQ(static_cast<int>(order.size()), counts[static_cast<std::size_t>(side)]);
    for (const int v : order) EXPECT_EQ(parts[static_cast<std::size_t>(v)], side);
    EXPECT_EQ(ordering.side_future(side).get(), order);
  }
  const std::vector<int> whole = ordering.vertex_ordering();
  EXPECT_TRUE(is_permutation_of_range(whole, mesh.vertex_count()));
  for (std::size_t k = whole.size() - static_cast<std::size_t>(counts[2]); k < whole.size(); ++k)
    EXPECT_EQ(parts[static_cast<std::size_t>(whole[k])], SeparatorFirstOrdering::separator);
}

// Built from the faces, the graph is the adjacency pattern's: the same stages.
TEST(SeparatorFirstOrdering, TheFacesGiveTheSameOrderAsTheAdjacencyPattern) {
  const Mesh mesh = planar_disk(60, 0.2);
  SeparatorFirstOrdering from_pattern, from_faces;
  from_pattern.compute(detail::AdjacencyPattern(mesh.faces, mesh.vertex_count()).take_matrix());
  from_faces.compute(mesh.faces, mesh.vertex_count());
  EXPECT_EQ(from_faces.parts(), from_pattern.parts());
  EXPECT_EQ(from_faces.side_order(0), from_pattern.side_order(0));
  EXPECT_EQ(from_faces.side_order(1), from_pattern.side_order(1));
}

TEST(SeparatorFirstOrdering, SmallGraphsAreOrderedWhole) {
  const Mesh mesh = planar_disk(20, 0.2);
  SeparatorFirstOrdering ordering;
  ordering.compute(detail::AdjacencyPattern(mesh.faces, mesh.vertex_count()).take_matrix());
  EXPECT_TRUE(ordering.parts().empty());
  EXPECT_TRUE(ordering.side_order(1).empty());
  const std::vector<int> whole = ordering.vertex_ordering();
  if (whole.empty()) GTEST_SKIP() << "built without CHOLMOD: no nested dissection";
  EXPECT_EQ(whole, ordering.side_order(0));
  EXPECT_TRUE(is_permutation_of_range(whole, mesh.vertex_count()));
}

}  // namespace
}  // namespace harmonia
