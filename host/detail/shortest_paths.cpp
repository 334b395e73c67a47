#include "host/detail/shortest_paths.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace harmonia::detail {

EdgeGraph build_edge_graph(const Mesh& mesh) {
  std::vector<std::pair<int, int>> directed;
  directed.reserve(static_cast<std::size_t>(mesh.face_count()) * 6);
  for (int face = 0; face < mesh.face_count(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = mesh.faces(face, corner);
      const int b = mesh.faces(face, (corner + 1) % 3);
      if (a == b) continue;
      directed.emplace_back(a, b);
      directed.emplace_back(b, a);
    }
  }
  std::sort(directed.begin(), directed.end());
  directed.erase(std::unique(directed.begin(), directed.end()), directed.end());

  EdgeGraph graph;
  graph.offset.assign(static_cast<std::size_t>(mesh.vertex_count()) + 1, 0);
  for (const auto& [from, to] : directed) ++graph.offset[static_cast<std::size_t>(from) + 1];
  for (std::size_t v = 1; v < graph.offset.size(); ++v) graph.offset[v] += graph.offset[v - 1];
  graph.neighbor.reserve(directed.size());
  graph.length.reserve(directed.size());
  for (const auto& [from, to] : directed) {
    graph.neighbor.push_back(to);
    graph.length.push_back((mesh.vertices.row(from) - mesh.vertices.row(to)).norm());
  }
  return graph;
}

ShortestPathTree dijkstra(const EdgeGraph& graph, int source) {
  const int n = graph.vertex_count();
  ShortestPathTree tree;
  tree.distance.assign(static_cast<std::size_t>(n), std::numeric_limits<double>::infinity());
  tree.parent.assign(static_cast<std::size_t>(n), -1);
  std::vector<char> settled(static_cast<std::size_t>(n), 0);

  using Entry = std::pair<double, int>;  // (distance, vertex): ties go to the smaller index.
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  tree.distance[static_cast<std::size_t>(source)] = 0.0;
  queue.emplace(0.0, source);
  while (!queue.empty()) {
    const auto [distance, vertex] = queue.top();
    queue.pop();
    if (settled[static_cast<std::size_t>(vertex)]) continue;
    settled[static_cast<std::size_t>(vertex)] = 1;
    for (int k = graph.offset[static_cast<std::size_t>(vertex)];
         k < graph.offset[static_cast<std::size_t>(vertex) + 1]; ++k) {
      const int next = graph.neighbor[static_cast<std::size_t>(k)];
      const double candidate = distance + graph.length[static_cast<std::size_t>(k)];
      if (candidate < tree.distance[static_cast<std::size_t>(next)]) {
        tree.distance[static_cast<std::size_t>(next)] = candidate;
        tree.parent[static_cast<std::size_t>(next)] = vertex;
        queue.emplace(candidate, next);
      }
    }
  }
  return tree;
}

int farthest_vertex(const ShortestPathTree& tree) {
  int best = -1;
  for (std::size_t v = 0; v < tree.distance.size(); ++v) {
    const double d = tree.distance[v];
    if (d == std::numeric_limits<double>::infinity()) continue;
    if (best < 0 || d > tree.distance[static_cast<std::size_t>(best)]) best = static_cast<int>(v);
  }
  return best;
}

std::vector<int> path_to(const ShortestPathTree& tree, int target) {
  std::vector<int> path;
  if (tree.distance[static_cast<std::size_t>(target)] ==
      std::numeric_limits<double>::infinity()) {
    return path;
  }
  for (int v = target; v >= 0; v = tree.parent[static_cast<std::size_t>(v)]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace harmonia::detail
