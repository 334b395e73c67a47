#include "deform/vertex_clusters.h"

#include <algorithm>
#include <cmath>
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

// The share of a cluster's radius over which its weight falls from 1 to 0 beyond its border (the
// band is measured in how much farther the cluster's seed is than the vertex's nearest). A cluster
// that ends abruptly makes its rotation jump at its border, which costs energy the true solution
// does not pay and pushes the fit to spread a limb's turn over every border between the limb and
// the fixed feet; a blend over half the radius lets the turn happen where the energy wants it
// (every edit case closer to ARAP; a whole radius blends so far that unlike rotations average to
// shrinking linear parts, and some cases get worse).
constexpr double kBlendWidth = 0.5;

// Soft membership: vertex v's weight for cluster c falls smoothly with how much farther c's seed is
// than v's nearest, (d_c(v) - d(v)) / band_c, band_c a share of c's radius; at a border two clusters
// weigh alike, so the weights are continuous. Each seed's search stops where it falls to 0.
void soften(const std::vector<std::vector<std::pair<int, double>>>& neighbours, const std::vector<double>& nearest,
            VertexClusters& clusters, const std::vector<int>& seeds) {
  const std::size_t vertex_count = nearest.size();
  std::vector<double> radius(seeds.size(), 0.0);
  for (std::size_t v = 0; v < vertex_count; ++v)
    if (std::isfinite(nearest[v]))
      radius[static_cast<std::size_t>(clusters.cluster_of[v])] =
          std::max(radius[static_cast<std::size_t>(clusters.cluster_of[v])], nearest[v]);
  std::vector<std::vector<std::pair<int, double>>> weights(vertex_count);
  for (std::size_t v = 0; v < vertex_count; ++v) weights[v].emplace_back(clusters.cluster_of[v], 1.0);
  std::vector<double> distance(vertex_count, std::numeric_limits<double>::infinity());
  std::vector<int> touched;
  using Reach = std::pair<double, int>;
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    const double band = kBlendWidth * radius[s];
    if (!(band > 0.0)) continue;
    std::priority_queue<Reach, std::vector<Reach>, std::greater<Reach>> frontier;
    distance[static_cast<std::size_t>(seeds[s])] = 0.0;
    touched.push_back(seeds[s]);
    frontier.emplace(0.0, seeds[s]);
    while (!frontier.empty()) {
      const auto [reached, vertex] = frontier.top();
      frontier.pop();
      if (reached > distance[static_cast<std::size_t>(vertex)]) continue;
      const double excess = (reached - nearest[static_cast<std::size_t>(vertex)]) / band;
      if (clusters.cluster_of[static_cast<std::size_t>(vertex)] != static_cast<int>(s) && excess < 1.0) {
        const double t = std::max(0.0, excess);
        weights[static_cast<std::size_t>(vertex)].emplace_back(static_cast<int>(s), (1.0 - t) * (1.0 - t) * (1.0 + 2.0 * t));
      }
      for (const auto& [next, length] : neighbours[static_cast<std::size_t>(vertex)]) {
        const double through = reached + length;
        if (through < distance[static_cast<std::size_t>(next)] &&
            through < nearest[static_cast<std::size_t>(next)] + band) {
          if (!std::isfinite(distance[static_cast<std::size_t>(next)])) touched.push_back(next);
          distance[static_cast<std::size_t>(next)] = through;
          frontier.emplace(through, next);
        }
      }
    }
    for (const int v : touched) distance[static_cast<std::size_t>(v)] = std::numeric_limits<double>::infinity();
    touched.clear();
  }
  clusters.weight_start.assign(1, 0);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    double sum = 0.0;
    for (const auto& [c, w] : weights[v]) sum += w;
    for (const auto& [c, w] : weights[v]) {
      clusters.weight_cluster.push_back(c);
      clusters.weight_value.push_back(w / sum);
    }
    clusters.weight_start.push_back(static_cast<int>(clusters.weight_cluster.size()));
  }
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
  if (used.empty() || count <= 0) {  // no cluster: no vertex has a weight
    clusters.weight_start.assign(static_cast<std::size_t>(vertex_count) + 1, 0);
    return clusters;
  }

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
  soften(neighbours, distance, clusters, seeds);
  return clusters;
}

}  // namespace harmonia::detail
