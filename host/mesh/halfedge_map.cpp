#include "mesh/halfedge_map.h"

#include <algorithm>
#include <tuple>

namespace harmonia::detail {

HalfedgeMap::HalfedgeMap(const Mesh& mesh) {
  const auto face_count = static_cast<std::size_t>(mesh.face_count());
  const auto vertex_count = static_cast<std::size_t>(mesh.vertex_count());
  // Counting sort by `from` (faces increasing within each vertex), then a sort of each vertex's
  // few half-edges by (to, face).
  vertex_offset_.assign(vertex_count + 1, 0);
  for (std::size_t face = 0; face < face_count; ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      ++vertex_offset_[static_cast<std::size_t>(
                           mesh.faces(static_cast<Eigen::Index>(face), corner)) +
                       1];
    }
  }
  for (std::size_t v = 0; v < vertex_count; ++v) vertex_offset_[v + 1] += vertex_offset_[v];
  halfedges_.resize(face_count * 3);
  std::vector<std::size_t> next_slot(vertex_offset_.begin(), vertex_offset_.end() - 1);
  for (std::size_t face = 0; face < face_count; ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const auto row = static_cast<Eigen::Index>(face);
      const int from = mesh.faces(row, corner);
      halfedges_[next_slot[static_cast<std::size_t>(from)]++] = {
          from, mesh.faces(row, (corner + 1) % 3), static_cast<int>(face), corner};
    }
  }
  for (std::size_t v = 0; v < vertex_count; ++v) {
    std::sort(halfedges_.begin() + static_cast<std::ptrdiff_t>(vertex_offset_[v]),
              halfedges_.begin() + static_cast<std::ptrdiff_t>(vertex_offset_[v + 1]),
              [](const Halfedge& a, const Halfedge& b) {
                return std::tie(a.to, a.face) < std::tie(b.to, b.face);
              });
  }
}

int HalfedgeMap::face_of(int from, int to) const {
  const std::span<const Halfedge> candidates = leaving(from);
  const auto it = std::lower_bound(candidates.begin(), candidates.end(), to,
                                   [](const Halfedge& h, int target) { return h.to < target; });
  if (it == candidates.end() || it->to != to) return -1;
  return it->face;
}

std::span<const Halfedge> HalfedgeMap::leaving(int vertex) const {
  const auto v = static_cast<std::size_t>(vertex);
  return {halfedges_.data() + vertex_offset_[v], vertex_offset_[v + 1] - vertex_offset_[v]};
}

}  // namespace harmonia::detail
