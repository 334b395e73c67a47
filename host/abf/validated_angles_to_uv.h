#pragma once
// Internal: angles_to_uv() for callers that have already validated the mesh and the angles
// (linear ABF, ABF). The public entry point checks the arrays, the disk topology and every angle
// and computes a fill-reducing vertex ordering: on a million-face mesh that is about a tenth of
// the reconstruction, all of it redundant for a caller that has the loop, valid angles and an
// ordering of its own.

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "abf/angle_reconstruction_least_squares.h"
#include "backend/backend.h"
#include "solve/uv_system_solver.h"

#include "harmonia/angles_to_uv.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"

namespace harmonia::detail {

//! A least-squares reconstruction set up before its angles are known: the backend, the pins and
//! the system (LeastSquaresLayout), whose symbolic analysis a caller can run ahead (analyze(),
//! on another thread where `overlappable`) while it computes the angles.
struct PreparedLayout {
  std::unique_ptr<Backend> backend;
  LayoutPins pins;
  std::unique_ptr<LeastSquaresLayout> system;
  //! The analysis may run beside other work of the caller: a CPU backend, which has no device
  //! queue to share.
  bool overlappable = false;
};

//! The reconstruction of `options` prepared for `mesh` (a validated disk with boundary `loop`):
//! the caller sets the system's vertex ordering (and may analyze it) before handing it to
//! angles_to_uv_validated. nullptr when `options` ask for another method, or their pins or
//! backend are not usable: angles_to_uv_validated then reports why.
[[nodiscard]] std::unique_ptr<PreparedLayout> prepare_layout(const Mesh& mesh,
                                                             const AnglesToUvOptions& options,
                                                             const std::vector<int>& loop);

//! What the caller vouches for: `loop` is the mesh's one boundary loop (validate_disk_input), the
//! angles are #F x 3, finite and in (0, pi), and `vertex_ordering` is a fill-reducing ordering of
//! all vertices (operator_pattern) or empty (the solver then orders the unknowns itself). The pins
//! of the options are still checked (they are the caller's options, not validated input).
//! `prepared`, when given, is prepare_layout's for the same mesh, options and loop, with its
//! vertex ordering set (`vertex_ordering` is then not read).
struct ValidatedAngleInput {
  const std::vector<int>& loop;
  const std::vector<int>& vertex_ordering;
  PreparedLayout* prepared = nullptr;
};

//! angles_to_uv() without the input validation and ordering it would repeat; the same result for
//! the same ordering.
[[nodiscard]] MapResult angles_to_uv_validated(const Mesh& mesh, const Eigen::MatrixX3d& angles,
                                               const AnglesToUvOptions& options,
                                               const ValidatedAngleInput& input);

}  // namespace harmonia::detail
