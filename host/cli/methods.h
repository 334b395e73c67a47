#pragma once
//! \file methods.h
//! \brief The planar methods the CLI offers, behind one call (shared by `unwrap` and `demo`).

#include <string>

#include "harmonia/boundary.h"
#include "harmonia/laplacian.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia::cli {

enum class MethodKind {
  conformal,  //!< Fixed-boundary map with a weight scheme of chapter 4 (fixed_boundary_map).
  lscm,       //!< Free-boundary least-squares conformal map (the baseline of 6.2.2).
  qhm,        //!< Quasi-harmonic map (chapter 5).
};

//! Everything that selects and configures one method run.
struct MethodChoice {
  MethodKind method = MethodKind::conformal;
  WeightScheme weights =
      WeightScheme::cotangent;  //!< conformal: any; qhm: cotangent or mean-value.
  BoundaryShape boundary = BoundaryShape::circle;  //!< conformal and qhm.
  BackendChoice backend = BackendChoice::automatic;
  UvNormalization normalization = UvNormalization::match_surface_area;
  int rounds = 5;  //!< qhm: most rounds.
};

//! CLI spellings: "conformal", "lscm", "qhm".
[[nodiscard]] std::string to_string(MethodKind method);

//! Runs the chosen method. The result's uv is #V by 2 when the status is ok or flipped_triangles.
//! \pre for qhm, weights is cotangent or mean_value (the two tensor schemes of chapter 5).
[[nodiscard]] MapResult run_method(const Mesh& mesh, const MethodChoice& choice,
                                   const ProgressCallback& progress);

}  // namespace harmonia::cli
