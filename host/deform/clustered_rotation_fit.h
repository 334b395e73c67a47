#pragma once
// Internal: where each handle's rotation acts, found by as-rigid-as-possible editing reduced to a
// few rotation clusters (harmonia/surface_editor.h, SurfaceEditOptions::rotation_clusters).
//
// The thesis blends each handle's rotation along its harmonic field (8.3, 8.5). On a limb turned
// about its joint, that field is 0.2-0.3 over the body, which then turns by a fifth of the limb's
// angle where the as-rigid-as-possible (ARAP) solution keeps it still. The fix here keeps the
// editor's Poisson reconstruction and its one factorization, and lets the energy decide the
// rotations: the vertices are grouped into C compact clusters (deform/vertex_clusters.h), each
// with one rotation R_c, as in the rotation clusters of Jacobson, Baran, Kavan, Popovic and
// Sorkine (2012, "Fast automatic skinning transformations").
//
// The ARAP energy (deform/arap_refinement.h, spokes and rims) with vertex v's linear part the blend
// R_v = sum_c w_vc M_c of its clusters' (w: the clusters' soft membership, a partition of unity
// that falls smoothly across their borders; M_c = s_c R_c, s_c the cluster's blended scale)
// becomes, after its global step (the Poisson solve) is taken exactly, a function of the cluster
// rotations alone. Write m_d for row d of all M_c side by side (3C numbers). The positions are
// affine in the M_c: x_d = x0_d + U m_d, where x0 is the harmonic extension of the constrained
// vertices' targets and column (c, j) of U the Poisson solution (zero at the constrained vertices)
// of the load of rest coordinate j weighted by cluster c's membership. Each cluster's covariance
// is then affine too: S_d = t0_d + P m_d, with P = G^T U (3C by 3C, symmetric: G, the covariance of
// a scalar field, is 3 times the load) and t0 the covariance of x0, itself linear in the handles'
// transformations through the harmonic extensions of 4 fields per handle (its rest coordinates
// and 1) and 3 for the fixed vertices. The energy's last term, sum over cells of |R_v e|^2, is
// m_d^T K m_d with K = sum over cells of w_v w_v^T (x) the cell's rest inertia sum w e e^T: a
// constant for a hard partition (rotations keep lengths), not for blends. The reduced energy to
// maximize is f = 1/2 sum_d m_d^T (P - K) m_d + t0_d^T m_d over the rotations; its gradient is
// the covariance less K m, so ARAP's local step R_c = polar(S_c) is the block-coordinate ascent on
// it for a hard partition. That ascent is as slow
// as full ARAP (hundreds of steps); here Newton's method on the rotations (R_c <- exp([d_c]) R_c,
// Levenberg-Marquardt damped) converges in a handful of steps of O(C^3), independent of the mesh.
//
// Set-up: 3C columns solved with the editor's factor, once (t0's fields come from the same
// solutions). A frame: the reduced Newton steps (a fraction of a millisecond), then the usual
// Poisson solve with the triangles' linear parts, the mean of their corners' blends R_v, which
// gives exactly x0 + U m.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include "deform/edit_roles.h"
#include "deform/similarity_fragment_load.h"
#include "deform/vertex_clusters.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/surface_editor.h"
#include "solve/dirichlet_system.h"

namespace harmonia::detail {

class ClusteredRotationFit {
 public:
  // What needs only the rest mesh: the clusters and their covariance map (it can run beside the
  // factorization). `load`: the editor's fragment load, whose corner loads give the clusters'.
  ClusteredRotationFit(const Mesh& mesh, VertexClusters clusters, const SimilarityFragmentLoad& load);

  // What needs the factor: the coupling P and the targets' covariances. `operator_matrix`: the
  // matrix `system` factorized; `fields`: the handles' harmonic fields (#V by H, clamped to
  // [0, 1]), which give each cluster its starting rotation and its scale. Returns false, with
  // report not ok, when a solve fails.
  [[nodiscard]] bool couple(const Mesh& mesh, const EditRoles& roles,
                            const Eigen::SparseMatrix<double>& operator_matrix,
                            const Eigen::MatrixXd& fields, DirichletSystem& system,
                            SolveReport& report);

  // One frame: every cluster's rotation and scale at the maximum of the reduced energy, starting
  // from `blended`, the handles' rotations blended along the fields at the cluster (thesis 8.3,
  // 8.5: what the handles ask of it). Returns the Newton steps taken.
  int fit(const std::vector<SimilarityTransform>& transforms, std::vector<Eigen::Quaterniond>& blended,
          std::vector<Eigen::Quaterniond>& rotations, Eigen::VectorXd& scales) const;

  // Each vertex's cluster.
  [[nodiscard]] const std::vector<int>& cluster_of() const { return clusters_.cluster_of; }
  [[nodiscard]] int cluster_count() const { return clusters_.count; }
  // The clusters with their soft membership.
  [[nodiscard]] const VertexClusters& clusters() const { return clusters_; }
  // Each triangle's clusters with the mean of its corners' weights: its linear part is their sum
  // of s_c R_c (SimilarityFragmentLoad::assemble).
  [[nodiscard]] const GroupMix& triangle_mix() const { return triangle_mix_; }

 private:
  // The energy's ingredients for the current rotations: covariances (3 by 3C) and f.
  void covariances(const Eigen::Matrix3Xd& stacked, const Eigen::Matrix3Xd& t0,
                   Eigen::Matrix3Xd& covariance, double& energy) const;

  VertexClusters clusters_;
  GroupMix triangle_mix_;
  int handle_count_ = 0;
  Eigen::SparseMatrix<double> covariance_map_;  // G, #V by 3C
  Eigen::MatrixXd cluster_fields_;  // C by H: each handle's mean field over the cluster
  Eigen::MatrixXd coupling_;        // P - K, 3C by 3C
  Eigen::MatrixXd rest_inertia_;    // K: sum over cells of w_c w_c' times the cell's rest inertia
  // The covariances of the fields that make x0 (3C each): per handle i, column 4 i + j for the
  // field that is rest coordinate j on the handle (0 elsewhere), 4 i + 3 for its harmonic field;
  // the last three, rest coordinate d on the fixed vertices.
  Eigen::MatrixXd target_covariance_;
};

}  // namespace harmonia::detail
