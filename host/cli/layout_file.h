#pragma once
//! \file layout_file.h
//! \brief Reading a layout of a 3D mesh as `eval` and `compare` take it: an OBJ with `vt` lines and
//! texture indices, or any mesh with the same faces whose x, y are the UVs.

#include <Eigen/Core>
#include <string>

#include "harmonia/mesh.h"

namespace harmonia::cli {

//! The layout: per-corner indices into uv, one row per face.
struct Layout {
  Eigen::MatrixX2d uv;
  Eigen::MatrixX3i uv_faces;
};

//! Reads PARAM: the `vt` layout of an OBJ that has `vt` lines, else the x, y of any mesh file.
//! Every problem is a CliFailure(input) whose reason names the file.
[[nodiscard]] Layout load_layout(const std::string& path);

//! The layout must belong to the 3D mesh: one face per 3D face, in the same order, and no UV
//! vertex standing for two different 3D vertices (a cut may split a 3D vertex into several UV
//! vertices, never the reverse). This accepts the mesh's own faces and the faces of a cut of it.
//! Otherwise CliFailure(input) naming both files and the first mismatch.
void require_layout_of(const Mesh& mesh3d, const std::string& mesh_path, const Layout& layout,
                       const std::string& layout_path);

}  // namespace harmonia::cli
