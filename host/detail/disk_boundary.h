#pragma once
// Internal: the disk check the planar maps run first, and the boundary loop they fix.
//
// Self-contained (directed edges only) so that the maps do not depend on the topology module;
// the messages follow topology.h's conventions (name the vertex/face/edge, say how to fix it).

#include <string>
#include <vector>

#include "harmonia/mesh.h"
#include "harmonia/types.h"

namespace harmonia::detail {

//! Outcome of examine_disk: ok and the boundary loop, or the first problem found.
struct DiskInput {
  Status status = Status::ok;
  std::string message;
  //! The boundary loop, mesh to its left (counter-clockwise for outward normals), starting at its
  //! smallest vertex index. Empty unless status is ok.
  std::vector<int> boundary_loop;
};

//! Checks, in order: faces present, indices in range, finite coordinates, no repeated vertex in a
//! face, no unreferenced vertex, edge-manifold and consistently oriented, one boundary loop through
//! manifold vertices, connected, Euler characteristic 1 (genus 0).
[[nodiscard]] DiskInput examine_disk(const Mesh& mesh);

}  // namespace harmonia::detail
