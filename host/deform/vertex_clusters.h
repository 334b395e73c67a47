#pragma once
// Internal: the vertices grouped into compact patches of about equal size, for the editor's
// rotation clusters (deform/clustered_rotation_fit.h).
//
// The seeds come from farthest-point sampling in space (the first: the vertex farthest from the
// centroid; each next: the vertex farthest from all seeds so far), which spreads them evenly over
// the surface at a cost of one distance per vertex and seed. Every vertex then belongs to its
// nearest seed along the edges (one Dijkstra search from all seeds at once), so a cluster never
// spans two limbs that merely come close in space; a vertex no edge path joins to a seed keeps its
// nearest seed in space.

#include <vector>

#include "harmonia/mesh.h"

namespace harmonia::detail {

struct VertexClusters {
  std::vector<int> cluster_of;  // #V: the cluster of each vertex, in [0, count)
  int count = 0;
};

// At most `count` clusters (fewer when the mesh has fewer vertices used by faces).
[[nodiscard]] VertexClusters geodesic_clusters(const Mesh& mesh, int count);

}  // namespace harmonia::detail
