#include "deform/vertex_clusters.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <utility>


namespace harmonia::detail {
namespace {

// Distances this close (relative) count as equal: the seeds then do not depend on the model's
// unit or on rounding, and the lowest index wins a tie (symmetric meshes have many).
constexpr double kTieTolerance = 1e-9;

std::size_t farthest_within_rounding(const std::vector<double>& distance) {
  const double largest = *std::max_element(distance.begin(), distance.end());
  for (std::size_t i = 0; i < distance.size(); ++i)
    if (distance[i] >= largest * (1.0 - kTieTolerance)) return i;
  return 0;
}

}  // namespace

VertexClusters geodesic_clusters(const Mesh& mesh, int count) {
  const int vertex_count = mesh.vertex_count();
  VertexClusters clusters;
  clusters.cluster_of.assign(static_cast<std::size_t>(vertex_count), 0);
  std::vector<int> used;  // the vertices some face uses (the others stay in cluster 0)
  {
    std::vector<bool> is_used(static_cast<std::size_t>(vertex_count), false);
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
      for (int k = 0; k < 3; ++k) is_used[static_cast<std::size_t>(mesh.faces(f, k))] = true;
    for (int v = 0; v < vertex_count; ++v)
      if (is_used[static_cast<std::size_t>(v)]) used.push_back(v);
  }
  if (used.empty() || count <= 0) return clusters;

  // Farthest-point sampling in space; each vertex remembers its nearest seed so far.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const int v : used) centroid += mesh.vertices.row(v).transpose();
  centroid /= static_cast<double>(used.size());
  std::vector<double> nearest(used.size());
  for (std::size_t i = 0; i < used.size(); ++i)
    nearest[i] = (mesh.vertices.row(used[i]).transpose() - centroid).squaredNorm();
  std::vector<int> seeds;
  const int most = std::min<int>(count, static_cast<int>(used.size()));
  while (static_cast<int>(seeds.size()) < most) {
    const std::size_t farthest = farthest_within_rounding(nearest);
    if (!seeds.empty() && nearest[farthest] == 0.0) break;  // every place already has a seed
    const int seed = used[farthest];
    const int cluster = static_cast<int>(seeds.size());
    seeds.push_back(seed);
    const Eigen::Vector3d at = mesh.vertices.row(seed);
    for (std::size_t i = 0; i < used.size(); ++i) {
      const double distance = (mesh.vertices.row(used[i]).transpose() - at).squaredNorm();
      if (cluster == 0 || distance < nearest[i]) {
        nearest[i] = distance;
        clusters.cluster_of[static_cast<std::size_t>(used[i])] = cluster;
      }
    }
  }
  clusters.count = static_cast<int>(seeds.size());

  // The nearest seed along the edges, from all seeds at once.
  std::vector<std::vector<std::pair<int, double>>> neighbours(static_cast<std::size_t>(vertex_count));
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces(f, k), b = mesh.faces(f, (k + 1) % 3);
      const double length = (mesh.vertices.row(a) - mesh.vertices.row(b)).norm();
      neighbours[static_cast<std::size_t>(a)].emplace_back(b, length);
      neighbours[static_cast<std::size_t>(b)].emplace_back(a, length);
    }
  std::vector<double> distance(static_cast<std::size_t>(vertex_count), std::numeric_limits<double>::infinity());
  using Reach = std::pair<double, int>;  // (distance, vertex)
  std::priority_queue<Reach, std::vector<Reach>, std::greater<Reach>> frontier;
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    distance[static_cast<std::size_t>(seeds[s])] = 0.0;
    clusters.cluster_of[static_cast<std::size_t>(seeds[s])] = static_cast<int>(s);
    frontier.emplace(0.0, seeds[s]);
  }
  while (!frontier.empty()) {
    const auto [reached, vertex] = frontier.top();
    frontier.pop();
    if (reached > distance[static_cast<std::size_t>(vertex)]) continue;  // a stale entry
    const int cluster = clusters.cluster_of[static_cast<std::size_t>(vertex)];
    for (const auto& [next, length] : neighbours[static_cast<std::size_t>(vertex)]) {
      const double through = reached + length;
      const double known = distance[static_cast<std::size_t>(next)];
      // Nearer, or as near within rounding and from a lower seed (ties decided by index, not by
      // rounding): the vertex joins this cluster and passes it on.
      const bool nearer = through < known * (1.0 - kTieTolerance);
      const bool tie = !nearer && through <= known * (1.0 + kTieTolerance) &&
                       cluster < clusters.cluster_of[static_cast<std::size_t>(next)];
      if (nearer || tie) {
        distance[static_cast<std::size_t>(next)] = std::min(through, known);
        clusters.cluster_of[static_cast<std::size_t>(next)] = cluster;
        frontier.emplace(distance[static_cast<std::size_t>(next)], next);
      }
    }
  }
  return clusters;
}

}  // namespace harmonia::detail
