#pragma once
// The lines of an OBJ file that carries a layout (a `vt` per corner), shared by the writers of
// maps (io_write.cpp) and atlases (atlas/atlas_obj.cpp): the faces as `f v/t` or `f v/t/n`, and,
// when the file keeps an asset's parts (harmonia/obj_asset.h), its material libraries, normals
// and the `o`, `g`, `usemtl` and `s` lines wherever they change from one face to the next.

#include <filesystem>
#include <functional>
#include <string>

#include <Eigen/Core>

#include "harmonia/obj_asset.h"

namespace harmonia::detail {

// An asset whose parts a written file keeps, and for each written face the asset's face it is
// (empty: the same face).
struct KeptAsset {
  const ObjAsset& asset;
  const Eigen::VectorXi& asset_face;
};

// `mtllib` lines naming the asset's libraries as seen from `output`'s folder.
void append_material_libraries(std::string& out, const ObjAsset& asset,
                               const std::filesystem::path& output);

// `vn` lines.
void append_normals(std::string& out, const ObjAsset& asset);

// The faces (`f v/t` with 1-based indices, `/n` added where the kept asset has a normal at that
// corner), with the kept asset's `o`, `usemtl` and `s` lines where they change and a `g` line
// wherever the group text changes: `group_prefix(face)` (empty: none) followed by the asset's own
// group names.
void append_layout_faces(std::string& out, const Eigen::MatrixX3i& faces,
                         const Eigen::MatrixX3i& uv_faces, const KeptAsset* kept,
                         const std::function<std::string(Eigen::Index)>& group_prefix);

// Throws Error(invalid_input) naming `path` unless `asset_face` fits: empty with as many faces as
// the asset, or one entry per face naming a face of the asset.
void check_kept_asset(const std::filesystem::path& path, Eigen::Index faces, const KeptAsset& kept);

}  // namespace harmonia::detail
