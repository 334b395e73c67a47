#include "operators/one_ring.h"

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

namespace harmonia::detail {
namespace {

// One face seen from a vertex: the face is (centre, from, to) counter-clockwise, so walking the fan
// counter-clockwise goes from `from` to `to`, and the next face is the one whose `from` is this `to`.
struct Wedge {
  int from;
  int to;
};

// Orders the wedges of one vertex into a single chain. Returns the kind and writes the neighbours.
FanKind order_fan(const std::vector<Wedge>& wedges, std::vector<int>& ordered) {
  ordered.clear();
  if (wedges.empty()) return FanKind::isolated;
  const std::size_t count = wedges.size();

  // A boundary fan starts at the wedge whose `from` is nobody's `to`; there must be at most one.
  std::size_t start = 0;
  int open_starts = 0;
  for (std::size_t a = 0; a < count; ++a) {
    bool is_someones_to = false;
    for (std::size_t b = 0; b < count; ++b)
      if (b != a && wedges[b].to == wedges[a].from) is_someones_to = true;
    if (!is_someones_to) {
      if (open_starts == 0) start = a;
      ++open_starts;
    }
  }
  if (open_starts > 1) return FanKind::irregular;

  // Walk the chain; every wedge must be used exactly once and each step must be unambiguous.
  std::vector<bool> used(count, false);
  std::size_t current = start;
  used[current] = true;
  ordered.push_back(wedges[current].from);
  for (std::size_t step = 1; step < count; ++step) {
    std::size_t next = count;
    for (std::size_t b = 0; b < count; ++b) {
      if (wedges[b].from != wedges[current].to) continue;
      if (used[b] || next != count) return FanKind::irregular;  // a branch or a repeated edge
      next = b;
    }
    if (next == count) return FanKind::irregular;  // the chain breaks: several fans
    used[next] = true;
    current = next;
    ordered.push_back(wedges[current].from);
  }
  if (open_starts == 1) {
    ordered.push_back(wedges[current].to);
    return FanKind::boundary;
  }
  // Closed: the last wedge must lead back to the first.
  return wedges[current].to == wedges[start].from ? FanKind::interior : FanKind::irregular;
}

}  // namespace

VertexFans::VertexFans(const Eigen::MatrixX3i& faces, int vertex_count) {
  const auto face_count = static_cast<int>(faces.rows());
  const auto vertices = static_cast<std::size_t>(vertex_count);

  // Wedges grouped per vertex by a counting sort (faces in increasing order: deterministic).
  std::vector<int> wedge_offsets(vertices + 1, 0);
  for (int f = 0; f < face_count; ++f)
    for (int k = 0; k < 3; ++k) ++wedge_offsets[static_cast<std::size_t>(faces(f, k)) + 1];
  for (std::size_t v = 0; v < vertices; ++v) wedge_offsets[v + 1] += wedge_offsets[v];
  std::vector<Wedge> all_wedges(static_cast<std::size_t>(wedge_offsets.back()));
  {
    std::vector<int> cursor(wedge_offsets.begin(), wedge_offsets.end() - 1);
    for (int f = 0; f < face_count; ++f)
      for (int k = 0; k < 3; ++k)
        all_wedges[static_cast<std::size_t>(cursor[static_cast<std::size_t>(faces(f, k))]++)] =
            Wedge{faces(f, (k + 1) % 3), faces(f, (k + 2) % 3)};
  }

  offsets_.assign(vertices + 1, 0);
  kinds_.assign(vertices, FanKind::isolated);
  neighbours_.reserve(all_wedges.size() + vertices / 8);
  std::vector<Wedge> wedges;
  std::vector<int> ordered;
  for (std::size_t v = 0; v < vertices; ++v) {
    wedges.assign(all_wedges.begin() + wedge_offsets[v], all_wedges.begin() + wedge_offsets[v + 1]);
    kinds_[v] = order_fan(wedges, ordered);
    if (kinds_[v] == FanKind::interior || kinds_[v] == FanKind::boundary)
      neighbours_.insert(neighbours_.end(), ordered.begin(), ordered.end());
    offsets_[v + 1] = static_cast<int>(neighbours_.size());
  }
}

double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

std::vector<Eigen::Vector2d> flatten_ring(const Eigen::MatrixX3d& vertices, int centre,
                                          std::span<const int> neighbours, bool closed) {
  const std::size_t count = neighbours.size();
  std::vector<Eigen::Vector2d> points(count, Eigen::Vector2d::Zero());
  if (count == 0) return points;
  const Eigen::Vector3d p = vertices.row(centre).transpose();
  const auto spoke = [&](std::size_t k) -> Eigen::Vector3d {
    return vertices.row(neighbours[k]).transpose() - p;
  };

  // Angles between consecutive spokes; a closed fan also has the angle from the last to the first.
  const std::size_t angle_count = closed ? count : count - 1;
  std::vector<double> angles(angle_count);
  double total = 0.0;
  for (std::size_t k = 0; k < angle_count; ++k) {
    angles[k] = angle_between(spoke(k), spoke((k + 1) % count));
    total += angles[k];
  }
  // Closed fans: the exponential map rescales the total angle to a full turn.
  const double scale = (closed && total > 0.0) ? 2.0 * std::numbers::pi / total : 1.0;

  double phi = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    const double radius = spoke(k).norm();
    points[k] = radius * Eigen::Vector2d(std::cos(phi), std::sin(phi));
    if (k < angle_count) phi += scale * angles[k];
  }
  return points;
}

}  // namespace harmonia::detail
