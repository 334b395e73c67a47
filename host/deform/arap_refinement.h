#pragma once
// Internal: as-rigid-as-possible refinement of an edit on the editor's own factorization
// (harmonia/surface_editor.h, SurfaceEditOptions::refinement_steps).
//
// The energy is the spokes-and-rims energy of Sorkine and Alexa (2007) with Chao et al.'s rim
// edges: every vertex i has a rotation R_i, and every edge (j, k) of every triangle t around i
// pays w_jk |(x_j - x_k) - s_t R_i (p_j - p_k)|^2 (w: half cotangents at rest, s_t the triangle's
// blended scale). Its global step is the editor's Poisson equation with the triangle's linear part
// s_t (R_a + R_b + R_c) / 3 for its corners a, b, c, so it reuses the factorization; its local step
// fits each R_i to the covariance of i's cell, S_i = sum over t around i of sum over t's edges of
// w e' e^T (e rest, e' deformed), by the rotation-extraction iteration of Mueller et al. (2016):
// from the current R_i, turn about sum_k r_k x s_k (columns of R_i and S_i) by an angle that
// shrinks as they align; a few steps from a warm start, no SVD.

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "harmonia/mesh.h"

namespace harmonia::detail {

class ArapRefinement {
 public:
  explicit ArapRefinement(const Mesh& rest);

  // The local step: every vertex rotation (#V, the warm start on entry) turned toward the best fit
  // of its cell in `positions` (#V by 3).
  void fit_vertex_rotations(const Eigen::MatrixXd& positions,
                            std::vector<Eigen::Quaterniond>& vertex_rotations) const;

  // The global step's linear part of every triangle: s_t times the mean of its corners' rotations.
  [[nodiscard]] std::vector<Eigen::Matrix3d> triangle_linear_parts(
      const std::vector<Eigen::Quaterniond>& vertex_rotations, const Eigen::VectorXd& scales) const;

 private:
  Eigen::MatrixX3i faces_;
  int vertex_count_ = 0;
  Eigen::Matrix3Xd weighted_edges_;  // column 3 f + k: w_k e_k, e_k the rest edge opposite corner k
};

}  // namespace harmonia::detail
