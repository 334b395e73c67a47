#include "fallback/bordered_cholesky.h"

#include <algorithm>
#include <cmath>

#include "fallback/cholmod_view.h"
#include "fallback/direct_solvers.h"
#include "fallback/renumbered_matrix.h"
#include "fallback/serial_openmp_regions.h"
#include "fallback/subtree_parallel_cholesky.h"

namespace harmonia::detail {

#ifdef HARMONIA_HAVE_CHOLMOD
namespace {

class CholmodBorderedCholesky final : public BorderedCholesky {
 public:
  CholmodBorderedCholesky() {
    cholmod_start(&common_);
    common_.supernodal = CHOLMOD_SUPERNODAL;
    // A simplicial factor as LL^T too (not LDL^T): R_BB is then read off it as off a supernodal
    // one, and a matrix that is not positive definite fails with a non-positive pivot.
    common_.final_ll = 1;
    common_.print = 0;
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_NATURAL;
  }
  ~CholmodBorderedCholesky() override {
    release();
    cholmod_finish(&common_);
  }
  CholmodBorderedCholesky(const CholmodBorderedCholesky&) = delete;
  CholmodBorderedCholesky& operator=(const CholmodBorderedCholesky&) = delete;

  // The matrix is renumbered in its elimination order (the postorder of `ordering` where
  // that keeps the border last, else `ordering` itself) and factorized as it is stored: on two
  // threads where its elimination tree splits below the border (subtree_parallel_cholesky.h),
  // else by CHOLMOD in its natural order, which reads the matrix without permuting it.
  bool analyze(const Eigen::SparseMatrix<double>& lower, const std::vector<int>& ordering,
               int border_size) override {
    release();
    const auto size = static_cast<int>(lower.rows());
    if (static_cast<int>(ordering.size()) != size || border_size < 0 || border_size > size)
      return false;
    std::vector<char> in_border(static_cast<std::size_t>(size), 0);
    for (int k = size - border_size; k < size; ++k)
      in_border[static_cast<std::size_t>(ordering[static_cast<std::size_t>(k)])] = 1;
    // The postorder keeps the border last when the border's Schur complement is connected
    // (the border is then the top of the tree); otherwise it may interleave it with others.
    order_ = postordered_ordering(lower, ordering);
    for (int k = size - border_size; k < size; ++k)
      if (!in_border[static_cast<std::size_t>(order_[static_cast<std::size_t>(k)])]) {
        order_ = ordering;
        break;
      }
    renumbered_ = renumber_lower(lower, order_);
    size_ = size;
    split_ = SubtreeParallelCholesky::analyze(renumbered_.matrix, {},
                                              SubtreeParallelCholesky::kDefaultMinimumRows,
                                              border_size);
    if (split_) {
      border_size_ = border_size;
      const SubtreeParallelCholesky::Shape shape = split_->shape();
      flops_ = shape.half_flops[0] + shape.half_flops[1] +
               std::pow(static_cast<double>(shape.separator_rows), 3);
      return true;
    }
    return analyze_natural(renumbered_.matrix, border_size);
  }

  bool analyze_in_elimination_order(const Eigen::SparseMatrix<double>& matrix, int border_size,
                                    StoredTriangle triangle) override {
    release();
    upper_ = triangle == StoredTriangle::upper;
    return analyze_natural(matrix, border_size);
  }

  [[nodiscard]] double factorization_flops() const override { return flops_; }
  [[nodiscard]] bool on_two_threads() const override { return split_ != nullptr; }
  [[nodiscard]] const char* name() const override {
    return factor_ != nullptr && !factor_->is_super ? "cholmod-simplicial-llt" : "cholmod-supernodal-llt";
  }

  // A symbolic supernodal factor becomes numeric by the allocation of its values alone
  // (cholmod_change_factor leaves them undefined); cholmod_factorize then fills them.
  std::pair<void*, std::size_t> allocate_factor_storage() override {
    if (split_ || factor_ == nullptr || !factor_->is_super) return {nullptr, 0};
    if (factor_->xtype == CHOLMOD_PATTERN &&
        cholmod_change_factor(CHOLMOD_REAL, true, true, true, true, factor_, &common_) == 0)
      return {nullptr, 0};
    return {factor_->x, factor_->xsize * sizeof(double)};
  }

  bool factorize(const Eigen::SparseMatrix<double>& lower) override {
    factorized_ = false;
    const Eigen::SparseMatrix<double>* matrix = &lower;
    if (!order_.empty()) {  // Renumbered: gather the values.
      renumbered_.gather(lower);
      matrix = &renumbered_.matrix;
    }
    if (split_) {
      factorized_ = split_->factorize(*matrix);
      return factorized_;
    }
    if (factor_ == nullptr) return false;
    cholmod_sparse view = lower_triangle_view(*matrix, upper_);
    const SerialOpenMpRegions serial_regions;
    factorized_ = cholmod_factorize(&view, factor_, &common_) != 0 && factor_->minor == factor_->n;
    return factorized_;
  }

  [[nodiscard]] Eigen::MatrixXd forward(const Eigen::MatrixXd& b) const override {
    if (b.rows() != static_cast<Eigen::Index>(size_)) return {};
    const Eigen::MatrixXd permuted = order_.empty() ? b : rows_in_order(b, order_);
    return split_ ? split_->forward(permuted) : solve_step(permuted, CHOLMOD_L);
  }

  [[nodiscard]] Eigen::MatrixXd backward(const Eigen::MatrixXd& y) const override {
    if (y.rows() != static_cast<Eigen::Index>(size_)) return {};
    const Eigen::MatrixXd solution = split_ ? split_->backward(y) : solve_step(y, CHOLMOD_Lt);
    if (order_.empty() || solution.rows() != y.rows()) return solution;
    return rows_from_order(solution, order_);
  }

  [[nodiscard]] Eigen::MatrixXd border_factor() const override {
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(border_size_, border_size_);
    if (!factorized_ || border_size_ == 0) return block;
    if (split_) return split_->trailing_factor(border_size_);
    const auto size = static_cast<int>(factor_->n);
    const int first = size - border_size_;
    const double* values = static_cast<const double*>(factor_->x);
    if (!factor_->is_super) {
      // Column j of the simplicial factor: nz[j] entries from p[j] on, the diagonal first.
      const int* column_start = static_cast<const int*>(factor_->p);
      const int* column_count = static_cast<const int*>(factor_->nz);
      const int* rows = static_cast<const int*>(factor_->i);
      for (int column = first; column < size; ++column)
        for (int k = column_start[column]; k < column_start[column] + column_count[column]; ++k)
          if (rows[k] >= first) block(rows[k] - first, column - first) = values[k];
      return block;
    }
    // Column j of the supernodal factor lives in the supernode s with super[s] <= j < super[s+1],
    // stored column-major as nsrow x nscol values with the row indices s[pi[s]..pi[s+1]).
    const int* super = static_cast<const int*>(factor_->super);
    const int* row_start = static_cast<const int*>(factor_->pi);
    const int* value_start = static_cast<const int*>(factor_->px);
    const int* rows = static_cast<const int*>(factor_->s);
    int supernode = 0;
    for (int column = first; column < size; ++column) {
      while (super[supernode + 1] <= column) ++supernode;
      const int row_count = row_start[supernode + 1] - row_start[supernode];
      const int offset = column - super[supernode];
      const double* column_values = values + value_start[supernode] + offset * row_count;
      // Rows above the diagonal within the supernode's own columns are not part of R.
      for (int position = offset; position < row_count; ++position) {
        const int row = rows[row_start[supernode] + position];
        if (row >= first) block(row - first, column - first) = column_values[position];
      }
    }
    return block;
  }

 private:
  // The natural-order analysis of `lower` (already in elimination order, its border last).
  bool analyze_natural(const Eigen::SparseMatrix<double>& matrix, int border_size) {
    size_ = static_cast<int>(matrix.rows());
    if (border_size < 0 || border_size > size_) return false;
    border_size_ = border_size;
    cholmod_sparse view = lower_triangle_view(matrix, upper_);
    const int saved_ordering = common_.method[0].ordering, saved_postorder = common_.postorder;
    common_.method[0].ordering = CHOLMOD_NATURAL;
    common_.postorder = 0;
    common_.supernodal = size_ < kCholmodSimplicialBelowRows ? CHOLMOD_AUTO : CHOLMOD_SUPERNODAL;
    factor_ = cholmod_analyze(&view, &common_);
    common_.method[0].ordering = saved_ordering;
    common_.postorder = saved_postorder;
    // CHOLMOD keeps the natural order (no permutation to undo in the solves).
    if (factor_ == nullptr || factor_->ordering != CHOLMOD_NATURAL) {
      release();
      return false;
    }
    flops_ = common_.fl;
    return true;
  }

  // One of CHOLMOD's solve systems (CHOLMOD_L or CHOLMOD_Lt) of the natural-order factor.
  Eigen::MatrixXd solve_step(const Eigen::MatrixXd& rhs, int system) const {
    if (factor_ == nullptr) return {};
    auto& common = const_cast<cholmod_common&>(common_);
    cholmod_dense view = dense_view(rhs);
    cholmod_dense* result = cholmod_solve(system, factor_, &view, &common);
    Eigen::MatrixXd solution;
    if (result != nullptr)
      solution = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(result->x),
                                                   rhs.rows(), rhs.cols());
    cholmod_free_dense(&result, &common);
    return solution;
  }

  void release() {
    if (factor_ != nullptr) cholmod_free_factor(&factor_, &common_);
    factor_ = nullptr;
    split_.reset();
    upper_ = false;
    order_.clear();
    renumbered_ = RenumberedLower();
    factorized_ = false;
    flops_ = 0.0;
  }

  cholmod_common common_;
  cholmod_factor* factor_ = nullptr;
  // Elimination order (order_[k]: the unknown eliminated k-th) and the matrix renumbered in it,
  // when analyze() was given an ordering; empty for analyze_in_elimination_order().
  std::vector<int> order_;
  RenumberedLower renumbered_;
  std::unique_ptr<SubtreeParallelCholesky> split_;
  bool upper_ = false;  // The matrix stores its upper triangle (analyze_in_elimination_order).
  int size_ = 0;
  int border_size_ = 0;
  double flops_ = 0.0;
  bool factorized_ = false;
};

}  // namespace

std::unique_ptr<BorderedCholesky> make_bordered_cholesky() {
  return std::make_unique<CholmodBorderedCholesky>();
}
#else
std::unique_ptr<BorderedCholesky> make_bordered_cholesky() { return nullptr; }
#endif

}  // namespace harmonia::detail
