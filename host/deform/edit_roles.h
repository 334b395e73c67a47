#pragma once
// Internal: what every vertex does in an edit (harmonia/surface_editor.h's EditRegions checked and
// resolved): free, fixed (a fixed vertex, one outside the region of interest, or one that no face
// uses), or on handle i.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"
#include "harmonia/surface_editor.h"

namespace harmonia::detail {

struct EditRoles {
  static constexpr int kFree = -1;
  static constexpr int kFixed = -2;
  std::vector<int> role;              // #V: kFree, kFixed, or the handle's index.
  Eigen::VectorXi constrained;        // The non-free vertices, in increasing order.
  int handle_count = 0;
};

// Resolves the regions. Returns an empty string, or what is wrong (an index out of range naming the
// set and the index, a vertex in two sets, an empty handle, no handle, a connected part of the mesh
// with free vertices and no constrained one, naming one of its vertices).
[[nodiscard]] std::string resolve_edit_roles(const Mesh& mesh, const EditRegions& regions,
                                             EditRoles& roles);

}  // namespace harmonia::detail
