#pragma once
// Internal: the vertices grouped into compact patches of about equal size, for the editor's
// rotation clusters (deform/clustered_rotation_fit.h).
//
// The seeds come from farthest-point sampling in space (the first: the vertex farthest from the
// centroid; each next: the vertex farthest from all seeds so far), which spreads them evenly over
// the surface at a cost of one distance per vertex and seed. Every vertex then belongs to its
// nearest seed along the edges (one Dijkstra search from all seeds at once), so a cluster never
// spans two limbs that merely come close in space; a vertex no edge path joins to a seed keeps its
// nearest seed in space. Beside this hard partition, a soft one: each vertex also weighs the
// clusters whose seeds are little farther than its own (a smooth fall over half a cluster's
// radius), so that the rotations the editor gives the clusters blend across their borders.

#include <vector>

#include "harmonia/mesh.h"

namespace harmonia::detail {

struct VertexClusters {
  std::vector<int> cluster_of;  // #V: the cluster of each vertex, in [0, count)
  int count = 0;
  // Soft membership, a partition of unity: vertex v's clusters are weight_cluster[k] with weights
  // weight_value[k] for k in [weight_start[v], weight_start[v + 1]), its own cluster first.
  std::vector<int> weight_start;
  std::vector<int> weight_cluster;
  std::vector<double> weight_value;
};

// At most `count` clusters (fewer when the mesh has fewer vertices used by faces).
[[nodiscard]] VertexClusters geodesic_clusters(const Mesh& mesh, int count);

}  // namespace harmonia::detail
