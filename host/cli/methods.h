#pragma once
//! \file methods.h
//! \brief The planar methods the CLI offers, behind one call (shared by `unwrap` and `demo`).

#include <string>

#include "harmonia/abf.h"
#include "harmonia/angles_to_uv.h"
#include "harmonia/boundary.h"
#include "harmonia/laplacian.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia::cli {

//! The solver options of every command: the backend asked for, the progress callback, and the
//! Vulkan device $HARMONIA_VULKAN_DEVICE names (docs/vulkan.md, "Choosing the device").
[[nodiscard]] SolverOptions program_solver_options(BackendChoice backend,
                                                   const ProgressCallback& progress);

//! The backend a --backend value names: "cpu", "vulkan", anything else (the commands allow only
//! "auto" besides) automatic.
[[nodiscard]] BackendChoice backend_choice(const std::string& name);

enum class MethodKind {
  conformal,  //!< Fixed-boundary map with a weight scheme of chapter 4 (fixed_boundary_map).
  lscm,       //!< Free-boundary least-squares conformal map (the baseline of 6.2.2).
  qhm,        //!< Quasi-harmonic map (chapter 5).
  abf,        //!< Angle based flattening (chapter 2), free boundary.
  linabf,     //!< Linear angle based flattening (chapter 3), free boundary.
  free,       //!< Free-boundary quasi-harmonic map (chapter 6).
};

//! Everything that selects and configures one method run.
struct MethodChoice {
  MethodKind method = MethodKind::conformal;
  WeightScheme weights =
      WeightScheme::cotangent;  //!< conformal: any; qhm and free: cotangent or mean-value.
  BoundaryShape boundary = BoundaryShape::circle;  //!< conformal and qhm.
  BackendChoice backend = BackendChoice::automatic;
  UvNormalization normalization = UvNormalization::match_surface_area;
  int rounds = 5;  //!< qhm: most rounds.
  bool polish = false;              //!< free: add the fixed-boundary polish P3.
  bool stop_after_conformal = false;  //!< free: stop at P1, the boundary-free conformal map.
  double boundary_t = 2.0;                     //!< abf: boundary control coefficient t (2.6).
  AbfSolver abf_solver = AbfSolver::automatic;  //!< abf: linear solver of each Newton step.
  bool underdetermined = false;                 //!< abf: objective zero (section 2.4.3).
  int linabf_rounds = 0;                        //!< linabf: 0 = one round, a second if needed.
  //! abf and linabf: how the angles become UVs.
  AngleReconstruction reconstruction = AngleReconstruction::least_squares;
};

//! CLI spellings: "conformal", "lscm", "qhm", "abf", "linabf", "free".
[[nodiscard]] std::string to_string(MethodKind method);

//! What the angle-based methods report beyond a map (AngleMapResult).
struct AngleFigures {
  double abf_energy = 0.0;  //!< The ABF objective (2.8) of the planar angles.
  double boundary_t = 0.0;  //!< The boundary control coefficient in effect (0: none used).
};

//! Runs the chosen method. The result's uv is #V by 2 when the status is ok or flipped_triangles.
//! For abf and linabf, `angle_figures` (when given) receives their energy and boundary t.
//! \pre for qhm and free, weights is cotangent or mean_value (the two tensor schemes of chapter 5).
[[nodiscard]] MapResult run_method(const Mesh& mesh, const MethodChoice& choice,
                                   const ProgressCallback& progress,
                                   AngleFigures* angle_figures = nullptr);

}  // namespace harmonia::cli
