#pragma once
//! \file gltf_output.h
//! \brief The commands' glTF outputs: a map written into the input's glTF document (or a new one
//! holding a mesh read from another format) as a texture-coordinate set, or new positions.

#include <string>

#include "harmonia/mesh.h"

namespace harmonia::cli {

//! Writes the layout of the mesh the program read from `input` into the glTF file `output`: a new
//! texture-coordinate set per primitive (the lowest it lacks), vertices split where the layout
//! has seams. `layout.mesh.faces` must be the faces read (a repair that changed them is refused
//! as a usage error).
void write_layout_gltf(const std::string& input, const std::string& output,
                       const TexturedMesh& layout);

//! Writes new positions (a row per vertex of the mesh the program read from `input`) into the
//! glTF file `output`, each primitive's in its own coordinates.
void write_positions_gltf(const std::string& input, const std::string& output,
                          const Eigen::MatrixX3d& positions);

}  // namespace harmonia::cli
