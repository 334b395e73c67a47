#pragma once
//! \file obj_asset.h
//! \brief What a Wavefront OBJ asset carries besides positions and faces: its texture coordinates
//! and normals per corner, its material libraries, and the object, group, material and smoothing
//! group of each face. Read with the mesh, so that the writers that put a new layout into an OBJ
//! (harmonia/atlas_io.h, harmonia/io.h) can keep the rest: a textured asset goes through
//! `harmonia atlas` with its materials, normals and names.

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"

namespace harmonia {

struct ObjAsset {
  Mesh mesh;  //!< As read_obj gives it: polygons fanned into triangles, in file order.
  //! The file's `vt` (u, v; a w is dropped) and, per triangle corner, the row it uses or -1.
  Eigen::MatrixX2d texcoords;
  Eigen::MatrixX3i texcoord_faces;
  //! The file's `vn` and, per triangle corner, the row it uses or -1.
  Eigen::MatrixX3d normals;
  Eigen::MatrixX3i normal_faces;
  //! Every `mtllib` argument as written, in file order (relative to `folder`).
  std::vector<std::string> material_libraries;
  //! The folder the file was read from: where relative material library names lead.
  std::filesystem::path folder;
  //! The text after `o`, `g`, `usemtl` and `s` (a name may hold spaces; a `g` line may list
  //! several groups), each text once; and per triangle the entry in force there, or -1 before
  //! the first such statement.
  std::vector<std::string> labels;
  std::vector<int> object_of_face;
  std::vector<int> groups_of_face;
  std::vector<int> material_of_face;
  std::vector<int> smoothing_of_face;

  //! True when the file has something beyond positions and faces that a writer could keep.
  [[nodiscard]] bool carries_more_than_a_mesh() const;
};

//! Reads an OBJ with everything ObjAsset holds. It takes what read_obj takes (harmonia/io.h),
//! with the same errors: a corner's `vt` or `vn` index that leads to none (which read_obj does not
//! look at) is read as none (-1).
[[nodiscard]] ObjAsset read_obj_asset(const std::filesystem::path& path);

}  // namespace harmonia
