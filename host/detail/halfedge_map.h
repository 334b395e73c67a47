#pragma once
// Directed-edge lookups built by sorting (no hash maps, so every traversal is deterministic).
//
// A face (a, b, c) owns the three half-edges a->b, b->c, c->a. On a consistently oriented manifold
// each interior edge appears once in each direction, and a boundary edge appears once.

#include <cstdint>
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

//! All half-edges of a mesh sorted by (from, to, face): lookups by binary search.
class HalfedgeMap {
 public:
  explicit HalfedgeMap(const Mesh& mesh);

  //! The face holding the half-edge from->to, or -1. If several faces hold it (a non-manifold or
  //! inconsistently oriented mesh) the one with the smallest index.
  [[nodiscard]] int face_of(int from, int to) const;
  //! Number of faces holding the half-edge from->to.
  [[nodiscard]] int count(int from, int to) const;
  //! True if from->to exists and to->from does not: an edge of the boundary, mesh on its left.
  [[nodiscard]] bool is_boundary_halfedge(int from, int to) const;
  //! Half-edges leaving `vertex`, sorted by (to, face).
  [[nodiscard]] std::vector<Halfedge> leaving(int vertex) const;

  [[nodiscard]] const std::vector<Halfedge>& sorted() const { return halfedges_; }

 private:
  [[nodiscard]] std::vector<Halfedge>::const_iterator first_not_before(int from, int to) const;
  std::vector<Halfedge> halfedges_;
};

//! An undirected edge (first < second) with the faces that use it, in increasing face order.
struct EdgeFaces {
  int first = 0;
  int second = 0;
  std::vector<int> faces;
};

//! Unique undirected edges of the mesh sorted by (first, second), skipping the self-loops of
//! faces with a repeated index. Each lists the faces using it (a face using an edge twice, as in
//! (a, b, a), is listed once).
[[nodiscard]] std::vector<EdgeFaces> edges_with_faces(const Mesh& mesh);

//! Index of edge (a, b) in the sorted list, or -1.
[[nodiscard]] int find_edge(const std::vector<EdgeFaces>& edges, int a, int b);

}  // namespace harmonia::detail
