#include "mesh/edge_table.h"

#include <algorithm>
#include <string>

#include "harmonia/types.h"

namespace harmonia::detail {

EdgeTable::EdgeTable(const Mesh& mesh) {
  if (mesh.face_count() > kMaxFaces) {
    throw Error(Status::invalid_input, "mesh of " + std::to_string(mesh.face_count()) +
                                           " faces is too large for topology analysis (at most " +
                                           std::to_string(kMaxFaces) + ")");
  }
  const auto face_count = static_cast<std::size_t>(mesh.face_count());
  const auto vertex_count = static_cast<std::size_t>(mesh.vertex_count());
  corner_count_ = face_count * 3;

  // Counting sort of the half-edges into buckets by their smaller vertex. Corners are visited in
  // increasing order, so each bucket holds its corners in increasing order.
  std::vector<int> bucket_offset(vertex_count + 1, 0);  // below 3 * kMaxFaces: fits an int
  for (std::size_t face = 0; face < face_count; ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = mesh.faces(static_cast<Eigen::Index>(face), corner);
      const int b = mesh.faces(static_cast<Eigen::Index>(face), (corner + 1) % 3);
      if (a != b) ++bucket_offset[static_cast<std::size_t>(std::min(a, b)) + 1];
    }
  }
  for (std::size_t v = 0; v < vertex_count; ++v) bucket_offset[v + 1] += bucket_offset[v];

  // Sorting a bucket by (larger vertex, corner) groups the half-edges of each edge, corners (hence
  // faces) increasing within the group.
  uses_.resize(static_cast<std::size_t>(bucket_offset[vertex_count]));
  std::vector<int> next_slot(bucket_offset.begin(), bucket_offset.end() - 1);
  for (std::size_t face = 0; face < face_count; ++face) {
    for (int corner = 0; corner < 3; ++corner) {
      const int a = mesh.faces(static_cast<Eigen::Index>(face), corner);
      const int b = mesh.faces(static_cast<Eigen::Index>(face), (corner + 1) % 3);
      if (a == b) continue;
      const auto corner_index =
          static_cast<std::uint32_t>(face * 3 + static_cast<std::size_t>(corner));
      uses_[static_cast<std::size_t>(next_slot[static_cast<std::size_t>(std::min(a, b))]++)] =
          EdgeUse(std::max(a, b), corner_index, a > b);
    }
  }

  // Runs of equal larger vertex within a bucket are the edges.
  const std::size_t edge_estimate = uses_.size() / 2 + 1;
  first_.reserve(edge_estimate);
  second_.reserve(edge_estimate);
  face_count_.reserve(edge_estimate);
  use_offset_.reserve(edge_estimate + 1);
  vertex_offset_.resize(vertex_count + 1);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    vertex_offset_[v] = size();
    const int begin = bucket_offset[v];
    const int end = bucket_offset[v + 1];
    std::sort(uses_.begin() + begin, uses_.begin() + end);
    int previous_face = -1;
    for (int slot = begin; slot < end; ++slot) {
      const EdgeUse& use = uses_[static_cast<std::size_t>(slot)];
      if (slot == begin || use.larger_vertex() != second_.back()) {
        first_.push_back(static_cast<int>(v));
        second_.push_back(use.larger_vertex());
        face_count_.push_back(0);
        use_offset_.push_back(slot);
        previous_face = -1;
      }
      // The two uses of a face (a, b, a) are neighbours in the run: count the face once.
      if (use.face() != previous_face) ++face_count_.back();
      previous_face = use.face();
    }
  }
  vertex_offset_[vertex_count] = size();
  use_offset_.push_back(static_cast<int>(uses_.size()));
}

int EdgeTable::other_face(int edge, int face) const {
  for (const EdgeUse& use : uses(edge)) {
    if (use.face() != face) return use.face();
  }
  return -1;
}

int EdgeTable::find(int a, int b) const {
  if (a == b) return -1;
  const auto smaller = static_cast<std::size_t>(std::min(a, b));
  const int larger = std::max(a, b);
  const auto begin = second_.begin() + vertex_offset_[smaller];
  const auto end = second_.begin() + vertex_offset_[smaller + 1];
  const auto it = std::lower_bound(begin, end, larger);
  if (it == end || *it != larger) return -1;
  return static_cast<int>(it - second_.begin());
}

std::vector<int> EdgeTable::corner_edges() const {
  std::vector<int> edge_of_corner(corner_count_, -1);
  for (int edge = 0; edge < size(); ++edge) {
    for (const EdgeUse& use : uses(edge)) {
      edge_of_corner[static_cast<std::size_t>(use.corner_index())] = edge;
    }
  }
  return edge_of_corner;
}

}  // namespace harmonia::detail
