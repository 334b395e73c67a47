#include "mesh/coincident_vertices.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <tuple>
#include <utility>

namespace harmonia::detail {
namespace {

// Union-find whose roots are the smallest members.
int find_root(std::vector<int>& parent, int x) {
  while (parent[static_cast<std::size_t>(x)] != x) {
    parent[static_cast<std::size_t>(x)] =
        parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    x = parent[static_cast<std::size_t>(x)];
  }
  return x;
}

void unite(std::vector<int>& parent, int a, int b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
}

}  // namespace

std::vector<int> coincident_vertex_representatives(const Eigen::MatrixX3d& vertices, double tolerance) {
  const int n = static_cast<int>(vertices.rows());
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  if (n == 0) return parent;
  if (tolerance <= 0.0) {
    std::vector<int> order(parent);
    auto position = [&vertices](int v) {
      return std::make_tuple(vertices(v, 0), vertices(v, 1), vertices(v, 2));
    };
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return std::make_pair(position(a), a) < std::make_pair(position(b), b);
    });
    for (std::size_t k = 1; k < order.size(); ++k) {
      if (position(order[k]) == position(order[k - 1])) unite(parent, order[k], order[k - 1]);
    }
  } else {
    using Cell = std::array<std::int64_t, 3>;
    const Eigen::RowVector3d lowest = vertices.colwise().minCoeff();
    const double extent = (vertices.colwise().maxCoeff() - lowest).maxCoeff();
    const double cell_size = std::max(tolerance, std::ldexp(extent, -40));
    auto cell_of = [&](int v) {
      Cell cell;
      for (int axis = 0; axis < 3; ++axis) {
        cell[static_cast<std::size_t>(axis)] =
            static_cast<std::int64_t>(std::floor((vertices(v, axis) - lowest(axis)) / cell_size));
      }
      return cell;
    };
    std::vector<std::pair<Cell, int>> cells;
    cells.reserve(static_cast<std::size_t>(n));
    for (int v = 0; v < n; ++v) cells.emplace_back(cell_of(v), v);
    std::sort(cells.begin(), cells.end());
    const double tolerance_squared = tolerance * tolerance;
    for (int v = 0; v < n; ++v) {
      const Cell home = cell_of(v);
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            const Cell key{home[0] + dx, home[1] + dy, home[2] + dz};
            auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(key, -1));
            for (; it != cells.end() && it->first == key; ++it) {
              const int w = it->second;
              if (w < v && (vertices.row(v) - vertices.row(w)).squaredNorm() <= tolerance_squared) {
                unite(parent, v, w);
              }
            }
          }
        }
      }
    }
  }
  for (int v = 0; v < n; ++v) parent[static_cast<std::size_t>(v)] = find_root(parent, v);
  return parent;
}

}  // namespace harmonia::detail
