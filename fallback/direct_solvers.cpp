#include "fallback/direct_solvers.h"

#include <string>
#include <utility>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#ifdef HARMONIA_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

namespace harmonia::detail {
namespace {

// Shared shape of every Eigen direct solver: analyzePattern once, factorize per update, then
// back-substitution for a block of right-hand sides.
template <typename EigenSolver>
class EigenDirectSolver final : public SparseSystemSolver {
 public:
  explicit EigenDirectSolver(std::string name) : name_(std::move(name)) {
#ifdef HARMONIA_HAVE_CHOLMOD
    // CHOLMOD would print its own warning for a matrix that is not SPD; the status says it instead.
    if constexpr (requires(EigenSolver & solver) { solver.cholmod().print; })
      solver_.cholmod().print = 0;
#endif
  }

  void analyze(const Eigen::SparseMatrix<double>& pattern) override {
    solver_.analyzePattern(pattern);
    analyzed_ = true;
    factorized_ = false;
  }

  SolveStats factorize(const Eigen::SparseMatrix<double>& matrix) override {
    SolveStats stats;
    if (!analyzed_) analyze(matrix);
    solver_.factorize(matrix);
    factorized_ = solver_.info() == Eigen::Success;
    if (!factorized_) {
      stats.status = Status::numerical_failure;
      stats.message = name_ + ": numeric factorization failed (" +
                      (solver_.info() == Eigen::NumericalIssue
                           ? "matrix is singular or not of the expected kind"
                           : "invalid input") +
                      ")";
    }
    return stats;
  }

  SolveStats solve(const Eigen::MatrixXd& rhs, Eigen::MatrixXd& solution) override {
    SolveStats stats;
    if (!factorized_) {
      stats.status = Status::numerical_failure;
      stats.message = name_ + ": solve called without a successful factorization";
      return stats;
    }
    solution = solver_.solve(rhs);
    if (solver_.info() != Eigen::Success) {
      stats.status = Status::numerical_failure;
      stats.message = name_ + ": back-substitution failed";
    }
    return stats;
  }

  [[nodiscard]] std::string name() const override { return name_; }

 private:
  EigenSolver solver_;
  std::string name_;
  bool analyzed_ = false;
  bool factorized_ = false;
};

}  // namespace

std::unique_ptr<SparseSystemSolver> make_cholesky_solver() {
#ifdef HARMONIA_HAVE_CHOLMOD
  using Cholesky = Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower>;
  return std::make_unique<EigenDirectSolver<Cholesky>>("cholmod-supernodal-llt");
#else
  using Cholesky = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>;
  return std::make_unique<EigenDirectSolver<Cholesky>>("eigen-simplicial-ldlt");
#endif
}

std::unique_ptr<SparseSystemSolver> make_lu_solver() {
  using Lu = Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>>;
  return std::make_unique<EigenDirectSolver<Lu>>("eigen-sparse-lu");
}

}  // namespace harmonia::detail
