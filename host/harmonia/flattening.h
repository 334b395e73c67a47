#pragma once
//! \file flattening.h
//! \brief Every planar method of the library behind one call, chosen by name: what `harmonia
//! unwrap --method` runs, for programs and bindings that let their users choose the method.
//!
//! \code
//!   harmonia::FlatteningChoice choice;
//!   choice.method = *harmonia::flattening_method_from_string("abf");
//!   const harmonia::MapResult map = harmonia::flatten_disk(disk, choice);
//! \endcode

#include <optional>
#include <string_view>

#include "harmonia/abf.h"
#include "harmonia/angles_to_uv.h"
#include "harmonia/boundary.h"
#include "harmonia/laplacian.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia {

enum class FlatteningMethod {
  conformal,  //!< Fixed-boundary map with a weight scheme of chapter 4 (fixed_boundary_map).
  lscm,       //!< Free-boundary least-squares conformal map (the baseline of 6.2.2).
  qhm,        //!< Quasi-harmonic map (chapter 5).
  abf,        //!< Angle based flattening (chapter 2), free boundary.
  linabf,     //!< Linear angle based flattening (chapter 3), free boundary.
  free,       //!< Free-boundary quasi-harmonic map (chapter 6).
};

//! The names `harmonia unwrap --method` takes: "conformal", "lscm", "qhm", "abf", "linabf", "free".
[[nodiscard]] std::string_view to_string(FlatteningMethod method);
//! The method of a name of to_string, or nothing.
[[nodiscard]] std::optional<FlatteningMethod> flattening_method_from_string(std::string_view name);

//! Everything that selects and configures one method (each field says which methods read it).
struct FlatteningChoice {
  FlatteningMethod method = FlatteningMethod::conformal;
  //! conformal: any scheme; qhm and free: cotangent or mean_value (the tensor forms of chapter 5).
  WeightScheme weights = WeightScheme::cotangent;
  BoundaryShape boundary = BoundaryShape::circle;  //!< conformal and qhm.
  UvNormalization normalization = UvNormalization::match_surface_area;
  int rounds = 5;                     //!< qhm: most rounds.
  bool polish = false;                //!< free: add the fixed-boundary polish P3.
  bool stop_after_conformal = false;  //!< free: stop at P1, the boundary-free conformal map.
  double boundary_t = 2.0;                      //!< abf: boundary control coefficient t (2.6).
  AbfSolver abf_solver = AbfSolver::automatic;  //!< abf: linear solver of each Newton step.
  bool underdetermined = false;                 //!< abf: objective zero (section 2.4.3).
  int linabf_rounds = 0;                        //!< linabf: 0 = one round, a second if needed.
  //! abf and linabf: how the angles become UVs.
  AngleReconstruction reconstruction = AngleReconstruction::least_squares;
};

//! What the angle-based methods report beyond a map (AngleMapResult).
struct AngleFigures {
  double abf_energy = 0.0;  //!< The ABF objective (2.8) of the planar angles.
  double boundary_t = 0.0;  //!< The boundary control coefficient in effect (0: none used).
};

//! Runs the chosen method on a disk. The result's uv is #V by 2 when the status is ok or
//! flipped_triangles. For abf and linabf, `angle_figures` (when given) receives their energy and
//! boundary t. Throws std::invalid_argument for qhm or free with weights other than cotangent or
//! mean_value.
[[nodiscard]] MapResult flatten_disk(const Mesh& mesh, const FlatteningChoice& choice,
                                     const SolverOptions& solver = {},
                                     AngleFigures* angle_figures = nullptr);

}  // namespace harmonia
