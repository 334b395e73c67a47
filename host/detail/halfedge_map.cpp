#include "host/detail/halfedge_map.h"

#include <algorithm>
#include <tuple>

namespace harmonia::detail {

namespace {

bool halfedge_less(const Halfedge& a, const Halfedge& b) {
  return std::tie(a.from, a.to, a.face) < std::tie(b.from, b.to, b.face);
}

}  // namespace

HalfedgeMap::HalfedgeMap(const Mesh& mesh) {
  halfedges_.reserve(static_cast<std::size_t>(mesh.face_count()) * 3);
  for (int face = 0; face < mesh.face_count(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      halfedges_.push_back(
          {mesh.faces(face, corner), mesh.faces(face, (corner + 1) % 3), face, corner});
    }
  }
  std::sort(halfedges_.begin(), halfedges_.end(), halfedge_less);
}

std::vector<Halfedge>::const_iterator HalfedgeMap::first_not_before(int from, int to) const {
  const Halfedge key{from, to, -1, 0};
  return std::lower_bound(halfedges_.begin(), halfedges_.end(), key, halfedge_less);
}

int HalfedgeMap::face_of(int from, int to) const {
  const auto it = first_not_before(from, to);
  if (it == halfedges_.end() || it->from != from || it->to != to) return -1;
  return it->face;
}

int HalfedgeMap::count(int from, int to) const {
  int found = 0;
  for (auto it = first_not_before(from, to);
       it != halfedges_.end() && it->from == from && it->to == to; ++it) {
    ++found;
  }
  return found;
}

bool HalfedgeMap::is_boundary_halfedge(int from, int to) const {
  return face_of(from, to) >= 0 && face_of(to, from) < 0;
}

std::vector<Halfedge> HalfedgeMap::leaving(int vertex) const {
  std::vector<Halfedge> result;
  for (auto it = first_not_before(vertex, -1); it != halfedges_.end() && it->from == vertex; ++it) {
    result.push_back(*it);
  }
  return result;
}

std::vector<EdgeFaces> edges_with_faces(const Mesh& mesh) {
  // (first, second, face) triples, sorted, then grouped by edge.
  std::vector<std::tuple<int, int, int>> uses;
  uses.reserve(static_cast<std::size_t>(mesh.face_count()) * 3);
  for (int face = 0; face < mesh.face_count(); ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = mesh.faces(face, corner);
      const int b = mesh.faces(face, (corner + 1) % 3);
      if (a == b) continue;
      uses.emplace_back(std::min(a, b), std::max(a, b), face);
    }
  }
  std::sort(uses.begin(), uses.end());
  uses.erase(std::unique(uses.begin(), uses.end()), uses.end());

  std::vector<EdgeFaces> edges;
  for (const auto& [first, second, face] : uses) {
    if (edges.empty() || edges.back().first != first || edges.back().second != second) {
      edges.push_back({first, second, {}});
    }
    edges.back().faces.push_back(face);
  }
  return edges;
}

int find_edge(const std::vector<EdgeFaces>& edges, int a, int b) {
  const int first = std::min(a, b);
  const int second = std::max(a, b);
  const auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(first, second),
                                   [](const EdgeFaces& edge, const std::pair<int, int>& key) {
                                     return std::tie(edge.first, edge.second) <
                                            std::tie(key.first, key.second);
                                   });
  if (it == edges.end() || it->first != first || it->second != second) return -1;
  return static_cast<int>(it - edges.begin());
}

}  // namespace harmonia::detail
