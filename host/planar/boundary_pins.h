#pragma once
// Internal: the default pinned vertices of the free-boundary maps (LSCM, angles to UVs).

#include <cstddef>
#include <utility>
#include <vector>

#include "harmonia/mesh.h"

namespace harmonia::detail {

// The two boundary vertices farthest apart in 3D; ties go to the lexicographically first pair.
// Quadratic in the loop's length, which is a few thousand vertices even on million-face meshes.
inline std::pair<int, int> farthest_boundary_pair(const Mesh& mesh, const std::vector<int>& loop) {
  std::pair<int, int> best{loop[0], loop[loop.size() > 1 ? 1 : 0]};
  double best_distance = -1.0;
  for (std::size_t a = 0; a < loop.size(); ++a) {
    for (std::size_t b = a + 1; b < loop.size(); ++b) {
      const double distance =
          (mesh.vertices.row(loop[a]) - mesh.vertices.row(loop[b])).squaredNorm();
      if (distance > best_distance) {
        best_distance = distance;
        best = {loop[a], loop[b]};
      }
    }
  }
  return best;
}

}  // namespace harmonia::detail
