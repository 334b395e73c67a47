#pragma once
// Internal: the angle-based least-squares reconstruction of UVs from corner angles (thesis
// section 3.3, [SLMB05]); see angle_reconstruction_least_squares.cpp.

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "detail/angle_reconstruction_sine_law.h"
#include "detail/backend.h"
#include "detail/map_pipeline.h"
#include "detail/uv_system_solver.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia::detail {

//! Twice the area of a face's reference triangle below which its weight stops growing (the
//! reference triangle has its edge anchor -> along of length 1 and its other edges at most 1, so
//! this is about the smallest angle, in radians, that still gets its full weight).
inline constexpr double kSmallestReferenceHeight = 1e-6;

//! The weight of a face's sine-law residual |r_f|^2 that turns it into the conformal energy of
//! the affine map from the face's reference triangle (0, 1, factor) to its UV triangle:
//! w_f |r_f|^2 = area_ref |grad u + rot90(grad v)|^2, w_f = 1 / (2 Im factor). Capped at
//! 1 / (2 kSmallestReferenceHeight) for needle-thin reference triangles.
[[nodiscard]] inline double sine_law_weight(const SineLawRelation& relation) {
  const double height = relation.factor.imag();
  return 0.5 / (height > kSmallestReferenceHeight ? height : kSmallestReferenceHeight);
}

//! Q (2V x 2V, unknowns u_0..u_{V-1} then v_0..v_{V-1}) with x^T Q x = sum_f w_f |r_f|^2: the
//! sine-law residuals r_f of every face (largest-sine corner placed, as sine_law_relation and
//! largest_sine_corner define them) weighted by sine_law_weight. Built as the conformal energy
//! [L N; N^T L]: L the cotangent Laplacian of the reference triangles' angles and N the signed
//! area coupling, which cancels on interior edges and so lives on the boundary (and on the edges
//! of capped faces). `angles` must be valid (#F x 3, finite, in (0, pi)), the faces consistently
//! oriented.
[[nodiscard]] Eigen::SparseMatrix<double> sine_law_conformal_form(const Mesh& mesh,
                                                                  const Eigen::MatrixX3d& angles);

//! UVs (#V x 2, pins as given) that satisfy the sine-law relation of every face in the weighted
//! least squares sense above. `angles` must be valid and the mesh a disk. `vertex_ordering` is
//! a fill-reducing ordering of the vertices (may be empty). Records the phases
//! assembly/analysis/factorization/solve on `clock`; on failure sets report.status and returns an
//! empty matrix.
[[nodiscard]] Eigen::MatrixX2d least_squares_layout(const Mesh& mesh,
                                                    const Eigen::MatrixX3d& angles,
                                                    const LayoutPins& pins, Backend& backend,
                                                    const SolverOptions& options,
                                                    const std::vector<int>& vertex_ordering,
                                                    SolveReport& report, PhaseClock& clock);

}  // namespace harmonia::detail
