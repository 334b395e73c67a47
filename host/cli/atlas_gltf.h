#pragma once
//! \file atlas_gltf.h
//! \brief `harmonia atlas IN OUT.glb|OUT.gltf`: atlases written into a glTF document (IN's, or a
//! new one holding IN's mesh): one atlas per mesh (`--group mesh`, the default), per primitive, or
//! one for every mesh of the scene at one texel density (`--group scene`), each put into a
//! texture-coordinate set of its primitives (harmonia/gltf.h) with a `_CHART` vertex attribute
//! naming each vertex's chart.

#include "cli/atlas.h"

namespace harmonia::cli {

[[nodiscard]] ExitCode run_gltf_atlas(const AtlasOptions& options, const GlobalOptions& global);

}  // namespace harmonia::cli
