#pragma once
// Directed-edge lookups built by sorting (no hash maps, so every traversal is deterministic).
//
// A face (a, b, c) owns the three half-edges a->b, b->c, c->a. On a consistently oriented manifold
// each interior edge appears once in each direction, and a boundary edge appears once.

#include <span>
#include <vector>

#include "harmonia/mesh.h"

namespace harmonia::detail {

//! One corner of a face seen as the half-edge leaving it: face(corner) -> face(corner + 1).
struct Halfedge {
  int from = 0;
  int to = 0;
  int face = 0;
  int corner = 0;  //!< 0, 1 or 2: position of `from` in the face.
};

//! All half-edges of a mesh sorted by (from, to, face), with the start of each vertex's run:
//! lookups by binary search among the few half-edges leaving one vertex.
class HalfedgeMap {
 public:
  explicit HalfedgeMap(const Mesh& mesh);

  //! The face holding the half-edge from->to, or -1. If several faces hold it (a non-manifold or
  //! inconsistently oriented mesh) the one with the smallest index.
  [[nodiscard]] int face_of(int from, int to) const;
  //! Half-edges leaving `vertex`, sorted by (to, face).
  [[nodiscard]] std::span<const Halfedge> leaving(int vertex) const;

 private:
  std::vector<Halfedge> halfedges_;
  std::vector<std::size_t> vertex_offset_;  //!< Half-edges leaving v: [offset[v], offset[v + 1]).
};

}  // namespace harmonia::detail
