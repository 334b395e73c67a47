#pragma once
//! \file atlas_io.h
//! \brief Writing a texture atlas (harmonia/texture_atlas.h) as an OBJ file with per-corner
//! texture coordinates, in the form the atlas evaluator atlaseval.py and xatlas's driver use.
//!
//! The file, in order:
//!   - comments: `# harmonia texture atlas`, the number of charts and the resolution, and
//!     `# xatlas_atlas W H 1` (the atlas size in texels, one atlas; atlaseval.py reads it);
//!   - `v x y z`: the mesh's vertices in their input order;
//!   - `vt u v`: one per chart, vertex and position, in order of first use (the faces of a chart
//!     share the `vt` of a vertex where their corners have the same UV; a chart whose corners at a
//!     vertex differ gets one per position, so nothing is merged or lost): at most 3 #F;
//!   - `f a/ta b/tb c/tc`: the faces in their input order with their corners' vertex order, and a
//!     `g chart_N` line before the first face and wherever the chart changes from the previous
//!     face (`g chart_-1` for faces of no chart).
//! Numbers are printed in the shortest form that reads back to the same double (as write_mesh),
//! so read_textured_obj gives back the same positions and UVs exactly.

#include <filesystem>

#include "harmonia/mesh.h"
#include "harmonia/obj_asset.h"
#include "harmonia/texture_atlas.h"

namespace harmonia {

//! Writes `atlas` of `mesh` to `obj` atomically (an existing file is replaced only when the new one
//! is complete; see harmonia/io.h). Throws Error(invalid_input) naming the problem, before writing
//! anything, when the atlas does not fit the mesh (chart_of_face or corner_uv not one row per face,
//! a chart id outside the atlas' charts, a chart that does not list exactly its faces, a
//! resolution outside 1..32768), when a vertex index is out of range, or when a position or UV is
//! not finite; Error(io_error) naming the file when it cannot be written. UVs outside [0, 1] are
//! written as they are (atlaseval.py reports them).
void write_atlas_obj(const std::filesystem::path& obj, const Mesh& mesh, const TextureAtlas& atlas);

//! The same, keeping what an OBJ asset carried (harmonia/obj_asset.h): its material libraries
//! (named from OUT's folder), normals, and the `o`, `usemtl` and `s` of each face, its groups
//! after the chart's on each `g` line (`g chart_3 Body`). The atlas' `vt` replace the asset's own
//! (OBJ holds one set). `mesh` has the asset's vertices; `asset_face` gives each face of it the
//! asset's face it is (empty: the same faces).
void write_atlas_obj(const std::filesystem::path& obj, const Mesh& mesh, const TextureAtlas& atlas,
                     const ObjAsset& asset, const Eigen::VectorXi& asset_face = {});

}  // namespace harmonia
