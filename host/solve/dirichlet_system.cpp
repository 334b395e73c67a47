#include "solve/dirichlet_system.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "solve/backend_selection.h"

namespace harmonia::detail {
namespace {

// a / b, or 0 where b is 0: a column whose residual is exactly zero takes no step.
double safe_divide(double a, double b) { return b != 0.0 ? a / b : 0.0; }

// Largest over the columns of |numerator_c| / |denominator_c| (the absolute norm where the
// denominator column is zero); infinity for a non-finite ratio.
double worst_relative(const Eigen::MatrixXd& numerator, const Eigen::MatrixXd& denominator) {
  double worst = 0.0;
  for (Eigen::Index c = 0; c < numerator.cols(); ++c) {
    const double top = numerator.col(c).norm(), bottom = denominator.col(c).norm();
    const double relative = bottom > 0.0 ? top / bottom : top;
    worst = std::max(worst, std::isfinite(relative) ? relative : INFINITY);
  }
  return worst;
}

}  // namespace

DirichletSystem::DirichletSystem(const Eigen::SparseMatrix<double>& operator_pattern,
                                 const Eigen::VectorXi& fixed_vertices, Backend& backend,
                                 MatrixKind kind, const SolverOptions& options,
                                 const std::vector<int>& vertex_ordering)
    : backend_(backend), options_(options), fixed_vertices_(fixed_vertices), kind_(kind) {
  const auto vertex_count = static_cast<int>(operator_pattern.rows());
  free_index_.assign(static_cast<std::size_t>(vertex_count), -1);
  fixed_index_.assign(static_cast<std::size_t>(vertex_count), -1);
  for (Eigen::Index k = 0; k < fixed_vertices.size(); ++k)
    fixed_index_[fixed_vertices[k]] = static_cast<int>(k);
  for (int v = 0; v < vertex_count; ++v) {
    if (fixed_index_[v] >= 0) continue;
    free_index_[v] = static_cast<int>(free_vertices_.size());
    free_vertices_.push_back(v);
  }
  build_index_maps(operator_pattern);
  analyze_with(
      make_system_solver(backend_, kind_, iterative_settings(options_), options_.progress),
      vertex_ordering);
}

void DirichletSystem::build_index_maps(const Eigen::SparseMatrix<double>& operator_pattern) {
  // A compressed pattern is read in place (the usual case: a freshly assembled operator).
  Eigen::SparseMatrix<double> compressed;
  if (!operator_pattern.isCompressed()) {
    compressed = operator_pattern;
    compressed.makeCompressed();
  }
  const Eigen::SparseMatrix<double>& pattern =
      operator_pattern.isCompressed() ? operator_pattern : compressed;
  const auto vertex_count = static_cast<int>(pattern.cols());
  const int* outer = pattern.outerIndexPtr();
  const int* inner = pattern.innerIndexPtr();
  pattern_outer_.assign(outer, outer + vertex_count + 1);
  pattern_inner_.assign(inner, inner + pattern.nonZeros());
  slot_target_.assign(pattern_inner_.size(), -1);

  // L_II: the free columns in order, each keeping its free rows. free_index is increasing, so the
  // rows of every column stay sorted. L_IB: the fixed columns in fixed_vertices order. Both are
  // written straight into their compressed arrays: one pass counts, one pass fills.
  const auto extract = [&](Eigen::SparseMatrix<double>& block, const auto& columns,
                           Eigen::Index column_count, bool interior) {
    block.resize(free_count(), column_count);
    Eigen::Index count = 0;
    for (Eigen::Index k = 0; k < column_count; ++k)
      for (int slot = outer[columns[k]]; slot < outer[columns[k] + 1]; ++slot)
        count += free_index_[inner[slot]] >= 0 ? 1 : 0;
    block.resizeNonZeros(count);
    int* block_outer = block.outerIndexPtr();
    int* block_inner = block.innerIndexPtr();
    int next = 0;
    block_outer[0] = 0;
    for (Eigen::Index k = 0; k < column_count; ++k) {
      for (int slot = outer[columns[k]]; slot < outer[columns[k] + 1]; ++slot) {
        const int row = free_index_[inner[slot]];
        if (row < 0) continue;
        slot_target_[static_cast<std::size_t>(slot)] = interior ? next : -2 - next;
        block_inner[next++] = row;
      }
      block_outer[k + 1] = next;
    }
    std::fill(block.valuePtr(), block.valuePtr() + count, 0.0);
  };
  extract(interior_, free_vertices_, free_count(), true);
  extract(coupling_, fixed_vertices_, fixed_vertices_.size(), false);
}

void DirichletSystem::analyze_with(std::unique_ptr<SparseSystemSolver> solver,
                                   const std::vector<int>& vertex_ordering) {
  solver_ = std::move(solver);
  if (free_count() > 0 && vertex_ordering.size() == free_index_.size()) {
    std::vector<int> ordering;  // The free vertices in the given order, as unknowns.
    ordering.reserve(free_vertices_.size());
    for (const int v : vertex_ordering)
      if (v >= 0 && v < static_cast<int>(free_index_.size()) && free_index_[v] >= 0)
        ordering.push_back(free_index_[v]);
    solver_->analyze_with_ordering(interior_, ordering);
  } else if (free_count() > 0) {
    solver_->analyze(interior_);
  }
  factorized_ = false;
  has_factor_ = false;
}

bool DirichletSystem::load(const Eigen::SparseMatrix<double>& operator_matrix,
                           SolveReport& report) {
  if (operator_matrix.rows() != static_cast<Eigen::Index>(free_index_.size()) ||
      operator_matrix.cols() != operator_matrix.rows())
    throw std::invalid_argument("DirichletSystem: operator has the wrong size");
  factorized_ = false;
  const Eigen::Index nonzeros = operator_matrix.nonZeros();
  const bool same_pattern =
      operator_matrix.isCompressed() &&
      nonzeros == static_cast<Eigen::Index>(pattern_inner_.size()) &&
      std::equal(pattern_outer_.begin(), pattern_outer_.end(), operator_matrix.outerIndexPtr()) &&
      std::equal(pattern_inner_.begin(), pattern_inner_.end(), operator_matrix.innerIndexPtr());
  if (!same_pattern) return scatter_other_pattern(operator_matrix, report);

  const double* values = operator_matrix.valuePtr();
  double* interior = interior_.valuePtr();
  double* coupling = coupling_.valuePtr();
  bool finite = true;
  for (Eigen::Index slot = 0; slot < nonzeros; ++slot) {
    const int target = slot_target_[static_cast<std::size_t>(slot)];
    if (target >= 0) {
      interior[target] = values[slot];
    } else if (target <= -2) {
      coupling[-2 - target] = values[slot];
    } else {
      continue;
    }
    finite = finite && std::isfinite(values[slot]);
  }
  // A non-finite entry is rare: the generic path finds it and names it.
  return finite || scatter_other_pattern(operator_matrix, report);
}

// Any pattern contained in the analyzed one: every entry is placed by a binary search.
bool DirichletSystem::scatter_other_pattern(const Eigen::SparseMatrix<double>& operator_matrix,
                                            SolveReport& report) {
  std::fill(interior_.valuePtr(), interior_.valuePtr() + interior_.nonZeros(), 0.0);
  std::fill(coupling_.valuePtr(), coupling_.valuePtr() + coupling_.nonZeros(), 0.0);
  const auto find = [](Eigen::SparseMatrix<double>& matrix, int column, int row) -> double& {
    const int* rows = matrix.innerIndexPtr() + matrix.outerIndexPtr()[column];
    const int* rows_end = matrix.innerIndexPtr() + matrix.outerIndexPtr()[column + 1];
    const int* found = std::lower_bound(rows, rows_end, row);
    if (found == rows_end || *found != row)
      throw std::logic_error("DirichletSystem: operator entry outside the mesh-edge pattern");
    return matrix.valuePtr()[found - matrix.innerIndexPtr()];
  };
  for (int column = 0; column < operator_matrix.outerSize(); ++column) {
    for (Eigen::SparseMatrix<double>::InnerIterator entry(operator_matrix, column); entry;
         ++entry) {
      const int row_free = free_index_[entry.row()];
      if (row_free < 0 || entry.value() == 0.0) continue;
      if (!std::isfinite(entry.value())) {
        report.status = Status::numerical_failure;
        report.message = "the operator has a non-finite entry at (" + std::to_string(entry.row()) +
                         ", " + std::to_string(column) + "): degenerate triangles near vertex " +
                         std::to_string(entry.row()) + "?";
        return false;
      }
      const int column_free = free_index_[column];
      if (column_free < 0)
        find(coupling_, fixed_index_[column], row_free) += entry.value();
      else
        find(interior_, column_free, row_free) += entry.value();
    }
  }
  return true;
}

bool DirichletSystem::factorize_loaded(SolveReport& report) {
  factorized_ = false;
  if (free_count() == 0) {
    factorized_ = true;
    return true;
  }
  SolveStats stats = solver_->factorize(interior_);
  if (stats.status != Status::ok && may_move_to_cpu(stats)) return move_to_cpu(stats, report);
  if (stats.status != Status::ok && kind_ == MatrixKind::symmetric_positive_definite &&
      active_backend().supports(Feature::direct_factorization)) {
    // Cotangent-type matrices are SPD for non-degenerate input; if Cholesky disagrees, LU decides.
    kind_ = MatrixKind::general;
    fell_back_to_lu_ = true;
    const std::string failed = solver_->name();
    analyze_with(
        make_system_solver(active_backend(), kind_, iterative_settings(options_), options_.progress));
    report.solver =
        solver_->name() + " (after " + failed + " found the matrix not positive definite)";
    stats = solver_->factorize(interior_);
  } else if (!fell_back_to_lu_) {
    report.solver = solver_->name();
  }
  if (stats.status != Status::ok) {
    report.status = stats.status;
    report.message = stats.message;
    return false;
  }
  factorized_ = true;
  has_factor_ = true;
  return true;
}

bool DirichletSystem::may_move_to_cpu(const SolveStats& failed) const {
  return !cpu_backend_ && may_retry_on_cpu(options_.backend, backend_, failed);
}

bool DirichletSystem::move_to_cpu(const SolveStats& failed, SolveReport& report) {
  const std::string device_solver = solver_->name();
  cpu_backend_ = make_backend(BackendChoice::cpu, nullptr);
  analyze_with(make_system_solver(*cpu_backend_, kind_, iterative_settings(options_), options_.progress));
  const SolveStats stats = solver_->factorize(interior_);
  if (stats.status != Status::ok) {
    report.status = stats.status;
    report.message = stats.message + " (on the CPU, after the device's " + device_solver + " failed: " +
                     failed.message + ")";
    return false;
  }
  report.fallbacks.push_back(cpu_retry_notice(device_solver, failed, *cpu_backend_));
  report.solver = solver_->name() + " (after the device's " + device_solver + " failed)";
  factorized_ = true;
  has_factor_ = true;
  return true;
}

Eigen::MatrixXd DirichletSystem::right_hand_side(const Eigen::MatrixXd& fixed_values) const {
  return -(coupling_ * fixed_values);
}

void DirichletSystem::record_solution(const Eigen::MatrixXd& solution, const Eigen::MatrixXd& rhs,
                                      const Eigen::MatrixXd& fixed_values, Eigen::MatrixXd& values,
                                      SolveReport& report) {
  // Residual of every column, measured here independently of the solver.
  if (measure_residual_) {
    const Eigen::MatrixXd residual = interior_ * solution - rhs;
    report.residual = std::max(report.residual, worst_relative(residual, rhs));
  }
  if (&solution != &last_solution_) last_solution_ = solution;
  values.resize(static_cast<Eigen::Index>(free_index_.size()), fixed_values.cols());
  for (Eigen::Index k = 0; k < fixed_vertices_.size(); ++k)
    values.row(fixed_vertices_[k]) = fixed_values.row(k);
  for (int i = 0; i < free_count(); ++i) values.row(free_vertices_[i]) = solution.row(i);
}

bool DirichletSystem::solve(const Eigen::MatrixX2d& fixed_uv, Eigen::MatrixX2d& uv,
                            SolveReport& report) {
  return solve(fixed_uv, Eigen::MatrixX2d(), uv, report);
}

bool DirichletSystem::solve(const Eigen::MatrixX2d& fixed_uv, const Eigen::MatrixX2d& load,
                            Eigen::MatrixX2d& uv, SolveReport& report) {
  Eigen::MatrixXd values;
  if (!solve_columns(fixed_uv, load, values, report)) return false;
  uv = values;
  return true;
}

bool DirichletSystem::solve_columns(const Eigen::MatrixXd& fixed_values,
                                    const Eigen::MatrixXd& load, Eigen::MatrixXd& values,
                                    SolveReport& report) {
  if (!factorized_) {
    report.status = Status::numerical_failure;
    report.message = "solve without a successful factorization";
    return false;
  }
  const Eigen::Index columns = fixed_values.cols();
  if (free_count() == 0) {
    record_solution(Eigen::MatrixXd(0, columns), Eigen::MatrixXd(0, columns), fixed_values, values,
                    report);
    return true;
  }
  // The right-hand side and the solution live in members, reused from solve to solve: a fresh
  // allocation of this size per frame costs page faults comparable to a back-substitution.
  rhs_.resize(free_count(), columns);
  rhs_.setZero();
  rhs_.noalias() -= coupling_ * fixed_values;
  if (load.rows() > 0) {
    for (int i = 0; i < free_count(); ++i) rhs_.row(i) += load.row(free_vertices_[i]);
  }
  // The last solution is the warm start of an iterative solver when it has the same shape.
  if (last_solution_.rows() != free_count() || last_solution_.cols() != columns)
    last_solution_.resize(0, columns);
  SolveStats stats = solver_->solve(rhs_, last_solution_);
  report.iterations += stats.iterations;
  if (stats.status != Status::ok && may_move_to_cpu(stats)) {
    if (!move_to_cpu(stats, report)) return false;
    stats = solver_->solve(rhs_, last_solution_);
  }
  if (stats.status != Status::ok) {
    report.status = stats.status;
    report.message = stats.message;
    return false;
  }
  record_solution(last_solution_, rhs_, fixed_values, values, report);
  return true;
}

bool DirichletSystem::has_reusable_factor() const {
  return has_factor_ && !fell_back_to_lu_ && kind_ == MatrixKind::symmetric_positive_definite &&
         active_backend().supports(Feature::direct_factorization) && free_count() > 0 &&
         last_solution_.rows() == free_count();
}

StaleFactorOutcome DirichletSystem::solve_with_stale_factor(const Eigen::MatrixX2d& fixed_uv,
                                                            double error_target,
                                                            double residual_target,
                                                            int max_iterations,
                                                            Eigen::MatrixX2d& uv,
                                                            SolveReport& report) {
  if (!has_reusable_factor()) return StaleFactorOutcome::too_slow;
  const Eigen::MatrixXd rhs = right_hand_side(fixed_uv);
  const auto precondition = [this](const Eigen::MatrixXd& residual, Eigen::MatrixXd& result,
                                   SolveReport& failure) {
    const SolveStats stats = solver_->solve(residual, result);
    if (stats.status == Status::ok) return true;
    failure.status = stats.status;
    failure.message = stats.message;
    return false;
  };

  // Conjugate gradients on every column at once, preconditioned by the stale factor F: z = F^-1 r
  // is then nearly A^-1 r, the error of the iterate, which is what the stopping test reads.
  Eigen::MatrixXd x = last_solution_;
  Eigen::MatrixXd residual = rhs - interior_ * x;
  Eigen::MatrixXd preconditioned;
  if (!precondition(residual, preconditioned, report)) return StaleFactorOutcome::failed;
  Eigen::MatrixXd direction = preconditioned;
  Eigen::VectorXd residual_dot = residual.cwiseProduct(preconditioned).colwise().sum();
  std::vector<double> error_history;
  for (int iteration = 0;; ++iteration) {
    const double error = worst_relative(preconditioned, x);
    error_history.push_back(error);
    if (worst_relative(residual, rhs) <= residual_target && error <= error_target) break;
    if (!std::isfinite(error) || iteration >= max_iterations) return StaleFactorOutcome::too_slow;
    if (iteration >= 2) {
      // Contraction per iteration over the last two; give up early when it predicts too many.
      const double rate = std::sqrt(error / error_history[iteration - 2]);
      if (!(rate < 1.0)) return StaleFactorOutcome::too_slow;
      const double remaining = std::log(error_target / error) / std::log(rate);
      if (iteration + remaining > max_iterations) return StaleFactorOutcome::too_slow;
    }
    const Eigen::MatrixXd product = interior_ * direction;
    const Eigen::VectorXd curvature = direction.cwiseProduct(product).colwise().sum();
    Eigen::VectorXd step(x.cols());
    for (Eigen::Index c = 0; c < x.cols(); ++c)
      step[c] = safe_divide(residual_dot[c], curvature[c]);
    x += direction * step.asDiagonal();
    residual -= product * step.asDiagonal();
    if (!precondition(residual, preconditioned, report)) return StaleFactorOutcome::failed;
    const Eigen::VectorXd next_dot = residual.cwiseProduct(preconditioned).colwise().sum();
    Eigen::VectorXd beta(x.cols());
    for (Eigen::Index c = 0; c < x.cols(); ++c) beta[c] = safe_divide(next_dot[c], residual_dot[c]);
    residual_dot = next_dot;
    direction = preconditioned + direction * beta.asDiagonal();
    ++report.iterations;
  }
  Eigen::MatrixXd values;
  record_solution(x, rhs, fixed_uv, values, report);
  uv = values;
  return StaleFactorOutcome::converged;
}

}  // namespace harmonia::detail
