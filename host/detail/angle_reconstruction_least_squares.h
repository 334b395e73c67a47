#pragma once
// Internal: the angle-based least-squares reconstruction of UVs from corner angles (thesis
// section 3.3, [SLMB05]); see angle_reconstruction_least_squares.cpp.

#include <vector>

#include <Eigen/Core>

#include "detail/backend.h"
#include "detail/map_pipeline.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia::detail {

//! The two vertices whose positions fix the similarity left free by angles: `first` at (0, 0),
//! `second` at (distance, 0).
struct LayoutPins {
  int first = 0;
  int second = 1;
  double distance = 1.0;
};

//! UVs (#V x 2, pins as given) that satisfy the sine-law relation of every face in the least
//! squares sense. `angles` must be valid (#F x 3, finite, in (0, pi)) and the mesh a disk.
//! `vertex_ordering` is a fill-reducing ordering of the vertices (may be empty). Records the
//! phases assembly/analysis/factorization/solve on `clock`; on failure sets report.status and
//! returns an empty matrix.
[[nodiscard]] Eigen::MatrixX2d least_squares_layout(const Mesh& mesh,
                                                    const Eigen::MatrixX3d& angles,
                                                    const LayoutPins& pins, Backend& backend,
                                                    const SolverOptions& options,
                                                    const std::vector<int>& vertex_ordering,
                                                    SolveReport& report, PhaseClock& clock);

}  // namespace harmonia::detail
