#pragma once
//! \file deformation_transfer.h
//! \brief Deformation transfer driven by a few marker pairs (thesis 8.4, 8.5): a source mesh in its
//! rest pose and in new poses, a target mesh in its rest pose, and pairs of corresponding vertices;
//! the target is made to perform the source's poses.
//!
//!   Set-up (once): on each mesh one harmonic field per marker, 1 at that marker and 0 at the
//!   others (all k fields share one factorization per mesh): a partition of unity, a k-vector per
//!   vertex, averaged over each triangle.
//!
//!   Correspondence (8.4, TransferMethod::correspondence): every target triangle is matched to the
//!   source triangle whose vector is closest, compared on the n largest components of the target
//!   triangle's vector (n = DeformationTransferOptions::components). Candidates are the source
//!   triangles whose largest component is one of the target triangle's n largest (an index by
//!   dominant marker, so that a match costs a few hundred comparisons, not #F). A target triangle
//!   without a candidate, or whose best distance exceeds max_match_distance, is unmatched and takes
//!   the deformation of its nearest matched neighbour across edges (the identity if none).
//!
//!   Transfer: per source triangle the deformation gradient Q from rest to pose (with a fourth
//!   vertex along the normal, as Sumner and Popovic do); every target triangle of the fragmented
//!   target is moved by the Q of its match (evened out with its neighbours', see
//!   smoothing_passes), and the target is rebuilt by the Poisson equation with the one
//!   factorization of its cotangent Laplacian (one vertex held, then placed, see below).
//!
//!   Direct variant (8.5, TransferMethod::quaternion): the source's deformation at each marker (the
//!   area-weighted mean of Q over the marker's triangles), split into a rotation (polar
//!   decomposition, as a unit quaternion) and a uniform scale, interpolated harmonically over the
//!   target with the target's marker fields (renormalized quaternions), then the same Poisson
//!   reconstruction. No correspondence search.
//!
//! Folds: a transfer is judged by the triangles it folds beyond those the source pose folds
//! (TransferResult::source_folded_triangles); DeformationTransferOptions::smoothing_passes evens
//! out the deformations across the seams between matched regions, and fold_repair_rounds evens
//! them out around any fold the result still has and solves again.
//!
//! Placement: the Poisson equation fixes the shape up to a translation; the result is translated so
//! that its area-weighted centroid moves from the target's rest centroid by as much as the source's
//! area-weighted centroid moved from its rest centroid.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"
#include "harmonia/types.h"

namespace harmonia {

//! One marker pair: a vertex of the source and the corresponding vertex of the target (0-based).
struct MarkerPair {
  int source = -1;
  int target = -1;
};

enum class TransferMethod {
  correspondence,  //!< 8.4: triangle correspondence from the marker fields (default).
  quaternion,      //!< 8.5: the deformations at the markers interpolated harmonically.
};

struct DeformationTransferOptions {
  TransferMethod method = TransferMethod::correspondence;
  //! The number n of largest field components compared when matching (3 <= n <= k; clamped to k).
  //! Few components compare only what is near; 8 was the best of 3..12 on the lion and cat and
  //! leaves the match insensitive to far markers.
  int components = 8;
  //! A match farther than this (Euclidean distance over the compared components, the fields being
  //! in [0, 1]) is refused and the triangle treated as unmatched.
  double max_match_distance = 0.25;
  //! Correspondence only: passes of averaging each target triangle's deformation with its edge
  //! neighbours' before the reconstruction. Where neighbouring matches jump between parts of the
  //! source their deformations disagree and the seam folds; on the lion and cat, 2 passes left
  //! fewer folded triangles in every pose than the source pose has (0 passes: more in two of the
  //! nine) for 0.1 % of the diagonal of accuracy. 0 turns it off.
  int smoothing_passes = 2;
  //! After the solve, rounds of fold repair: where the result folds triangles onto their
  //! neighbours that are not folded at rest, the deformations around them (three rings of
  //! neighbours) are evened out and the target is solved again, while the folds become fewer.
  //! Each round costs one more back-substitution; a pose without new folds costs none. 0 turns
  //! it off.
  int fold_repair_rounds = 3;
  SolverOptions solver;
};

struct TransferResult {
  //! #V_target by 3: the target in the source's pose, the target's vertex order. Empty on failure.
  Eigen::MatrixX3d positions;
  //! flipped_triangles: folded_triangles below; degenerate_triangles: zero area.
  SolveReport report;
  //! Target triangles folded onto their neighbours in the result (the unit normal more than 90
  //! degrees from the sum of the edge neighbours' unit normals, or zero area) that were not folded
  //! at rest. A patch turned over as a whole counts only at its rim. The transfer's targets (and
  //! its fold repair) use this count, against source_folded_triangles.
  int folded_triangles = 0;
  //! The same count for the source pose against the source's rest pose: what the pose itself
  //! folds (joints bent until the surface touches itself), which a transfer may reproduce.
  int source_folded_triangles = 0;
  //! Target triangles whose normal in the result makes 90 degrees or more with the normal their
  //! transferred deformation gives them (the deformation the solve was given, after fold repair):
  //! the strict count, triangle by triangle, that `deform` reports as turned over too. Zero-area
  //! triangles are left to degenerate_triangles.
  int turned_over_triangles = 0;
};

//! Built once from (source rest, target rest, markers); transfer() is one pose.
class DeformationTransfer {
 public:
  //! Problems (a marker index out of range, naming the pair; the same vertex in two pairs; fewer
  //! than 3 pairs; a mesh with a part that holds no marker) go into setup_report(), and transfer()
  //! then returns that status.
  DeformationTransfer(const Mesh& source_rest, const Mesh& target_rest,
                      const std::vector<MarkerPair>& markers,
                      const DeformationTransferOptions& options = {});
  ~DeformationTransfer();
  DeformationTransfer(DeformationTransfer&&) noexcept;
  DeformationTransfer& operator=(DeformationTransfer&&) noexcept;

  [[nodiscard]] const SolveReport& setup_report() const;
  //! The marker fields of the source and the target, #V by k (each row sums to 1).
  [[nodiscard]] const Eigen::MatrixXd& source_fields() const;
  [[nodiscard]] const Eigen::MatrixXd& target_fields() const;
  //! Correspondence: the source triangle each target triangle takes its deformation from (-1
  //! none: no matched triangle anywhere near); empty for the quaternion method.
  [[nodiscard]] const std::vector<int>& matches() const;
  //! Target triangles matched directly / given a neighbour's match or the identity.
  [[nodiscard]] int matched_triangles() const;
  [[nodiscard]] int unmatched_triangles() const;

  //! One pose: #V_source by 3 positions of the source's vertices (the source's connectivity).
  [[nodiscard]] TransferResult transfer(const Eigen::MatrixX3d& source_pose);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace harmonia
