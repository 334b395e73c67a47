#pragma once
// Internal: 1-to-4 midpoint subdivision of a triangle mesh without smoothing: every edge gets a
// vertex at its midpoint and every triangle becomes four similar ones (its three corners' and the
// middle one), so the surface, its orientation and its topology are unchanged and every graph
// distance between the input's vertices doubles.

#include "harmonia/mesh.h"

namespace harmonia::detail {

// The subdivided mesh: the input's vertices first, in their order (a vertex keeps its index),
// then one per edge; triangle f becomes triangles 4f .. 4f + 3, each oriented as f.
[[nodiscard]] Mesh midpoint_subdivision(const Mesh& mesh);

}  // namespace harmonia::detail
