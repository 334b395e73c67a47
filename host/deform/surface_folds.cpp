#include "deform/surface_folds.h"

#include <algorithm>
#include <cstddef>
#include <utility>

#include <Eigen/Geometry>

namespace harmonia::detail {

std::vector<std::vector<int>> edge_neighbours(const Eigen::MatrixX3i& faces) {
  // Every directed edge as (smaller vertex, larger vertex, face), sorted: the faces around one edge
  // come out next to each other.
  std::vector<std::pair<std::pair<int, int>, int>> edges;
  edges.reserve(static_cast<std::size_t>(faces.rows()) * 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = faces(f, k), b = faces(f, (k + 1) % 3);
      edges.push_back({{std::min(a, b), std::max(a, b)}, static_cast<int>(f)});
    }
  std::sort(edges.begin(), edges.end());
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(faces.rows()));
  for (std::size_t begin = 0, end = 0; begin < edges.size(); begin = end) {
    for (end = begin; end < edges.size() && edges[end].first == edges[begin].first;) ++end;
    for (std::size_t i = begin; i < end; ++i)
      for (std::size_t j = begin; j < end; ++j)
        if (edges[i].second != edges[j].second)
          neighbours[static_cast<std::size_t>(edges[i].second)].push_back(edges[j].second);
  }
  for (std::vector<int>& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return neighbours;
}

std::vector<char> folded_triangles(const Eigen::MatrixX3i& faces,
                                   const std::vector<std::vector<int>>& neighbours,
                                   const Eigen::MatrixX3d& positions) {
  const auto count = static_cast<std::size_t>(faces.rows());
  std::vector<Eigen::Vector3d> normals(count);
  std::vector<char> folded(count, 0);
  for (std::size_t f = 0; f < count; ++f) {
    const auto i = static_cast<Eigen::Index>(f);
    const Eigen::Vector3d a = positions.row(faces(i, 0)), b = positions.row(faces(i, 1)),
                          c = positions.row(faces(i, 2));
    normals[f] = (b - a).cross(c - a);
    const double length = normals[f].norm();
    if (length > 0.0)
      normals[f] /= length;
    else
      folded[f] = 1;  // zero area: degenerate
  }
  for (std::size_t f = 0; f < count; ++f) {
    if (folded[f]) continue;
    Eigen::Vector3d around = Eigen::Vector3d::Zero();
    for (const int g : neighbours[f]) around += normals[static_cast<std::size_t>(g)];
    if (normals[f].dot(around) < 0.0) folded[f] = 1;
  }
  return folded;
}

int triangles_folded_by_pose(const Eigen::MatrixX3i& faces,
                             const std::vector<std::vector<int>>& neighbours,
                             const Eigen::MatrixX3d& rest, const Eigen::MatrixX3d& posed) {
  const std::vector<char> at_rest = folded_triangles(faces, neighbours, rest);
  const std::vector<char> in_pose = folded_triangles(faces, neighbours, posed);
  int count = 0;
  for (std::size_t f = 0; f < at_rest.size(); ++f) count += in_pose[f] && !at_rest[f] ? 1 : 0;
  return count;
}

}  // namespace harmonia::detail
