// Elimination trees and their postorders (elimination_tree.h).

#include "fallback/elimination_tree.h"

#include <algorithm>

namespace harmonia::detail {

// Liu's algorithm with path compression over the rows of the renumbered lower triangle.
std::vector<int> elimination_tree(const Eigen::SparseMatrix<double>& lower,
                                  const std::vector<int>& position) {
  const auto size = static_cast<int>(lower.rows());
  const int* outer = lower.outerIndexPtr();
  const int* inner = lower.innerIndexPtr();
  const int* nonzeros = lower.innerNonZeroPtr();  // Set when the matrix is not compressed.
  const auto column_end = [&](int column) {
    return nonzeros != nullptr ? outer[column] + nonzeros[column] : outer[column + 1];
  };
  const auto renumbered = [&position](int row) {
    return position.empty() ? row : position[static_cast<std::size_t>(row)];
  };
  // The renumbered lower triangle by rows: the columns j < i of each row i.
  std::vector<int> row_start(static_cast<std::size_t>(size) + 1, 0);
  for (int column = 0; column < size; ++column)
    for (int k = outer[column]; k < column_end(column); ++k)
      if (inner[k] > column)
        ++row_start[static_cast<std::size_t>(
                        std::max(renumbered(inner[k]), renumbered(column))) + 1];
  for (int row = 0; row < size; ++row)
    row_start[static_cast<std::size_t>(row) + 1] += row_start[static_cast<std::size_t>(row)];
  std::vector<int> row_columns(static_cast<std::size_t>(row_start.back()));
  std::vector<int> cursor(row_start.begin(), row_start.end() - 1);
  for (int column = 0; column < size; ++column)
    for (int k = outer[column]; k < column_end(column); ++k)
      if (inner[k] > column) {
        const int a = renumbered(inner[k]), b = renumbered(column);
        row_columns[static_cast<std::size_t>(cursor[static_cast<std::size_t>(std::max(a, b))]++)] =
            std::min(a, b);
      }

  std::vector<int> parent(static_cast<std::size_t>(size), -1);
  std::vector<int> ancestor(static_cast<std::size_t>(size), -1);
  for (int row = 0; row < size; ++row) {
    for (int k = row_start[static_cast<std::size_t>(row)];
         k < row_start[static_cast<std::size_t>(row) + 1]; ++k) {
      // Climb from the column to the root of its current subtree, which becomes a child of row.
      for (int node = row_columns[static_cast<std::size_t>(k)]; node != -1 && node < row;) {
        const int next = ancestor[static_cast<std::size_t>(node)];
        ancestor[static_cast<std::size_t>(node)] = row;
        if (next == -1) parent[static_cast<std::size_t>(node)] = row;
        node = next;
      }
    }
  }
  return parent;
}

std::vector<int> postorder(const std::vector<int>& parent) {
  const auto size = static_cast<int>(parent.size());
  // Each node's children as a linked list (first_child, next_sibling), built from the highest
  // index down so that the lists come out increasing.
  std::vector<int> first_child(static_cast<std::size_t>(size), -1);
  std::vector<int> next_sibling(static_cast<std::size_t>(size), -1);
  std::vector<int> roots;
  for (int node = size - 1; node >= 0; --node) {
    const int up = parent[static_cast<std::size_t>(node)];
    if (up < 0) {
      roots.push_back(node);
      continue;
    }
    next_sibling[static_cast<std::size_t>(node)] = first_child[static_cast<std::size_t>(up)];
    first_child[static_cast<std::size_t>(up)] = node;
  }
  std::reverse(roots.begin(), roots.end());
  // Depth-first, without recursion: a node is emitted once its children are.
  std::vector<int> post;
  post.reserve(static_cast<std::size_t>(size));
  std::vector<int> stack;
  for (const int root : roots) {
    stack.push_back(root);
    while (!stack.empty()) {
      const int node = stack.back();
      const int child = first_child[static_cast<std::size_t>(node)];
      if (child >= 0) {
        // Descend into the next child, unlinking it so that the node is emitted on return.
        first_child[static_cast<std::size_t>(node)] = next_sibling[static_cast<std::size_t>(child)];
        stack.push_back(child);
      } else {
        post.push_back(node);
        stack.pop_back();
      }
    }
  }
  return post;
}

}  // namespace harmonia::detail
