#include "fallback/direct_solvers.h"

#include <mutex>
#include <string>
#include <utility>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#ifdef HARMONIA_HAVE_UMFPACK
#include <Eigen/UmfPackSupport>
#endif
#include "fallback/cholmod_view.h"
#include "fallback/elimination_tree.h"
#include "fallback/renumbered_matrix.h"
#include "fallback/serial_openmp_regions.h"
#include "fallback/subtree_parallel_cholesky.h"

namespace harmonia::detail {
namespace {

// Shared shape of every Eigen direct solver: analyzePattern once, factorize per update, then
// back-substitution for a block of right-hand sides.
template <typename EigenSolver>
class EigenDirectSolver final : public SparseSystemSolver {
 public:
  explicit EigenDirectSolver(std::string name) : name_(std::move(name)) {
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


#ifdef HARMONIA_HAVE_CHOLMOD
// CHOLMOD's Cholesky, supernodal or, for small systems, simplicial (LL^T both; see
// choose_factor_kind), driven directly so that its analysis can take an ordering
// computed elsewhere (cholmod_analyze_p with CHOLMOD_GIVEN). Without one, CHOLMOD chooses (AMD,
// METIS where AMD fills badly), as Eigen's CholmodSupernodalLLT does.
class CholmodCholeskySolver final : public SparseSystemSolver {
 public:
  CholmodCholeskySolver() {
    cholmod_start(&common_);
    common_.print = 0;  // A matrix that is not SPD is reported through the status instead.
    // Simplicial factors as LL^T too (not LDL^T): a matrix that is not positive definite then
    // fails with a non-positive pivot, as in the supernodal factorization, instead of factorizing.
    common_.final_ll = 1;
  }
  ~CholmodCholeskySolver() override {
    release_factor();
    for (cholmod_dense** dense : {&solution_, &workspace_y_, &workspace_e_})
      if (*dense != nullptr) cholmod_free_dense(dense, &common_);
    cholmod_finish(&common_);
  }
  CholmodCholeskySolver(const CholmodCholeskySolver&) = delete;
  CholmodCholeskySolver& operator=(const CholmodCholeskySolver&) = delete;

  void analyze(const Eigen::SparseMatrix<double>& pattern) override {
    release_factor();
    choose_factor_kind(pattern);
    cholmod_sparse view = lower_triangle_view(pattern);
    factor_ = cholmod_analyze(&view, &common_);
  }

  void analyze_with_ordering(const Eigen::SparseMatrix<double>& pattern,
                             const std::vector<int>& ordering) override {
    if (static_cast<Eigen::Index>(ordering.size()) != pattern.rows()) return analyze(pattern);
    release_factor();
    choose_factor_kind(pattern);
    cholmod_sparse view = lower_triangle_view(pattern);
    const int saved_methods = common_.nmethods, saved_ordering = common_.method[0].ordering;
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_GIVEN;
    factor_ = cholmod_analyze_p(&view, const_cast<int*>(ordering.data()), nullptr, 0, &common_);
    common_.nmethods = saved_methods;
    common_.method[0].ordering = saved_ordering;
  }

  // A large matrix whose elimination tree splits in two is factorized on two threads
  // (subtree_parallel_cholesky.h). Otherwise the matrix is renumbered in the order once, and
  // CHOLMOD analyzes and factorizes the renumbered one in its natural order, not postordered:
  // cholmod_factorize then reads it as stored, where a given ordering makes it permute and
  // transpose the matrix on every factorization.
  void analyze_in_elimination_order(const Eigen::SparseMatrix<double>& pattern,
                                    const std::vector<int>& order) override {
    if (static_cast<Eigen::Index>(order.size()) != pattern.rows()) return analyze(pattern);
    release_factor();
    split_ = SubtreeParallelCholesky::analyze(pattern, order);
    if (split_) return;
    choose_factor_kind(pattern);
    order_ = order;
    renumbered_ = renumber_lower(pattern, order_);
    cholmod_sparse view = lower_triangle_view(renumbered_.matrix);
    const int saved_methods = common_.nmethods, saved_ordering = common_.method[0].ordering;
    const int saved_postorder = common_.postorder;
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_NATURAL;
    common_.postorder = 0;
    factor_ = cholmod_analyze(&view, &common_);
    common_.nmethods = saved_methods;
    common_.method[0].ordering = saved_ordering;
    common_.postorder = saved_postorder;
  }

  // Half 0 is factorized while half 1's order is computed (SubtreeParallelCholesky::
  // factorize_halves); where that split cannot be made, the whole order is awaited.
  SolveStats factorize_in_halves(const Eigen::SparseMatrix<double>& matrix,
                                 const std::vector<int>& separator,
                                 const std::vector<int>& first_half,
                                 const std::shared_future<std::vector<int>>& second_half,
                                 const std::function<void()>& meanwhile) override {
    release_factor();
    bool meanwhile_done = false;
    const std::function<void()> once = [&] {
      meanwhile_done = true;
      if (meanwhile) meanwhile();
    };
    split_ = SubtreeParallelCholesky::factorize_halves(matrix, separator, first_half, second_half,
                                                       once);
    if (!split_)
      return SparseSystemSolver::factorize_in_halves(
          matrix, separator, first_half, second_half,
          meanwhile_done ? std::function<void()>() : meanwhile);
    factorized_ = true;
    return {};
  }

  SolveStats factorize(const Eigen::SparseMatrix<double>& matrix) override {
    SolveStats stats;
    if (split_) {
      factorized_ = split_->factorize(matrix);
    } else {
      if (factor_ == nullptr) analyze(matrix);
      if (!order_.empty()) renumbered_.gather(matrix);
      cholmod_sparse view = lower_triangle_view(order_.empty() ? matrix : renumbered_.matrix);
      const SerialOpenMpRegions serial_regions;
      factorized_ = factor_ != nullptr && cholmod_factorize(&view, factor_, &common_) != 0 &&
                    factor_->minor == factor_->n;
      // A simplicial factor is solved as it is: the copy below is for supernodal ones.
      if (factorized_ && fast_solves_ && factor_->is_super) make_solve_factor();
    }
    if (!factorized_) {
      stats.status = Status::numerical_failure;
      stats.message = std::string(kind_name()) +
                      ": numeric factorization failed (matrix is singular or not of the expected "
                      "kind)";
    }
    return stats;
  }

  SolveStats solve(const Eigen::MatrixXd& rhs, Eigen::MatrixXd& solution) override {
    SolveStats stats;
    if (!factorized_) {
      stats.status = Status::numerical_failure;
      stats.message = std::string(kind_name()) + ": solve called without a successful factorization";
      return stats;
    }
    if (split_) {
      solution = split_->solve(rhs);
      if (solution.rows() != rhs.rows()) {
        stats.status = Status::numerical_failure;
        stats.message = std::string(kind_name()) + ": back-substitution failed";
      }
      return stats;
    }
    const Eigen::MatrixXd in_order = order_.empty() ? Eigen::MatrixXd() : rows_in_order(rhs, order_);
    cholmod_dense view = dense_view(order_.empty() ? rhs : in_order);
    // cholmod_solve2 keeps the solution and its workspace from one solve to the next: a fresh
    // allocation per solve costs page faults comparable to the back-substitution itself.
    // Many right-hand sides: the supernodal factor, whose dense kernels then pay off (an editor's
    // set-up solves a hundred columns; kSupernodalSolveColumns).
    const bool many_columns = rhs.cols() >= kSupernodalSolveColumns;
    if (cholmod_solve2(CHOLMOD_A, solve_factor_ != nullptr && !many_columns ? solve_factor_ : factor_, &view,
                       nullptr, &solution_, nullptr, &workspace_y_, &workspace_e_,
                       &common_) == 0) {
      stats.status = Status::numerical_failure;
      stats.message = std::string(kind_name()) + ": back-substitution failed";
      return stats;
    }
    solution = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(solution_->x),
                                                 rhs.rows(), rhs.cols());
    if (!order_.empty()) solution = rows_from_order(solution, order_);
    return stats;
  }

  [[nodiscard]] std::string name() const override {
    return split_ ? std::string(kName) + " on two subtrees" : std::string(kind_name());
  }

  void prefer_fast_solves() override { fast_solves_ = true; }

 private:
  // The copy of the factor that solves use with prefer_fast_solves: simplicial, its columns
  // packed in order. A supernodal solve calls dense BLAS kernels supernode by supernode, which for
  // a few right-hand sides costs more than the arithmetic; the simplicial loops over the same
  // entries take about two thirds of the time (measured on mesh Laplacians of 20K-45K rows).
  void make_solve_factor() {
    if (solve_factor_ != nullptr) cholmod_free_factor(&solve_factor_, &common_);
    solve_factor_ = cholmod_copy_factor(factor_, &common_);
    if (solve_factor_ != nullptr &&
        cholmod_change_factor(CHOLMOD_REAL, /*to_ll=*/1, /*to_super=*/0, /*to_packed=*/1,
                              /*to_monotonic=*/1, solve_factor_, &common_) == 0)
      cholmod_free_factor(&solve_factor_, &common_);
  }

  static constexpr const char* kName = "cholmod-supernodal-llt";
  // From this many right-hand sides on, solves use the supernodal factor rather than the
  // simplicial copy: its BLAS-3 kernels amortize over the columns.
  static constexpr Eigen::Index kSupernodalSolveColumns = 8;

  // Small systems as CHOLMOD chooses, mostly simplicial (kCholmodSimplicialBelowRows, direct_solvers.h).
  void choose_factor_kind(const Eigen::SparseMatrix<double>& pattern) {
    common_.supernodal = pattern.rows() < kCholmodSimplicialBelowRows ? CHOLMOD_AUTO : CHOLMOD_SUPERNODAL;
  }

  [[nodiscard]] const char* kind_name() const {
    return !split_ && common_.supernodal == CHOLMOD_SIMPLICIAL ? "cholmod-simplicial-llt" : kName;
  }

  void release_factor() {
    if (factor_ != nullptr) cholmod_free_factor(&factor_, &common_);
    if (solve_factor_ != nullptr) cholmod_free_factor(&solve_factor_, &common_);
    factor_ = nullptr;
    split_.reset();
    order_.clear();
    renumbered_ = RenumberedLower();
    factorized_ = false;
  }

  cholmod_common common_;
  cholmod_factor* factor_ = nullptr;
  cholmod_factor* solve_factor_ = nullptr;  // prefer_fast_solves: the simplicial copy
  // The last solve's solution and workspace, reused by the next (cholmod_solve2).
  cholmod_dense* solution_ = nullptr;
  cholmod_dense* workspace_y_ = nullptr;
  cholmod_dense* workspace_e_ = nullptr;
  bool fast_solves_ = false;
  std::unique_ptr<SubtreeParallelCholesky> split_;
  // analyze_in_elimination_order without a split: the order and the matrix renumbered in it.
  std::vector<int> order_;
  RenumberedLower renumbered_;
  bool factorized_ = false;
};
#endif

}  // namespace

#ifdef HARMONIA_HAVE_CHOLMOD
namespace {

// CHOLMOD's AMD or METIS ordering of a symmetric pattern; empty when it fails (METIS may be
// missing from CHOLMOD's build).
std::vector<int> cholmod_ordering(const Eigen::SparseMatrix<double>& pattern,
                                  bool nested_dissection) {
  if (pattern.rows() == 0) return {};
  // Two maps run on threads of one application, each ordering on its own background thread, would
  // otherwise share METIS's random numbers; AMD has no such state.
  std::unique_lock<std::mutex> metis;
  if (nested_dissection) metis = metis_lock();
  std::vector<int> ordering(static_cast<std::size_t>(pattern.rows()));
  cholmod_common common;
  cholmod_start(&common);
  common.print = 0;
  cholmod_sparse view = lower_triangle_view(pattern);
  // METIS's order as it is, not postordered: every user postorders it in its own analysis (the
  // reduced angle system on its block graph), and CHOLMOD's postorder costs an elimination tree
  // and two transposes of the pattern.
  const int ordered = nested_dissection
                          ? cholmod_metis(&view, nullptr, 0, 0, ordering.data(), &common)
                          : cholmod_amd(&view, nullptr, 0, ordering.data(), &common);
  cholmod_finish(&common);
  if (ordered == 0) ordering.clear();
  return ordering;
}

}  // namespace
#endif

std::unique_lock<std::mutex> metis_lock() {
  static std::mutex mutex;
  return std::unique_lock<std::mutex>(mutex);
}

std::vector<int> fill_reducing_ordering(const Eigen::SparseMatrix<double>& pattern) {
#ifdef HARMONIA_HAVE_CHOLMOD
  return cholmod_ordering(pattern, false);
#else
  (void)pattern;
  return {};
#endif
}

std::vector<int> nested_dissection_ordering(const Eigen::SparseMatrix<double>& pattern) {
#ifdef HARMONIA_HAVE_CHOLMOD
  // A small graph is ordered by AMD: METIS's multilevel bisection costs more than it saves there
  // (linear ABF on atlas charts of up to 5,000 faces: less CPU time with AMD at every size).
  constexpr Eigen::Index amd_below_rows = 5000;
  if (pattern.rows() < amd_below_rows) return cholmod_ordering(pattern, false);
  std::vector<int> ordering = cholmod_ordering(pattern, true);
  return ordering.empty() ? cholmod_ordering(pattern, false) : ordering;  // AMD without METIS.
#else
  (void)pattern;
  return {};
#endif
}

std::vector<int> postordered_ordering(const Eigen::SparseMatrix<double>& pattern,
                                      const std::vector<int>& ordering) {
  if (ordering.size() != static_cast<std::size_t>(pattern.rows())) return ordering;
  std::vector<int> position(ordering.size(), -1);
  for (std::size_t k = 0; k < ordering.size(); ++k) {
    const int row = ordering[k];
    if (row < 0 || row >= pattern.rows() || position[static_cast<std::size_t>(row)] >= 0)
      return ordering;  // Not a permutation.
    position[static_cast<std::size_t>(row)] = static_cast<int>(k);
  }
  // The tree's k-th node is the row eliminated k-th.
  std::vector<int> postordered = postorder(elimination_tree(pattern, position));
  for (int& node : postordered) node = ordering[static_cast<std::size_t>(node)];
  return postordered;
}

std::unique_ptr<SparseSystemSolver> make_cholesky_solver() {
#ifdef HARMONIA_HAVE_CHOLMOD
  return std::make_unique<CholmodCholeskySolver>();
#else
  using Cholesky = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>;
  return std::make_unique<EigenDirectSolver<Cholesky>>("eigen-simplicial-ldlt");
#endif
}

std::unique_ptr<SparseSystemSolver> make_lu_solver() {
#ifdef HARMONIA_HAVE_UMFPACK
  // SuiteSparse's multifrontal LU (dense frontal matrices through BLAS): about 2.5 times faster
  // than Eigen's supernodal SparseLU on the mean-value systems of 100K vertices.
  return std::make_unique<EigenDirectSolver<Eigen::UmfPackLU<Eigen::SparseMatrix<double>>>>(
      "umfpack-lu");
#else
  using Lu = Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>>;
  return std::make_unique<EigenDirectSolver<Lu>>("eigen-sparse-lu");
#endif
}

}  // namespace harmonia::detail
