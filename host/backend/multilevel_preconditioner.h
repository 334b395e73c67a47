#pragma once
// Internal: the V-cycle of a smoothed-aggregation hierarchy (backend/aggregation_hierarchy.h),
// applied on any backend with its SpMV and vector operations: the default of
// Backend::multilevel_preconditioner.
//
// On each level above the coarsest: `sweeps` damped Jacobi sweeps, the residual restricted to the
// next level, the cycle there, its correction prolongated back, and `sweeps` sweeps again; the
// coarsest level is solved by its dense inverse (one SpMV). The same smoother before and after
// makes the cycle a symmetric positive definite operator, as the conjugate gradients need.

#include <memory>
#include <vector>

#include "backend/aggregation_hierarchy.h"
#include "backend/backend.h"

namespace harmonia::detail {

class MultilevelCycle final : public Preconditioner {
 public:
  // Uploads every level's matrices to `backend`, which must outlive the cycle.
  MultilevelCycle(Backend& backend, const AggregationHierarchy& hierarchy, int sweeps = 2);

  // z = V-cycle(r), from z = 0.
  void apply(const DeviceVectors& r, DeviceVectors& z) override;

 private:
  struct Level {
    std::unique_ptr<DeviceMatrix> matrix, smoother, prolongation, restriction;
    // Work blocks: right-hand side and solution (the levels below the finest), the residual and
    // a smoothing step (every level).
    std::unique_ptr<DeviceVectors> rhs, solution, residual, step;
  };

  void cycle(std::size_t level, const DeviceVectors& b, DeviceVectors& x);
  // x += w D^-1 (b - A x) on one level.
  void smooth(Level& level, const DeviceVectors& b, DeviceVectors& x);
  void prepare_work_vectors(int cols);

  Backend& backend_;
  int sweeps_;
  std::vector<Level> levels_;
  std::unique_ptr<DeviceMatrix> coarsest_inverse_;
  std::unique_ptr<DeviceVectors> coarsest_rhs_, coarsest_solution_;
  int work_cols_ = 0;
  Eigen::VectorXd ones_, minus_ones_;
};

}  // namespace harmonia::detail
