#pragma once
//! \file lscm.h
//! \brief Free-boundary least-squares conformal map (LSCM) / discrete natural conformal map with two
//! pinned boundary vertices, the classic baseline the thesis compares against (section 6.2.2).

#include <memory>
#include <optional>

#include "harmonia/map_result.h"
#include "harmonia/mesh.h"
#include "harmonia/solver_options.h"

namespace harmonia {

struct LscmOptions {
  //! The two pinned vertices; by default the two boundary vertices farthest apart in 3D.
  std::optional<int> pin_first;
  std::optional<int> pin_second;
  SolverOptions solver;
  UvNormalization normalization = UvNormalization::match_surface_area;
};

[[nodiscard]] MapResult lscm(const Mesh& mesh, const LscmOptions& options = {});

//! Reusable solver: topology and pattern in the constructor, factorization in update_geometry.
class LscmSolver {
 public:
  LscmSolver(const Mesh& mesh, const LscmOptions& options = {});
  ~LscmSolver();
  LscmSolver(LscmSolver&&) noexcept;
  LscmSolver& operator=(LscmSolver&&) noexcept;
  [[nodiscard]] const SolveReport& setup_report() const;
  void update_geometry(const Eigen::MatrixX3d& vertices);
  [[nodiscard]] MapResult solve();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace harmonia
