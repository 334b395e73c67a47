#pragma once
//! \file mesh.h
//! \brief The triangle mesh type: a vertex list and a face list, nothing more (thesis chapter 9:
//! algorithms work on the vertex and face arrays and the sparse matrices built from them).

#include <Eigen/Core>

namespace harmonia {

//! A triangle mesh.
//!   vertices: #V by 3, positions.
//!   faces:    #F by 3, 0-based vertex indices, counter-clockwise seen from the outside/front.
struct Mesh {
  Eigen::MatrixX3d vertices;
  Eigen::MatrixX3i faces;

  [[nodiscard]] int vertex_count() const { return static_cast<int>(vertices.rows()); }
  [[nodiscard]] int face_count() const { return static_cast<int>(faces.rows()); }
};

//! A mesh with a texture layout that may have seams (a cut makes several UVs per 3D vertex).
//!   mesh:     the 3D mesh, in the input's vertex order.
//!   uv:       #UV by 2 texture coordinates.
//!   uv_faces: #F by 3, rows of `uv` used by each corner of the matching face of `mesh.faces`.
//! Without seams #UV = #V and uv_faces = mesh.faces.
struct TexturedMesh {
  Mesh mesh;
  Eigen::MatrixX2d uv;
  Eigen::MatrixX3i uv_faces;
};

}  // namespace harmonia
