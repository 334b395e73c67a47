#include "backend/iterative_system_solver.h"

#include <optional>
#include <string>

#include "backend/aggregation_hierarchy.h"

namespace harmonia::detail {
namespace {

class IterativeSystemSolver final : public SparseSystemSolver {
 public:
  IterativeSystemSolver(Backend& backend, MatrixKind kind, const IterativeSettings& settings,
                        const ProgressCallback& progress)
      : backend_(backend), kind_(kind), settings_(settings), progress_(progress) {}

  // Nothing symbolic to do for a Krylov method: the pattern is uploaded with the first values.
  void analyze(const Eigen::SparseMatrix<double>&) override { matrix_.reset(); }

  SolveStats factorize(const Eigen::SparseMatrix<double>& matrix) override {
    transpose_ = matrix.transpose();
    // General matrices are solved through the SPD normal equations.
    const Eigen::SparseMatrix<double> system =
        kind_ == MatrixKind::general ? Eigen::SparseMatrix<double>(transpose_ * matrix) : matrix;
    RowMajorSparse row_major(system);
    row_major.makeCompressed();
    if (matrix_ && matrix_->rows() == row_major.rows() &&
        pattern_nonzeros_ == row_major.nonZeros()) {
      matrix_->update_values(
          Eigen::Map<const Eigen::VectorXd>(row_major.valuePtr(), row_major.nonZeros()));
    } else {
      matrix_ = backend_.upload(row_major);
      pattern_nonzeros_ = row_major.nonZeros();
    }
    if (uses_multilevel()) prepare_multilevel(system);
    return {};
  }

  SolveStats solve(const Eigen::MatrixXd& rhs, Eigen::MatrixXd& solution) override {
    if (!matrix_) {
      SolveStats stats;
      stats.status = Status::numerical_failure;
      stats.message = name() + ": solve called before factorize";
      return stats;
    }
    const Eigen::MatrixXd system_rhs =
        kind_ == MatrixKind::general ? Eigen::MatrixXd(transpose_ * rhs) : rhs;
    if (solution.rows() != rhs.rows() || solution.cols() != rhs.cols())
      solution = Eigen::MatrixXd::Zero(rhs.rows(), rhs.cols());
    const auto b = backend_.upload(system_rhs);
    const auto x = backend_.upload(solution);
    const SolveStats stats =
        kind_ == MatrixKind::symmetric_indefinite
            ? backend_.minres(*matrix_, *b, *x, settings_, progress_)
        : preconditioner_
            ? backend_.preconditioned_pcg(*matrix_, *preconditioner_, *b, *x, settings_, progress_)
            : backend_.pcg(*matrix_, *b, *x, settings_, progress_);
    solution = x->download();
    return stats;
  }

  [[nodiscard]] std::string name() const override {
    // Before the first factorization, what the settings ask for; after it, what was built.
    const bool multilevel = matrix_ ? preconditioner_ != nullptr : uses_multilevel();
    const std::string pcg = multilevel ? "pcg-multilevel" : "pcg-jacobi";
    switch (kind_) {
      case MatrixKind::symmetric_positive_definite:
        return pcg;
      case MatrixKind::symmetric_indefinite:
        return "minres";
      case MatrixKind::general:
        return pcg + "-normal-equations";
    }
    return "iterative";
  }

 private:
  [[nodiscard]] bool uses_multilevel() const {
    return kind_ != MatrixKind::symmetric_indefinite &&
           settings_.preconditioner == IterativePreconditioner::multilevel;
  }

  // The hierarchy of the SPD system: its numeric part only when the pattern is the one aggregated
  // (a quasi-harmonic round, a new Newton step), else aggregated anew. A matrix with a diagonal
  // entry that is not positive has no Jacobi smoother: its solves fall back to plain pcg, which
  // then reports the failure with its own figures.
  void prepare_multilevel(const Eigen::SparseMatrix<double>& system) {
    try {
      if (!hierarchy_ || !hierarchy_->refresh(system)) hierarchy_.emplace(system);
      preconditioner_ = backend_.multilevel_preconditioner(*hierarchy_);
    } catch (const Error&) {
      hierarchy_.reset();
      preconditioner_.reset();
    }
  }

  Backend& backend_;
  MatrixKind kind_;
  IterativeSettings settings_;
  ProgressCallback progress_;
  std::unique_ptr<DeviceMatrix> matrix_;
  Eigen::Index pattern_nonzeros_ = 0;
  Eigen::SparseMatrix<double> transpose_;
  std::optional<AggregationHierarchy> hierarchy_;
  std::unique_ptr<Preconditioner> preconditioner_;
};

}  // namespace

std::unique_ptr<SparseSystemSolver> make_iterative_solver(Backend& backend, MatrixKind kind,
                                                          const IterativeSettings& settings,
                                                          const ProgressCallback& progress) {
  return std::make_unique<IterativeSystemSolver>(backend, kind, settings, progress);
}

IterativeSettings iterative_settings(const SolverOptions& options) {
  IterativeSettings settings;
  settings.relative_tolerance = options.tolerance;
  settings.max_iterations = options.max_iterations;
  settings.preconditioner = options.preconditioner;
  return settings;
}

}  // namespace harmonia::detail
