#pragma once
//! \file quasi_harmonic_map.h
//! \brief Quasi-harmonic maps with a fixed boundary (thesis chapter 5): start from a map, compute the
//! tensor C per triangle from its first fundamental form, solve div(C grad f) = 0 with the same
//! boundary, repeat until stable (3-5 rounds). Self-corrects an ill-shaped start (figure 5.6).

#include <memory>
#include <vector>

#include "harmonia/boundary.h"
#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia {

enum class QuasiHarmonicWeights {
  //! Eq. 5.10 (symmetric; exact for developable surfaces). Its weights can be negative; a map
  //! that folds gets one more round with tensor_mean_value (SolveReport::fallbacks says so).
  tensor_cotangent,
  tensor_mean_value,  //!< Section 5.4 (positive for any triangle shapes; non-symmetric).
};

enum class InitialMap {
  conformal,         //!< Fixed-boundary cotangent map with the same boundary (default).
  plane_projection,  //!< Interior: projection onto the least-squares plane; boundary as configured.
  given,             //!< QuasiHarmonicOptions::initial_uv (#V by 2); boundary vertices keep it.
};

struct QuasiHarmonicOptions {
  QuasiHarmonicWeights weights = QuasiHarmonicWeights::tensor_cotangent;
  InitialMap initial = InitialMap::conformal;
  Eigen::MatrixX2d initial_uv;   //!< Used when initial == given.
  BoundaryOptions boundary;      //!< Boundary of every round (ignored for initial == given).
  int max_rounds = 5;            //!< Upper bound on rounds.
  //! Stop when the largest vertex move of a round, relative to the layout's diameter, is below this.
  double stability_tolerance = 1e-4;
  SolverOptions solver;
  UvNormalization normalization = UvNormalization::match_surface_area;
};

struct QuasiHarmonicResult {
  Eigen::MatrixX2d uv;              //!< #V by 2.
  SolveReport report;               //!< report.rounds = rounds done.
  std::vector<double> round_change; //!< Relative largest move of each round.
};

[[nodiscard]] QuasiHarmonicResult quasi_harmonic_map(const Mesh& mesh,
                                                     const QuasiHarmonicOptions& options = {});

//! Reusable solver: topology, boundary and the symbolic factorization of the pattern are kept and
//! reused across rounds and across solve() calls.
class QuasiHarmonicMapper {
 public:
  QuasiHarmonicMapper(const Mesh& mesh, const QuasiHarmonicOptions& options = {});
  ~QuasiHarmonicMapper();
  QuasiHarmonicMapper(QuasiHarmonicMapper&&) noexcept;
  QuasiHarmonicMapper& operator=(QuasiHarmonicMapper&&) noexcept;
  [[nodiscard]] const SolveReport& setup_report() const;
  void update_geometry(const Eigen::MatrixX3d& vertices);
  [[nodiscard]] QuasiHarmonicResult solve();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace harmonia
