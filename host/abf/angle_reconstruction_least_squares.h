#pragma once
// Internal: the angle-based least-squares reconstruction of UVs from corner angles (thesis
// section 3.3, [SLMB05]); see angle_reconstruction_least_squares.cpp.

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "abf/angle_reconstruction_sine_law.h"
#include "backend/backend.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"
#include "planar/map_pipeline.h"
#include "solve/uv_system_solver.h"

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
//! [L N; N^T L]: L the cotangent Laplacian of the reference triangles' angles (every entry of the
//! vertex adjacency stored, zero or not, so that its pattern does not depend on the angles) and N
//! the signed area coupling, which cancels on interior edges and so lives on the boundary (and on
//! the edges of capped faces); N's zeros are not stored. `angles` must be valid (#F x 3, finite, in (0, pi)), the faces consistently
//! oriented.
[[nodiscard]] Eigen::SparseMatrix<double> sine_law_conformal_form(const Mesh& mesh,
                                                                  const Eigen::MatrixX3d& angles);

//! sine_law_conformal_form in two steps: what depends on the mesh alone (the vertex adjacency
//! pattern and each face's six off-diagonal places in it) once, then the values for each set of
//! angles, with no search. The same matrix, bit for bit.
class SineLawFormAssembler {
 public:
  explicit SineLawFormAssembler(const Mesh& mesh);
  [[nodiscard]] Eigen::SparseMatrix<double> assemble(const Eigen::MatrixX3d& angles) const;
  //! A matrix with the pattern of assemble(angles), for an analysis ahead of the values: L's
  //! entries (all of the vertex adjacency, stored whatever their values) hold zeros, N's those of
  //! assemble(). Only the faces with an angle within 0.01 of 0 or pi need a sine (whether their
  //! weight is capped), which makes it several times cheaper than assemble().
  [[nodiscard]] Eigen::SparseMatrix<double> pattern(const Eigen::MatrixX3d& angles) const;

 private:
  // Q from L's values at the adjacency pattern's entries (zeros for none) and N's.
  [[nodiscard]] Eigen::SparseMatrix<double> form_of(const std::vector<double>* dirichlet,
                                                    const std::vector<double>& area) const;

  const Mesh& mesh_;
  Eigen::SparseMatrix<double> pattern_;  // Vertex adjacency with the diagonal (values unused).
  std::vector<int> diagonal_;            // Position of each vertex's diagonal entry.
  // Per face, the position of entry (faces(f, i), faces(f, j)) for the ordered corner pairs
  // (i, j), i != j, at kPairSlot[i][j].
  std::vector<int> face_places_;
};

//! The least-squares reconstruction's system for one mesh, pair of pins and vertex ordering:
//! its symbolic work can be done ahead of the final angles (and on another thread), the numeric
//! work per set of angles.
class LeastSquaresLayout {
 public:
  //! `backend` must outlive the layout. Builds the form's pattern (SineLawFormAssembler).
  LeastSquaresLayout(const Mesh& mesh, const LayoutPins& pins, Backend& backend,
                     const SolverOptions& options);
  //! A fill-reducing ordering of the vertices for the analysis (none: the solver orders the
  //! unknowns itself); set before analyze() or layout().
  void set_vertex_ordering(std::vector<int> vertex_ordering);
  //! The analysis for the form of `predicted` angles (valid ones: the pattern depends on the
  //! angles only through capped, needle-thin faces, so any estimate of the final angles gives the
  //! final pattern but for those), from SineLawFormAssembler::pattern(): no values are computed.
  //! layout() analyzes again only when its form's pattern differs.
  void analyze(const Eigen::MatrixX3d& predicted);
  //! UVs (#V x 2, pins as given) that satisfy the sine-law relation of every face in the weighted
  //! least squares sense above. `angles` must be valid and the mesh a disk. Records the phases
  //! assembly/analysis/factorization/solve on `clock`; on failure sets report.status and returns
  //! an empty matrix.
  [[nodiscard]] Eigen::MatrixX2d layout(const Eigen::MatrixX3d& angles, SolveReport& report,
                                        PhaseClock& clock);

 private:
  SineLawFormAssembler assembler_;
  LayoutPins pins_;
  std::vector<int> vertex_ordering_;
  UvSystemSolver solver_;
};

//! LeastSquaresLayout's layout in one call.
[[nodiscard]] Eigen::MatrixX2d least_squares_layout(const Mesh& mesh,
                                                    const Eigen::MatrixX3d& angles,
                                                    const LayoutPins& pins, Backend& backend,
                                                    const SolverOptions& options,
                                                    const std::vector<int>& vertex_ordering,
                                                    SolveReport& report, PhaseClock& clock);

}  // namespace harmonia::detail
