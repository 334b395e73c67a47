#pragma once
//! \file surface_editor.h
//! \brief Interactive surface editing along harmonic fields (thesis 8.2, 8.3, 8.5): handles are
//! moved by similarity transformations (rotation about a centre, uniform scale, translation), the
//! transformations are propagated over the region of interest by harmonic fields, and the surface
//! is rebuilt from the transformed triangles by one Poisson solve whose matrix never changes.
//!
//!   Set-up (once per choice of regions): the cotangent Laplacian L of the rest mesh with the
//!   constrained vertices (fixed, handles, everything outside the region of interest) moved to
//!   the right-hand side, factorized once (CPU) or uploaded once (Vulkan); one harmonic field per
//!   handle, L h_i = 0 with h_i = 1 on handle i and 0 on every other constrained vertex (8.3), with
//!   the same factorization; the fields averaged onto the triangles (the barycentre samples).
//!
//!   A frame (new handle transformations): per triangle a rotation and a scale blended from the
//!   handles' by the fields; each triangle of the fragmented rest mesh rotated and scaled by its
//!   own; the Poisson equation L x = div(grad of the fragmented target) (8.3) with the constraints'
//!   targets on the right, solved by back-substitution (CPU) or by warm-started conjugate gradients
//!   (Vulkan). The translation of a triangle does not enter a gradient: where the surface goes is
//!   decided by the constrained vertices.
//!
//! Blending. One handle: quaternion slerp from the identity to the handle's rotation by the
//! triangle's field value, and the scale 1 + h (s - 1). Several handles (8.5): the four quaternion
//! components and the scale interpolated harmonically with every handle (and the identity on the
//! fixed set) as constraints, i.e. sum_i h_i q_i + (1 - sum_i h_i) 1 since the fields are linear in
//! their boundary values, then renormalized. Each handle's quaternion is taken with a non-negative
//! real part (the shorter way round from the identity), so that no blend cancels out.
//!
//! Limits (thesis 8.6): the deformation of a triangle depends only on its field value, not on where
//! the handle went, so a translation alone rotates nothing (a translation-only edit gives the
//! harmonic displacement interpolation), and with few handles a joint bends smoothly over the whole
//! region between handle and fixed set ("rubbery") instead of at the joint.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"
#include "harmonia/types.h"

namespace harmonia {

//! A similarity transformation of space: p -> center + rotation * (scale * (p - center)) +
//! translation (the edit-file convention, ../shared/data/edit/README.md).
struct SimilarityTransform {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  //!< Unit quaternion.
  Eigen::Vector3d center = Eigen::Vector3d::Zero();              //!< Fixed point of rotation and scale.
  double scale = 1.0;                                            //!< Uniform, > 0.
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();         //!< Applied last.

  //! The image of one point.
  [[nodiscard]] Eigen::Vector3d apply(const Eigen::Vector3d& point) const;
  //! The transformation a fraction t in [0, 1] of the way from the identity: rotation slerped from
  //! the identity (the shorter way), scale 1 + t (scale - 1), translation t * translation, the same
  //! centre. t = 0: the identity; t = 1: this transformation.
  [[nodiscard]] SimilarityTransform partial(double t) const;
};

//! Which vertices do what. Indices are 0-based vertex indices of the mesh; the sets are disjoint.
struct EditRegions {
  //! Vertices that stay where they are.
  std::vector<int> fixed;
  //! Each handle: vertices that move rigidly (with uniform scale) by their handle's transformation.
  std::vector<std::vector<int>> handles;
  //! The region of interest: the vertices the edit may move. Empty: the whole mesh. Vertices
  //! outside it stay where they are (they act as fixed ones).
  std::vector<int> region_of_interest;
};

struct SurfaceEditOptions {
  //! Check every frame's triangles against their target orientation (SurfaceEditResult's
  //! report.flipped_triangles, degenerate_triangles). About a tenth of a frame's time.
  bool check_orientation = true;
  //! As-rigid-as-possible refinement steps per frame (deform/arap_refinement.h): each fits one
  //! rotation per vertex to the current result (spokes-and-rims cells) and solves the same Poisson
  //! system again, so it costs about one frame more. 0: the thesis' method alone.
  int refinement_steps = 0;
  //! A time budget per frame, in seconds (0: none). With it, refinement steps follow the
  //! harmonic-field frame for as long as one more step (expected to last as long as the same step
  //! of the frame before) still ends within the budget: as many as fit, for a tool that wants
  //! ARAP quality while the user pauses and a bounded frame while they drag. refinement_steps
  //! then caps their number (0: up to 10000). The frame itself (blending, one solve, the check)
  //! is always made, so a budget shorter than it gives the harmonic-field result.
  //! SurfaceEditResult::refinement_steps says how many were made; the positions then depend on
  //! the machine's speed.
  double frame_budget = 0.0;
  //! Where the handles' rotations act: the vertices are grouped into this many compact clusters,
  //! each with one rotation, and each frame finds the cluster rotations that make the result as
  //! rigid as possible (spokes-and-rims energy, its Poisson step taken exactly; Newton's method on
  //! the rotations, well under a millisecond at 16, independent of the mesh's size), starting from the
  //! thesis' blend along the harmonic fields. A limb turned about its joint then turns alone,
  //! where the blend turns the body by the field's share. Set-up: 3 solves with the one factor
  //! per cluster. 0: the thesis' blend (8.3, 8.5) alone. Empty (the default):
  //! automatic_rotation_clusters(the number of handles), 16 for one handle, 24 for two: each
  //! handle's rotation fades out somewhere else, and the clusters must resolve every such region
  //! (16 clusters serve one handle best on the edit cases; with two, 24 carry every two-handle case
  //! past its target, 16 do not).
  std::optional<int> rotation_clusters;
  SolverOptions solver;
};

//! The rotation clusters SurfaceEditOptions::rotation_clusters chooses when it is empty:
//! kRotationClustersPerPart for the fixed part and as many for each handle, 8 (handles + 1).
inline constexpr int kRotationClustersPerPart = 8;
[[nodiscard]] constexpr int automatic_rotation_clusters(int handles) {
  return kRotationClustersPerPart * (handles + 1);
}

//! The time one frame took, in its three stages (seconds).
struct EditFrameTiming {
  double blending = 0.0;  //!< Per-triangle rotations and scales from the fields.
  double assembly = 0.0;  //!< The Poisson right-hand side of the transformed fragments.
  double solve = 0.0;     //!< Back-substitution (CPU) or conjugate gradients (Vulkan).
  double refinement = 0.0;  //!< The rotation fits of the refinement steps (their solves: in solve).
  double check = 0.0;     //!< The orientation check (0 without check_orientation).
  [[nodiscard]] double total() const noexcept { return blending + assembly + solve + refinement + check; }
};

struct SurfaceEditResult {
  //! #V by 3, the deformed vertex positions in the mesh's order; constrained vertices exactly at
  //! their targets. Empty when report.status is neither ok nor flipped_triangles.
  Eigen::MatrixX3d positions;
  //! report.flipped_triangles: triangles whose deformed normal makes 90 degrees or more with their
  //! target normal (the rest normal turned by the triangle's own blended rotation);
  //! degenerate_triangles: triangles of zero area in the result. Both counted only with
  //! check_orientation; status stays ok (the positions are what the method gives). residual: the
  //! largest relative residual of the set-up's field solves, with the factor every frame uses (a
  //! frame's back-substitution is not re-measured: that would cost a tenth of it); iterations: the
  //! frame's (conjugate gradients on Vulkan, 0 for a direct solve).
  SolveReport report;
  EditFrameTiming timing;
  //! The refinement steps this frame made (SurfaceEditOptions::refinement_steps, or as many as
  //! fit its frame_budget).
  int refinement_steps = 0;
};

//! The reusable editor: the constructor checks the input, computes the fields and factorizes; each
//! deform() is one frame. Not thread-safe: one frame at a time per editor.
class SurfaceEditor {
 public:
  //! `mesh`: any manifold or non-manifold triangle mesh with finite coordinates; every connected
  //! part of the region of interest needs at least one constrained vertex (else invalid_input,
  //! naming a vertex of the part). Problems go into setup_report() (then deform() returns that
  //! status).
  SurfaceEditor(const Mesh& mesh, const EditRegions& regions, const SurfaceEditOptions& options = {});
  ~SurfaceEditor();
  SurfaceEditor(SurfaceEditor&&) noexcept;
  SurfaceEditor& operator=(SurfaceEditor&&) noexcept;

  //! Status, solver, backend and timings of the set-up (phases "validation", "analysis",
  //! "factorization", "fields").
  [[nodiscard]] const SolveReport& setup_report() const;
  //! The harmonic field of each handle, #V by #handles (h_i = 1 on handle i, 0 on the fixed
  //! vertices, the other handles and outside the region of interest).
  [[nodiscard]] const Eigen::MatrixXd& handle_fields() const;
  //! Numeric factorizations (or, on Vulkan, matrix uploads) made so far: 1 after the set-up, and
  //! still 1 after any number of frames.
  [[nodiscard]] int factorization_count() const;

  //! One frame: one transformation per handle, in the order of EditRegions::handles.
  [[nodiscard]] SurfaceEditResult deform(const std::vector<SimilarityTransform>& handle_transforms);
  //! Drag mode: each handle translated rigidly (no rotation, no scale); the result is the
  //! harmonic interpolation of the handles' displacements.
  [[nodiscard]] SurfaceEditResult drag(const std::vector<Eigen::Vector3d>& handle_translations);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//! One-shot: build a SurfaceEditor and deform once.
[[nodiscard]] SurfaceEditResult edit_surface(const Mesh& mesh, const EditRegions& regions,
                                             const std::vector<SimilarityTransform>& handle_transforms,
                                             const SurfaceEditOptions& options = {});

}  // namespace harmonia
