#pragma once
// The unique undirected edges of a mesh with the half-edges that use them, in flat arrays.
//
// Built by a counting sort of the half-edges on their smaller vertex, then a sort of each (small)
// bucket on the larger vertex: O(F) plus the cost of sorting each vertex's few edges, without hash
// maps, so every traversal is deterministic. Everything a topology check needs per edge (how many
// faces, in which directions, at which corners) is read from one contiguous run per edge.

#include <cstdint>
#include <span>
#include <vector>

#include "harmonia/mesh.h"

namespace harmonia::detail {

//! One use of an edge by a face: the half-edge face(corner) -> face(corner + 1). Ordered by the
//! edge's larger vertex, then by corner: the order that groups an edge's uses while sorting.
class EdgeUse {
 public:
  EdgeUse() = default;
  EdgeUse(int larger_vertex, std::uint32_t corner_index, bool backward)
      : key_((static_cast<std::uint64_t>(larger_vertex) << 32) | (corner_index * 2u + backward)) {}
  //! The larger vertex of the edge.
  [[nodiscard]] int larger_vertex() const { return static_cast<int>(key_ >> 32); }
  //! 3 * face + corner.
  [[nodiscard]] int corner_index() const { return static_cast<int>((key_ & 0xffffffffu) >> 1); }
  [[nodiscard]] int face() const { return corner_index() / 3; }
  [[nodiscard]] int corner() const { return corner_index() % 3; }
  //! The corner index of the half-edge's end vertex in the same face.
  [[nodiscard]] int next_corner_index() const { return face() * 3 + (corner() + 1) % 3; }
  //! True if the half-edge runs second -> first.
  [[nodiscard]] bool backward() const { return (key_ & 1u) != 0; }

  friend bool operator<(const EdgeUse& a, const EdgeUse& b) { return a.key_ < b.key_; }

 private:
  std::uint64_t key_ = 0;  // larger vertex (high 32 bits), 2 * corner index + backward (low 32)
};

//! Edges sorted by (first, second), first < second, skipping the self-loops of faces with a
//! repeated index. A face with two distinct vertices, (a, b, a), uses its edge twice (once in each
//! direction); any other face uses each of its edges once.
class EdgeTable {
 public:
  //! Throws Error(invalid_input) for more than kMaxFaces faces (the corner indices are packed into
  //! 32 bits).
  explicit EdgeTable(const Mesh& mesh);
  static constexpr int kMaxFaces = 715'827'882;  // 2 * 3 * faces must fit in 32 bits

  [[nodiscard]] int size() const { return static_cast<int>(first_.size()); }
  [[nodiscard]] int first(int edge) const { return first_[static_cast<std::size_t>(edge)]; }
  [[nodiscard]] int second(int edge) const { return second_[static_cast<std::size_t>(edge)]; }
  //! Number of distinct faces using the edge: 1 on the boundary, 2 inside, more if non-manifold.
  [[nodiscard]] int face_count(int edge) const {
    return face_count_[static_cast<std::size_t>(edge)];
  }
  //! The half-edges on the edge, by increasing corner index (so by increasing face).
  [[nodiscard]] std::span<const EdgeUse> uses(int edge) const {
    const auto begin = static_cast<std::size_t>(use_offset_[static_cast<std::size_t>(edge)]);
    const auto end = static_cast<std::size_t>(use_offset_[static_cast<std::size_t>(edge) + 1]);
    return {uses_.data() + begin, end - begin};
  }
  //! For an edge with two faces: the one that is not `face`.
  [[nodiscard]] int other_face(int edge, int face) const;
  //! Index of the edge between a and b (either order), or -1.
  [[nodiscard]] int find(int a, int b) const;
  //! Per corner (3 * face + corner): the edge of its half-edge, or -1 for a self-loop. Built on
  //! request, for walks from face to face.
  [[nodiscard]] std::vector<int> corner_edges() const;

 private:
  std::size_t corner_count_ = 0;
  std::vector<int> first_;
  std::vector<int> second_;
  std::vector<int> face_count_;
  std::vector<int> use_offset_;  //!< Uses of edge e: uses_[use_offset_[e] .. [e + 1]).
  std::vector<EdgeUse> uses_;
  std::vector<int> vertex_offset_;  //!< Edges with first == v: [vertex_offset_[v] .. [v + 1]).
};

}  // namespace harmonia::detail
