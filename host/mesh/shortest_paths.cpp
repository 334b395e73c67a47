#include "mesh/shortest_paths.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace harmonia::detail {

EdgeGraph build_edge_graph(const Mesh& mesh, const EdgeTable& edges) {
  const auto vertex_count = static_cast<std::size_t>(mesh.vertex_count());
  EdgeGraph graph;
  graph.offset.assign(vertex_count + 1, 0);
  for (int e = 0; e < edges.size(); ++e) {
    ++graph.offset[static_cast<std::size_t>(edges.first(e)) + 1];
    ++graph.offset[static_cast<std::size_t>(edges.second(e)) + 1];
  }
  for (std::size_t v = 0; v < vertex_count; ++v) graph.offset[v + 1] += graph.offset[v];
  const auto entry_count = static_cast<std::size_t>(graph.offset[vertex_count]);
  graph.neighbor.resize(entry_count);
  graph.length.resize(entry_count);
  graph.edge.resize(entry_count);
  std::vector<int> next_slot(graph.offset.begin(), graph.offset.end() - 1);
  auto append = [&](int from, int to, int e) {
    const auto slot = static_cast<std::size_t>(next_slot[static_cast<std::size_t>(from)]++);
    graph.neighbor[slot] = to;
    graph.length[slot] = (mesh.vertices.row(from) - mesh.vertices.row(to)).norm();
    graph.edge[slot] = e;
  };
  // The edges are sorted by (first, second): appending every vertex's smaller neighbours first,
  // then its larger ones, leaves each row sorted.
  for (int e = 0; e < edges.size(); ++e) append(edges.second(e), edges.first(e), e);
  for (int e = 0; e < edges.size(); ++e) append(edges.first(e), edges.second(e), e);
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
  if (tree.distance[static_cast<std::size_t>(target)] == std::numeric_limits<double>::infinity()) {
    return path;
  }
  for (int v = target; v >= 0; v = tree.parent[static_cast<std::size_t>(v)]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace harmonia::detail
