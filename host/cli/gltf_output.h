#pragma once
//! \file gltf_output.h
//! \brief The commands' glTF outputs: a map written into the input's glTF document (or a new one
//! holding a mesh read from another format) as a texture-coordinate set, or new positions.

#include <string>

#include <CLI/CLI.hpp>

#include "harmonia/gltf.h"
#include "harmonia/mesh.h"

namespace harmonia::cli {

//! --texcoord N and --overwrite, the texture-coordinate set a glTF output's map goes to.
void add_texcoord_options(CLI::App& command, GltfWriteOptions& options);

//! Writes the layout of the mesh the program read from `input` into the glTF file `output`: a new
//! texture-coordinate set per primitive (`options`; by default the lowest it lacks), vertices
//! split where the layout has seams. `layout.mesh.faces` must be the faces read; a repair that
//! changed them, or a set the options may not take, is refused as a usage error before anything
//! is written.
void write_layout_gltf(const std::string& input, const std::string& output,
                       const TexturedMesh& layout, const GltfWriteOptions& options = {});

//! Writes new positions (a row per vertex of the mesh the program read from `input`) into the
//! glTF file `output`, each primitive's in its own coordinates.
void write_positions_gltf(const std::string& input, const std::string& output,
                          const Eigen::MatrixX3d& positions);

}  // namespace harmonia::cli
