// 1-to-4 midpoint subdivision (midpoint_subdivision.h).
#include "mesh/midpoint_subdivision.h"

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

namespace harmonia::detail {

Mesh midpoint_subdivision(const Mesh& mesh) {
  std::map<std::pair<int, int>, int> midpoint_of;  // edge (lower vertex first) -> its new vertex
  std::vector<Eigen::Vector3d> added;
  const auto midpoint = [&](int a, int b) {
    const std::pair<int, int> edge{std::min(a, b), std::max(a, b)};
    const auto [found, inserted] =
        midpoint_of.try_emplace(edge, static_cast<int>(mesh.vertices.rows() + static_cast<Eigen::Index>(added.size())));
    if (inserted) added.emplace_back(0.5 * (mesh.vertices.row(a) + mesh.vertices.row(b)).transpose());
    return found->second;
  };
  Mesh refined;
  refined.faces.resize(4 * mesh.faces.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const int a = mesh.faces(f, 0), b = mesh.faces(f, 1), c = mesh.faces(f, 2);
    const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    refined.faces.row(4 * f) << a, ab, ca;
    refined.faces.row(4 * f + 1) << ab, b, bc;
    refined.faces.row(4 * f + 2) << ca, bc, c;
    refined.faces.row(4 * f + 3) << ab, bc, ca;
  }
  refined.vertices.resize(mesh.vertices.rows() + static_cast<Eigen::Index>(added.size()), 3);
  refined.vertices.topRows(mesh.vertices.rows()) = mesh.vertices;
  for (std::size_t k = 0; k < added.size(); ++k)
    refined.vertices.row(mesh.vertices.rows() + static_cast<Eigen::Index>(k)) = added[k].transpose();
  return refined;
}

}  // namespace harmonia::detail
