#pragma once
// Internal: angles_to_uv() for callers that have already validated the mesh and the angles
// (linear ABF, ABF). The public entry point checks the arrays, the disk topology and every angle
// and computes a fill-reducing vertex ordering: on a million-face mesh that is about a tenth of
// the reconstruction, all of it redundant for a caller that has the loop, valid angles and an
// ordering of its own.

#include <vector>

#include <Eigen/Core>

#include "harmonia/angles_to_uv.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

//! What the caller vouches for: `loop` is the mesh's one boundary loop (validate_disk_input), the
//! angles are #F x 3, finite and in (0, pi), and `vertex_ordering` is a fill-reducing ordering of
//! all vertices (operator_pattern) or empty (the solver then orders the unknowns itself). The pins
//! of the options are still checked (they are the caller's options, not validated input).
struct ValidatedAngleInput {
  const std::vector<int>& loop;
  const std::vector<int>& vertex_ordering;
};

//! angles_to_uv() without the input validation and ordering it would repeat; the same result for
//! the same ordering.
[[nodiscard]] MapResult angles_to_uv_validated(const Mesh& mesh, const Eigen::MatrixX3d& angles,
                                               const AnglesToUvOptions& options,
                                               const ValidatedAngleInput& input);

}  // namespace harmonia::detail
