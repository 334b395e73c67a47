#include "backend/multilevel_preconditioner.h"

#include <utility>

namespace harmonia::detail {

MultilevelCycle::MultilevelCycle(Backend& backend, const AggregationHierarchy& hierarchy,
                                 int sweeps)
    : backend_(backend), sweeps_(sweeps < 1 ? 1 : sweeps) {
  for (const AggregationLevel& source : hierarchy.levels()) {
    Level level;
    level.matrix = backend_.upload(source.matrix);
    level.smoother = backend_.upload(source.smoother);
    level.prolongation = backend_.upload(source.prolongation);
    level.restriction = backend_.upload(source.restriction);
    levels_.push_back(std::move(level));
  }
  coarsest_inverse_ = backend_.upload(hierarchy.coarsest_inverse());
}

void MultilevelCycle::prepare_work_vectors(int cols) {
  if (cols == work_cols_) return;
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    Level& level = levels_[l];
    const int rows = level.matrix->rows();
    if (l > 0) {
      level.rhs = backend_.allocate(rows, cols);
      level.solution = backend_.allocate(rows, cols);
    }
    level.residual = backend_.allocate(rows, cols);
    level.step = backend_.allocate(rows, cols);
  }
  if (!levels_.empty()) {
    coarsest_rhs_ = backend_.allocate(coarsest_inverse_->rows(), cols);
    coarsest_solution_ = backend_.allocate(coarsest_inverse_->rows(), cols);
  }
  ones_ = Eigen::VectorXd::Ones(cols);
  minus_ones_ = -ones_;
  work_cols_ = cols;
}

void MultilevelCycle::smooth(Level& level, const DeviceVectors& b, DeviceVectors& x) {
  backend_.spmv(*level.matrix, x, *level.residual);
  backend_.xpay(b, minus_ones_, *level.residual);  // b - A x
  backend_.spmv(*level.smoother, *level.residual, *level.step);
  backend_.axpy(ones_, *level.step, x);
}

void MultilevelCycle::cycle(std::size_t l, const DeviceVectors& b, DeviceVectors& x) {
  if (l == levels_.size()) {
    backend_.spmv(*coarsest_inverse_, b, x);
    return;
  }
  Level& level = levels_[l];
  // The first sweep from x = 0 is x = w D^-1 b.
  backend_.spmv(*level.smoother, b, x);
  for (int sweep = 1; sweep < sweeps_; ++sweep) smooth(level, b, x);

  backend_.spmv(*level.matrix, x, *level.residual);
  backend_.xpay(b, minus_ones_, *level.residual);
  const bool next_is_coarsest = l + 1 == levels_.size();
  DeviceVectors& coarse_b = next_is_coarsest ? *coarsest_rhs_ : *levels_[l + 1].rhs;
  DeviceVectors& coarse_x = next_is_coarsest ? *coarsest_solution_ : *levels_[l + 1].solution;
  backend_.spmv(*level.restriction, *level.residual, coarse_b);
  cycle(l + 1, coarse_b, coarse_x);
  backend_.spmv(*level.prolongation, coarse_x, *level.step);
  backend_.axpy(ones_, *level.step, x);

  for (int sweep = 0; sweep < sweeps_; ++sweep) smooth(level, b, x);
}

void MultilevelCycle::apply(const DeviceVectors& r, DeviceVectors& z) {
  prepare_work_vectors(r.cols());
  cycle(0, r, z);
}

std::unique_ptr<Preconditioner> Backend::multilevel_preconditioner(
    const AggregationHierarchy& hierarchy) {
  return std::make_unique<MultilevelCycle>(*this, hierarchy);
}

}  // namespace harmonia::detail
