#include "mesh/face_checks.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>

#include "mesh/power_of_two_scale.h"

namespace harmonia::detail {

bool face_has_repeated_vertex(const Mesh& mesh, int face) {
  const int a = mesh.faces(face, 0);
  const int b = mesh.faces(face, 1);
  const int c = mesh.faces(face, 2);
  return a == b || b == c || c == a;
}

bool face_is_degenerate(const Mesh& mesh, int face) {
  if (face_has_repeated_vertex(mesh, face)) return true;
  // Scale free, with neither overflow nor underflow: the corners are brought into the safe range
  // (a model at 1e300), then the legs scaled by a power of two to unit size (legs of 1e-103, whose
  // cross product's squared length would be 1e-412, even in a model of unit size).
  Eigen::Matrix3d corners;
  for (int k = 0; k < 3; ++k) corners.row(k) = mesh.vertices.row(mesh.faces(face, k));
  corners = scaled_into_safe_range(corners);
  Eigen::Matrix3d legs;
  legs.row(0) = corners.row(1) - corners.row(0);
  legs.row(1) = corners.row(2) - corners.row(1);
  legs.row(2) = corners.row(0) - corners.row(2);
  if (legs.allFinite()) legs *= unit_scale_for(legs.cwiseAbs().maxCoeff());
  const Eigen::Vector3d ab = legs.row(0), bc = legs.row(1), ca = legs.row(2);
  const double longest_squared = std::max({ab.squaredNorm(), bc.squaredNorm(), ca.squaredNorm()});
  const double twice_area = ab.cross(-ca).norm();
  return twice_area <= 1e-14 * longest_squared;
}

std::vector<int> duplicate_face_list(const Mesh& mesh) {
  // Counting sort of the faces into buckets by their smallest vertex (faces increasing within a
  // bucket), then a sort of each bucket by (middle, largest vertex, face): equal vertex sets end
  // up next to each other, the earliest face first.
  const auto face_count = static_cast<std::size_t>(mesh.face_count());
  const auto vertex_count = static_cast<std::size_t>(mesh.vertex_count());
  std::vector<std::array<int, 3>> sorted_corners(face_count);
  std::vector<std::size_t> bucket_offset(vertex_count + 1, 0);
  for (std::size_t face = 0; face < face_count; ++face) {
    const auto row = static_cast<Eigen::Index>(face);
    std::array<int, 3>& key = sorted_corners[face];
    key = {mesh.faces(row, 0), mesh.faces(row, 1), mesh.faces(row, 2)};
    std::sort(key.begin(), key.end());
    ++bucket_offset[static_cast<std::size_t>(key[0]) + 1];
  }
  for (std::size_t v = 0; v < vertex_count; ++v) bucket_offset[v + 1] += bucket_offset[v];
  using Keyed = std::pair<std::uint64_t, int>;  // ((middle, largest), face)
  std::vector<Keyed> buckets(face_count);
  std::vector<std::size_t> next_slot(bucket_offset.begin(), bucket_offset.end() - 1);
  for (std::size_t face = 0; face < face_count; ++face) {
    const std::array<int, 3>& key = sorted_corners[face];
    buckets[next_slot[static_cast<std::size_t>(key[0])]++] = {
        (static_cast<std::uint64_t>(key[1]) << 32) | static_cast<std::uint32_t>(key[2]),
        static_cast<int>(face)};
  }
  std::vector<int> duplicates;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const auto begin = buckets.begin() + static_cast<std::ptrdiff_t>(bucket_offset[v]);
    const auto end = buckets.begin() + static_cast<std::ptrdiff_t>(bucket_offset[v + 1]);
    std::sort(begin, end);
    for (auto it = begin; it != end; ++it) {
      if (it != begin && it->first == (it - 1)->first) duplicates.push_back(it->second);
    }
  }
  std::sort(duplicates.begin(), duplicates.end());
  return duplicates;
}

bool face_has_halfedge(const Mesh& mesh, int face, int from, int to) {
  for (int corner = 0; corner < 3; ++corner) {
    if (mesh.faces(face, corner) == from && mesh.faces(face, (corner + 1) % 3) == to) return true;
  }
  return false;
}

FaceOrientation orient_faces(const Mesh& mesh, const EdgeTable& edges) {
  const int face_count = mesh.face_count();
  FaceOrientation result;
  result.component.assign(static_cast<std::size_t>(face_count), -1);
  result.flip.assign(static_cast<std::size_t>(face_count), 0);

  const std::vector<int> corner_edge = edges.corner_edges();
  std::vector<int> queue;  // first-in first-out: faces are taken from `head` on
  queue.reserve(static_cast<std::size_t>(face_count));
  for (int seed = 0; seed < face_count; ++seed) {
    if (result.component[static_cast<std::size_t>(seed)] >= 0) continue;
    const int id = static_cast<int>(result.first_face.size());
    result.first_face.push_back(seed);
    result.component[static_cast<std::size_t>(seed)] = id;
    if (face_has_repeated_vertex(mesh, seed)) continue;
    queue.assign(1, seed);
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int face = queue[head];
      for (int corner = 0; corner < 3; ++corner) {
        // The half-edge a->b as this face is written; after its own flip it runs the other way.
        const int a = mesh.faces(face, corner);
        const int b = mesh.faces(face, (corner + 1) % 3);
        const int edge =
            corner_edge[static_cast<std::size_t>(face) * 3 + static_cast<std::size_t>(corner)];
        if (edges.face_count(edge) != 2) continue;
        const int other = edges.other_face(edge, face);
        if (face_has_repeated_vertex(mesh, other)) continue;
        // Neighbours agree when they run the shared edge in opposite directions.
        const bool same_direction = face_has_halfedge(mesh, other, a, b);
        const char wanted = static_cast<char>(result.flip[static_cast<std::size_t>(face)] ^
                                              (same_direction ? 1 : 0));
        if (result.component[static_cast<std::size_t>(other)] < 0) {
          result.component[static_cast<std::size_t>(other)] = id;
          result.flip[static_cast<std::size_t>(other)] = wanted;
          queue.push_back(other);
        } else if (result.flip[static_cast<std::size_t>(other)] != wanted && result.orientable) {
          result.orientable = false;
          result.conflict_face = std::min(face, other);
        }
      }
    }
  }
  return result;
}

}  // namespace harmonia::detail
