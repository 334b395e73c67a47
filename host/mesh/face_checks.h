#pragma once
// Face-level checks shared by topology analysis, cleanup and cutting: degenerate faces, duplicate
// faces, and the breadth-first orientation of the faces of each component.

#include <vector>

#include "harmonia/mesh.h"
#include "mesh/edge_table.h"

namespace harmonia::detail {

//! True if the face uses one vertex twice.
[[nodiscard]] bool face_has_repeated_vertex(const Mesh& mesh, int face);

//! True if the face uses one vertex twice or has zero area. "Zero" is relative to the face's size:
//! |cross product| <= 1e-14 * (longest edge)^2, i.e. the sine of its largest angle is below ~1e-14,
//! which only collinear corners (up to rounding) reach.
[[nodiscard]] bool face_is_degenerate(const Mesh& mesh, int face);

//! Faces with the same vertex set as an earlier face (the later ones), increasing.
[[nodiscard]] std::vector<int> duplicate_face_list(const Mesh& mesh);

//! True if the face holds the half-edge from->to.
[[nodiscard]] bool face_has_halfedge(const Mesh& mesh, int face, int from, int to);

//! Result of orienting the faces of each edge-connected component to agree with its first face.
struct FaceOrientation {
  std::vector<int> component;   //!< Per face: component id (faces joined across two-face edges).
  std::vector<int> first_face;  //!< Per component: its smallest face index (the reference).
  std::vector<char> flip;       //!< Per face: 1 if it must be reversed to agree with the reference.
  bool orientable = true;
  int conflict_face = -1;  //!< A face where the orientation contradicts itself (not orientable).
};

//! Breadth-first search over faces in index order, crossing only edges with exactly two faces
//! (faces with a repeated vertex are left alone, each in its own component).
[[nodiscard]] FaceOrientation orient_faces(const Mesh& mesh, const EdgeTable& edges);

}  // namespace harmonia::detail
