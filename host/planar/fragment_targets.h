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
#include "fallback/fragment_load.h"
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
  //! K^step of every face.
  [[nodiscard]] std::vector<Eigen::Matrix2d> powers(double step) const;
  //! The tensors C = K^-s of quasi_harmonic_operator.h for the given step, #F by 4.
  [[nodiscard]] Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> conductances(
      double step) const;
};
[[nodiscard]] TriangleStretches triangle_stretches(const Mesh& mesh, const Eigen::MatrixX2d& uv);

//! Least-squares rotation of the fragments (see the file comment): over the interior edges e
//! between faces f and g, minimize the weighted sum of (theta_f - theta_g - delta_e)^2 with
//! delta_e the angle that turns the edge as fragment f shapes it onto the edge as fragment g shapes
//! it; theta of face 0 is 0, which fixes the map's rotation.
//!
//! Solved on the vertices rather than on the faces. On a disk the edge values split into the
//! differences of a face potential (what theta can match) and the circulations around the
//! interior vertices, c_e (psi_a - psi_b) on each edge a -> b for a vertex potential psi that is
//! zero on the boundary; the split is orthogonal for the weights 1 / c_e, the discrete Hodge star
//! of the faces' graph (dual edge length over primal edge length), when c_e are the cotangent
//! weights of the edges. The circulation of delta around an interior vertex is the angle defect
//! of its fragments (zero where the surface is developable), and psi solves the cotangent
//! Laplacian's Dirichlet problem with those defects as the load: the very system of the start map
//! P0, whose factorization is reused. What is left, delta_e - c_e (psi_a - psi_b), has no
//! circulation, so theta follows by summing it along a spanning tree of the faces. Each field
//! costs one back-substitution of the vertices and a walk over the faces.
class FragmentRotationField {
 public:
  explicit FragmentRotationField(const Mesh& mesh);
  //! The cotangent weight c_e of every interior edge, read from the 3D cotangent Laplacian (its
  //! off-diagonal entries are -c_e); call again after the geometry changes.
  void set_cotangent_weights(const Eigen::SparseMatrix<double>& cotangent_laplacian);
  //! theta (#F) for the fragments shapes[f] (e.g. K^step, TriangleStretches::powers) of the
  //! layout uv's triangles. `boundary_system`: the cotangent Laplacian's Dirichlet system with the
  //! boundary loop fixed, factorized.
  [[nodiscard]] bool solve(const Eigen::MatrixX2d& uv, const std::vector<Eigen::Matrix2d>& shapes,
                           DirichletSystem& boundary_system, Eigen::VectorXd& theta,
                           SolveReport& report);

 private:
  const Mesh& mesh_;
  // Interior edges: the two faces and the edge's vertices (a -> b as face `first` runs it).
  std::vector<int> first_face_, second_face_, edge_from_, edge_to_;
  std::vector<double> cotangent_weight_;
  // The spanning tree of the faces from face 0, in the order it reaches them: the face reached,
  // the interior edge it is reached over.
  std::vector<int> tree_face_, tree_edge_;
};

//! The tensor-cotangent stiffness (5.10) of the triangles of the layout uv under `tensors`, for
//! gather_fragment_load (fallback/fragment_load.h).
[[nodiscard]] PairStiffness tensor_pair_stiffness(
    const Mesh& mesh, const Eigen::MatrixX2d& uv,
    const Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>& tensors);

//! The fragmented mesh (3 #F by 2): row 3 f + k is corner k of the fragment of face f,
//! R(theta_f) shapes[f] uv_k (`theta` empty: no rotation, the thesis' frame of the layout). The
//! centroid is left out: it drops out of the Poisson load, where only the differences of a
//! fragment's corners count.
[[nodiscard]] Eigen::MatrixXd fragment_corners(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                                               const std::vector<Eigen::Matrix2d>& shapes,
                                               const Eigen::VectorXd& theta);

}  // namespace harmonia::detail
