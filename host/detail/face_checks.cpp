#include "host/detail/face_checks.h"

#include <algorithm>
#include <array>
#include <deque>
#include <tuple>

#include <Eigen/Geometry>

namespace harmonia::detail {

bool face_has_repeated_vertex(const Mesh& mesh, int face) {
  const int a = mesh.faces(face, 0);
  const int b = mesh.faces(face, 1);
  const int c = mesh.faces(face, 2);
  return a == b || b == c || c == a;
}

bool face_is_degenerate(const Mesh& mesh, int face) {
  if (face_has_repeated_vertex(mesh, face)) return true;
  const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(face, 0));
  const Eigen::Vector3d b = mesh.vertices.row(mesh.faces(face, 1));
  const Eigen::Vector3d c = mesh.vertices.row(mesh.faces(face, 2));
  const double longest_squared =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  const double twice_area = (b - a).cross(c - a).norm();
  return twice_area <= 1e-14 * longest_squared;
}

std::vector<int> duplicate_face_list(const Mesh& mesh) {
  std::vector<std::tuple<std::array<int, 3>, int>> keyed;
  keyed.reserve(static_cast<std::size_t>(mesh.face_count()));
  for (int face = 0; face < mesh.face_count(); ++face) {
    std::array<int, 3> key{mesh.faces(face, 0), mesh.faces(face, 1), mesh.faces(face, 2)};
    std::sort(key.begin(), key.end());
    keyed.emplace_back(key, face);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<int> duplicates;
  for (std::size_t k = 1; k < keyed.size(); ++k) {
    if (std::get<0>(keyed[k]) == std::get<0>(keyed[k - 1])) duplicates.push_back(std::get<1>(keyed[k]));
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

FaceOrientation orient_faces(const Mesh& mesh, const std::vector<EdgeFaces>& edges) {
  const int face_count = mesh.face_count();
  FaceOrientation result;
  result.component.assign(static_cast<std::size_t>(face_count), -1);
  result.flip.assign(static_cast<std::size_t>(face_count), 0);

  std::deque<int> queue;
  for (int seed = 0; seed < face_count; ++seed) {
    if (result.component[static_cast<std::size_t>(seed)] >= 0) continue;
    const int id = static_cast<int>(result.first_face.size());
    result.first_face.push_back(seed);
    result.component[static_cast<std::size_t>(seed)] = id;
    if (face_has_repeated_vertex(mesh, seed)) continue;
    queue.push_back(seed);
    while (!queue.empty()) {
      const int face = queue.front();
      queue.pop_front();
      for (int corner = 0; corner < 3; ++corner) {
        // The half-edge a->b as this face is written; after its own flip it runs the other way.
        const int a = mesh.faces(face, corner);
        const int b = mesh.faces(face, (corner + 1) % 3);
        const EdgeFaces& edge = edges[static_cast<std::size_t>(find_edge(edges, a, b))];
        if (edge.faces.size() != 2) continue;
        const int other = edge.faces[0] == face ? edge.faces[1] : edge.faces[0];
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
