#include "atlas/chart_borders.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace harmonia::detail {

ChartAdjacency chart_adjacency(const Mesh& mesh, const FaceGeometry& geometry, const std::vector<int>& chart_of_face,
                               int chart_count) {
  ChartAdjacency adjacency;
  adjacency.perimeter.assign(static_cast<std::size_t>(chart_count), 0.0);
  adjacency.area.assign(static_cast<std::size_t>(chart_count), 0.0);
  for (int f = 0; f < geometry.face_count(); ++f) {
    const int chart = chart_of_face[static_cast<std::size_t>(f)];
    if (chart < 0) continue;
    adjacency.area[static_cast<std::size_t>(chart)] += geometry.area[static_cast<std::size_t>(f)];
    for (int k = 0; k < 3; ++k) {
      const int g = geometry.across[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
      const double length = geometry.edge_length[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
      if (g < 0 || chart_of_face[static_cast<std::size_t>(g)] != chart)
        adjacency.perimeter[static_cast<std::size_t>(chart)] += length;
      if (g < f) continue;  // each edge once (g = -1: no neighbour)
      const int other = chart_of_face[static_cast<std::size_t>(g)];
      if (other < 0 || other == chart) continue;
      ChartBorder& border = adjacency.borders[{std::min(chart, other), std::max(chart, other)}];
      border.length += length;
      border.edges.emplace_back(mesh.faces(f, k), mesh.faces(f, (k + 1) % 3));
    }
  }
  return adjacency;
}

std::vector<std::pair<int, int>> pairs_longest_border_first(const ChartAdjacency& adjacency,
                                                          const std::vector<int>& rank) {
  std::vector<std::pair<int, int>> pairs;
  pairs.reserve(adjacency.borders.size());
  for (const auto& entry : adjacency.borders) pairs.push_back(entry.first);
  const auto ranks = [&rank](const std::pair<int, int>& pair) {
    const int first = rank[static_cast<std::size_t>(pair.first)], second = rank[static_cast<std::size_t>(pair.second)];
    return std::pair<int, int>(std::min(first, second), std::max(first, second));
  };
  std::sort(pairs.begin(), pairs.end(), [&](const std::pair<int, int>& x, const std::pair<int, int>& y) {
    const double x_length = adjacency.borders.at(x).length, y_length = adjacency.borders.at(y).length;
    if (x_length != y_length) return x_length > y_length;
    return ranks(x) < ranks(y);
  });
  return pairs;
}

bool border_worth_joining(const ChartAdjacency& adjacency, int a, int b) {
  return border_worth_joining(adjacency, a, b, adjacency.borders.at({std::min(a, b), std::max(a, b)}).length);
}

bool border_worth_joining(const ChartAdjacency& adjacency, int a, int b, double joined_length) {
  const double perimeter_a = adjacency.perimeter[static_cast<std::size_t>(a)];
  const double perimeter_b = adjacency.perimeter[static_cast<std::size_t>(b)];
  // A border too short for its seam to matter: joining at it would only hinge two charts at a
  // corner, an awkward shape to pack for little seam saved.
  if (joined_length < kLeastBorderShare * std::min(perimeter_a, perimeter_b)) return false;
  // The union about as compact as its parts were, area for area (isoperimetric ratio
  // 4 pi area / perimeter^2, 1 for a disk): an L or a hook packs worse than its parts did.
  const auto compactness = [](double area, double perimeter) {
    return perimeter > 0.0 ? 4.0 * std::numbers::pi * area / (perimeter * perimeter) : 0.0;
  };
  const double area_a = adjacency.area[static_cast<std::size_t>(a)], area_b = adjacency.area[static_cast<std::size_t>(b)];
  const double parts =
      (area_a * compactness(area_a, perimeter_a) + area_b * compactness(area_b, perimeter_b)) / (area_a + area_b);
  const double union_perimeter = perimeter_a + perimeter_b - 2.0 * joined_length;
  return compactness(area_a + area_b, union_perimeter) >= kCompactnessKept * parts;
}

bool is_one_path(const ChartBorder& border) {
  std::map<int, std::vector<int>> neighbours;
  for (const auto& [v, w] : border.edges) {
    neighbours[v].push_back(w);
    neighbours[w].push_back(v);
  }
  int ends = 0;
  for (const auto& [v, around] : neighbours) {
    if (around.size() > 2) return false;
    if (around.size() == 1) ++ends;
  }
  if (ends != 2) return false;  // a cycle has none, several pieces have more
  // Connected: a walk from one end reaches every vertex.
  int previous = -1;
  int current = std::find_if(neighbours.begin(), neighbours.end(), [](const auto& entry) {
                  return entry.second.size() == 1;
                })->first;
  std::size_t visited = 1;
  while (true) {
    const std::vector<int>& around = neighbours[current];
    const int next = around[0] != previous ? around[0] : (around.size() > 1 ? around[1] : -1);
    if (next < 0 || next == previous) break;
    previous = current;
    current = next;
    ++visited;
    if (neighbours[current].size() == 1) break;
  }
  return visited == neighbours.size();
}

bool normals_within_cone(const FaceGeometry& geometry, const std::vector<int>& faces, double cone_cosine) {
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  for (const int f : faces) normal_sum += geometry.area[static_cast<std::size_t>(f)] * geometry.normal[static_cast<std::size_t>(f)];
  if (!(normal_sum.norm() > 0.0)) return false;
  const Eigen::Vector3d mean = normal_sum.normalized();
  return std::all_of(faces.begin(), faces.end(),
                     [&](int f) { return geometry.normal[static_cast<std::size_t>(f)].dot(mean) >= cone_cosine; });
}

}  // namespace harmonia::detail
