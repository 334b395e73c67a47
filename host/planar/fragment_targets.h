#pragma once
// Internal: the fragmented mesh of the free-boundary maps (thesis 6.2.2, figure 6.1). Every
// triangle of a current planar map is cut loose and reshaped toward its 3D triangle; the Poisson
// equation then glues the fragments back into one map.
//
// The reshaping of a triangle is its stretch K = sqrt(I), the symmetric planar Jacobian with
// K^T K = I, the first fundamental form of the map from the layout to the surface (5.1-5.5): K
// applied to the layout's triangle gives a triangle congruent to the 3D one. A step s in [0, 1]
// applies K^s instead (s = 0: the layout's own triangle, s = 1: the 3D shape); the maps use a
// smaller step only where the full one would fold (free_boundary_map.cpp).
//
// The thesis applies K in the frame of the layout's triangle. Fragments placed that way do not fit
// together even on a developable surface: the layout turns its triangles by different amounts, so
// the glued map keeps part of the start map's distortion. Here each fragment is also turned by an
// angle theta_f, the rotation field that makes neighbouring fragments agree along their shared
// edge in the least-squares sense (FragmentRotationField). On a developable disk the fragments then
// fit exactly and the Poisson solution is the isometric unrolling, whatever the start map.

#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "backend/backend.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"
#include "harmonia/types.h"
#include "solve/dirichlet_system.h"

namespace harmonia::detail {

//! The stretch K of each triangle under the map `uv` -> mesh, as its eigen decomposition so that
//! powers K^s are cheap: K = R(angle) diag(major, minor) R(angle)^T. A triangle with zero uv area
//! (no Jacobian) gets K = identity: its fragment is the layout's triangle.
struct TriangleStretches {
  Eigen::VectorXd angle, major, minor;  // #F each
  [[nodiscard]] Eigen::Matrix2d power(Eigen::Index face, double step) const;
  //! The tensors C = K^-s of quasi_harmonic_operator.h for the given step, #F by 4.
  [[nodiscard]] Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> conductances(
      double step) const;
};
[[nodiscard]] TriangleStretches triangle_stretches(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! Least-squares rotation of the fragments (see the file comment): over the interior edges e
//! between faces f and g, minimize sum (theta_f - theta_g - delta_e)^2 with delta_e the angle that
//! turns the edge as fragment f shapes it onto the edge as fragment g shapes it; theta of face 0
//! is 0, which fixes the map's rotation. The matrix (a graph Laplacian of the faces) depends on the
//! connectivity only and is factorized once; each field is one back-substitution.
class FragmentRotationField {
 public:
  FragmentRotationField(const Mesh& mesh, Backend& backend, const SolverOptions& options);
  //! Factorizes the face-graph Laplacian. False with report.status set on failure.
  [[nodiscard]] bool factorize(SolveReport& report);
  //! theta (#F) for fragments K^step of the layout uv.
  [[nodiscard]] bool solve(const Eigen::MatrixX2d& uv, const TriangleStretches& stretches,
                           double step, Eigen::VectorXd& theta, SolveReport& report);

 private:
  const Mesh& mesh_;
  // Interior edges: the two faces and the edge's vertices (a -> b as face `first` runs it).
  std::vector<int> first_face_, second_face_, edge_from_, edge_to_;
  Eigen::SparseMatrix<double> laplacian_;
  std::unique_ptr<DirichletSystem> system_;
};

//! Fragment corners (#F*3 by 2): for face f and corner k, R(theta_f) K_f^step (uv_k - centroid_f).
//! `theta` may be empty (no rotation: the thesis' frame of the layout).
[[nodiscard]] Eigen::MatrixXd stretched_fragments(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                                                  const TriangleStretches& stretches, double step,
                                                  const Eigen::VectorXd& theta);

}  // namespace harmonia::detail
