// Greedy reconstruction of UVs from corner angles (thesis section 3.3).
//
// A walk over the faces: the first face is laid out from its angles alone; stepping across an
// edge into a new face, the two ends of the edge are placed already and the face's third vertex
// follows from the sine-law relation of that face (angle_reconstruction_sine_law.h). A vertex
// keeps its first position: the face that closes a fan around an interior vertex is never
// constructed explicitly, so with inconsistent angles the error lands in those closing faces.
//
// Breadth-first, not depth-first as in the thesis: a new vertex inherits the errors of the two
// it is built from, (1 - c) e_i + c e_j with |1 - c| + |c| > 1 for the sine-law factor c, so where
// the two come from different branches of the walk the error grows geometrically with the depth
// of the construction tree. A depth-first walk snakes through the whole mesh (depth ~ #F): on a
// 30 x 8 developable strip rounding errors alone grow to 20% of the edge lengths, and inconsistent
// angles overflow on corpus meshes. Breadth-first makes every face's depth its distance from the
// start face, the least any walk can achieve, and reproduces consistent angles to rounding.
// The queue visits the neighbours of a face in corner order, so the layout is deterministic.

#include "abf/angle_reconstruction_greedy.h"

#include <complex>
#include <vector>

#include "abf/angle_reconstruction_sine_law.h"
#include "mesh/edge_table.h"

namespace harmonia::detail {
namespace {

// The first face holding `vertex` (smallest index), or 0.
int first_face_of(const Mesh& mesh, int vertex) {
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.faces(f, k) == vertex) return f;
  return 0;
}

}  // namespace

Eigen::MatrixX2d greedy_layout(const Mesh& mesh, const Eigen::MatrixX3d& angles, int start_vertex) {
  const int vertex_count = mesh.vertex_count();
  const int face_count = mesh.face_count();
  std::vector<std::complex<double>> position(static_cast<std::size_t>(vertex_count));
  std::vector<char> placed(static_cast<std::size_t>(vertex_count), 0);
  std::vector<char> visited(static_cast<std::size_t>(face_count), 0);
  const EdgeTable edges(mesh);
  const std::vector<int> corner_edge = edges.corner_edges();

  // Places the vertex at corner `corner` of face f from the face's two other (placed) corners.
  const auto place_corner = [&](int f, int corner) {
    const Eigen::Vector3d face_angles = angles.row(f).transpose();
    const SineLawRelation relation = sine_law_relation(face_angles, corner);
    const std::complex<double> anchor = position[mesh.faces(f, relation.anchor)];
    const std::complex<double> along = position[mesh.faces(f, relation.along)];
    const int vertex = mesh.faces(f, corner);
    position[vertex] = anchor + relation.factor * (along - anchor);
    placed[vertex] = 1;
  };

  // The first face: the start vertex at 0, its next corner at 1, the third from the angles.
  const int first_face = first_face_of(mesh, start_vertex);
  int start_corner = 0;
  while (mesh.faces(first_face, start_corner) != start_vertex && start_corner < 2) ++start_corner;
  const int next_vertex = mesh.faces(first_face, (start_corner + 1) % 3);
  position[start_vertex] = 0.0;
  position[next_vertex] = 1.0;
  placed[start_vertex] = placed[next_vertex] = 1;
  place_corner(first_face, (start_corner + 2) % 3);
  visited[first_face] = 1;

  // Breadth-first: faces are laid out in the order they enter the queue.
  std::vector<int> queue{first_face};
  queue.reserve(static_cast<std::size_t>(face_count));
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int face = queue[head];
    for (int corner = 0; corner < 3; ++corner) {
      const int edge = corner_edge[3 * static_cast<std::size_t>(face) + corner];
      if (edge < 0 || edges.face_count(edge) != 2) continue;  // Boundary edge.
      const int neighbour = edges.other_face(edge, face);
      if (neighbour < 0 || visited[neighbour]) continue;
      visited[neighbour] = 1;
      for (int k = 0; k < 3; ++k)
        if (!placed[mesh.faces(neighbour, k)]) place_corner(neighbour, k);
      queue.push_back(neighbour);
    }
  }

  Eigen::MatrixX2d uv(vertex_count, 2);
  for (int v = 0; v < vertex_count; ++v) uv.row(v) << position[v].real(), position[v].imag();
  return uv;
}

}  // namespace harmonia::detail
