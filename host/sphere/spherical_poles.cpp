// The poles of a spherical map (spherical_poles.h).

#include "sphere/spherical_poles.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <vector>

#include "mesh/edge_table.h"
#include "mesh/power_of_two_scale.h"
#include "mesh/shortest_paths.h"

namespace harmonia::detail {
namespace {

// True when position a comes before position b: x, then y, then z.
bool lexicographically_before(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  for (int axis = 0; axis < 3; ++axis)
    if (a[axis] != b[axis]) return a[axis] < b[axis];
  return false;
}

// The vertex with the largest `score`; among exact ties the lexicographically smallest position.
template <typename Score>
int best_vertex(const Mesh& mesh, const Score& score) {
  int best = -1;
  double best_score = -std::numeric_limits<double>::infinity();
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    const double value = score(v);
    if (!std::isfinite(value)) continue;
    if (best < 0 || value > best_score ||
        (value == best_score && lexicographically_before(mesh.vertices.row(v).transpose(),
                                                         mesh.vertices.row(best).transpose()))) {
      best = v;
      best_score = value;
    }
  }
  return best;
}

// Hops from `source` over the edge graph.
std::vector<int> hop_distances(const EdgeGraph& graph, int source) {
  std::vector<int> hops(static_cast<std::size_t>(graph.vertex_count()), -1);
  std::queue<int> queue;
  hops[static_cast<std::size_t>(source)] = 0;
  queue.push(source);
  while (!queue.empty()) {
    const int v = queue.front();
    queue.pop();
    for (int slot = graph.offset[static_cast<std::size_t>(v)];
         slot < graph.offset[static_cast<std::size_t>(v) + 1]; ++slot) {
      const int w = graph.neighbor[static_cast<std::size_t>(slot)];
      if (hops[static_cast<std::size_t>(w)] >= 0) continue;
      hops[static_cast<std::size_t>(w)] = hops[static_cast<std::size_t>(v)] + 1;
      queue.push(w);
    }
  }
  return hops;
}

}  // namespace

std::array<int, 2> automatic_poles(const Mesh& input) {
  // Distances on the copy of unit size: no overflow for a model in units of 1e300, and scaling by
  // a power of two changes no comparison.
  const Mesh mesh = unit_scaled(input).mesh;
  const EdgeGraph graph = build_edge_graph(mesh, EdgeTable(mesh));
  const Eigen::RowVector3d centroid = mesh.vertices.colwise().mean();
  const int start =
      best_vertex(mesh, [&](int v) { return (mesh.vertices.row(v) - centroid).squaredNorm(); });
  const auto farthest_from = [&](int source) {
    const ShortestPathTree tree = dijkstra(graph, source);
    return best_vertex(mesh, [&](int v) { return tree.distance[static_cast<std::size_t>(v)]; });
  };
  const int north = farthest_from(start);
  const int south = farthest_from(north);
  return {north, south};
}

std::string pole_problem(const Mesh& mesh, const std::array<int, 2>& poles) {
  for (const int pole : poles) {
    if (pole < 0 || pole >= mesh.vertex_count())
      return "pole " + std::to_string(pole) + " is out of range [0, " +
             std::to_string(mesh.vertex_count()) + ")";
  }
  if (poles[0] == poles[1]) return "the two poles are the same vertex " + std::to_string(poles[0]);
  const EdgeGraph graph = build_edge_graph(mesh, EdgeTable(mesh));
  const int hops = hop_distances(graph, poles[0])[static_cast<std::size_t>(poles[1])];
  if (hops < 3) {
    return "the poles " + std::to_string(poles[0]) + " and " + std::to_string(poles[1]) +
           " are only " + std::to_string(hops) +
           (hops == 1 ? " edge" : " edges") +
           " apart; the rings around them must not touch, so they must be at least 3 edges "
           "apart" +
           (poles == automatic_poles(mesh) ? " (the mesh is too small: subdivide it first)" : "");
  }
  return {};
}

}  // namespace harmonia::detail
