#pragma once
// Dijkstra on the edge graph of a mesh with Euclidean edge lengths.
//
// Determinism: the queue orders by (distance, vertex index), a label is only replaced by a strictly
// shorter one, and neighbours are visited in increasing index order, so equal inputs give equal
// trees on every platform.

#include <vector>

#include "harmonia/mesh.h"
#include "mesh/edge_table.h"

namespace harmonia::detail {

//! The edge graph in compressed rows: neighbours of v are neighbor[offset[v] .. offset[v + 1]),
//! sorted by index, with the Euclidean length of each edge and its index in the EdgeTable.
struct EdgeGraph {
  std::vector<int> offset;
  std::vector<int> neighbor;
  std::vector<double> length;
  std::vector<int> edge;

  [[nodiscard]] int vertex_count() const { return static_cast<int>(offset.size()) - 1; }
};

[[nodiscard]] EdgeGraph build_edge_graph(const Mesh& mesh, const EdgeTable& edges);

//! Distances and shortest-path-tree parents (-1 at sources and unreachable vertices).
struct ShortestPathTree {
  std::vector<double> distance;  //!< +infinity where unreachable.
  std::vector<int> parent;
};

//! Single-source Dijkstra.
[[nodiscard]] ShortestPathTree dijkstra(const EdgeGraph& graph, int source);

//! The vertex with the largest finite distance (the smallest index among equals).
[[nodiscard]] int farthest_vertex(const ShortestPathTree& tree);

//! The path source -> target read from the parents: source first, target last. Empty if the
//! target is unreachable.
[[nodiscard]] std::vector<int> path_to(const ShortestPathTree& tree, int target);

}  // namespace harmonia::detail
