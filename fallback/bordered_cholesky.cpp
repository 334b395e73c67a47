#include "fallback/bordered_cholesky.h"

#include "fallback/cholmod_view.h"
#include "fallback/dynamic_openmp_teams.h"

namespace harmonia::detail {

#ifdef HARMONIA_HAVE_CHOLMOD
namespace {

class CholmodBorderedCholesky final : public BorderedCholesky {
 public:
  CholmodBorderedCholesky() {
    cholmod_start(&common_);
    common_.supernodal = CHOLMOD_SUPERNODAL;
    common_.print = 0;
    common_.nmethods = 1;
    common_.method[0].ordering = CHOLMOD_GIVEN;
  }
  ~CholmodBorderedCholesky() override {
    release();
    cholmod_finish(&common_);
  }
  CholmodBorderedCholesky(const CholmodBorderedCholesky&) = delete;
  CholmodBorderedCholesky& operator=(const CholmodBorderedCholesky&) = delete;

  bool analyze(const Eigen::SparseMatrix<double>& lower, const std::vector<int>& ordering,
               int border_size) override {
    release();
    const auto size = static_cast<int>(lower.rows());
    if (static_cast<int>(ordering.size()) != size || border_size < 0 || border_size > size)
      return false;
    border_size_ = border_size;
    std::vector<char> in_border(static_cast<std::size_t>(size), 0);
    for (int k = size - border_size; k < size; ++k)
      in_border[static_cast<std::size_t>(ordering[static_cast<std::size_t>(k)])] = 1;
    cholmod_sparse view = lower_triangle_view(lower);
    // CHOLMOD postorders the elimination tree after the given ordering. The border columns form
    // the top of the tree when its Schur complement is connected, and then stay last; otherwise
    // the postorder may interleave them with others, and the ordering is taken as it is.
    for (const int postorder : {1, 0}) {
      common_.postorder = postorder;
      factor_ = cholmod_analyze_p(&view, const_cast<int*>(ordering.data()), nullptr, 0, &common_);
      if (factor_ == nullptr || !factor_->is_super) break;
      const int* permutation = static_cast<const int*>(factor_->Perm);
      bool border_last = true;
      for (int k = size - border_size; k < size && border_last; ++k)
        border_last = in_border[static_cast<std::size_t>(permutation[k])] != 0;
      if (border_last) {
        flops_ = common_.fl;
        return true;
      }
      release();
    }
    release();
    return false;
  }

  bool analyze_in_elimination_order(const Eigen::SparseMatrix<double>& lower,
                                    int border_size) override {
    release();
    const auto size = static_cast<int>(lower.rows());
    if (border_size < 0 || border_size > size) return false;
    border_size_ = border_size;
    cholmod_sparse view = lower_triangle_view(lower);
    // The natural ordering, not postordered: the border stays last by construction.
    const int saved_ordering = common_.method[0].ordering, saved_postorder = common_.postorder;
    common_.method[0].ordering = CHOLMOD_NATURAL;
    common_.postorder = 0;
    factor_ = cholmod_analyze(&view, &common_);
    common_.method[0].ordering = saved_ordering;
    common_.postorder = saved_postorder;
    if (factor_ == nullptr || !factor_->is_super) {
      release();
      return false;
    }
    flops_ = common_.fl;
    return true;
  }

  [[nodiscard]] double factorization_flops() const override { return flops_; }

  bool factorize(const Eigen::SparseMatrix<double>& lower) override {
    factorized_ = false;
    if (factor_ == nullptr) return false;
    cholmod_sparse view = lower_triangle_view(lower);
    const DynamicOpenMpTeams teams;
    factorized_ = cholmod_factorize(&view, factor_, &common_) != 0 && factor_->minor == factor_->n;
    return factorized_;
  }

  [[nodiscard]] Eigen::MatrixXd forward(const Eigen::MatrixXd& b) const override {
    return solve_steps(b, CHOLMOD_P, CHOLMOD_L);
  }

  [[nodiscard]] Eigen::MatrixXd backward(const Eigen::MatrixXd& y) const override {
    return solve_steps(y, CHOLMOD_Lt, CHOLMOD_Pt);
  }

  // Column j of the supernodal factor lives in the supernode s with super[s] <= j < super[s+1],
  // stored column-major as nsrow x nscol values with the row indices s[pi[s]..pi[s+1]).
  [[nodiscard]] Eigen::MatrixXd border_factor() const override {
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(border_size_, border_size_);
    if (!factorized_ || border_size_ == 0) return block;
    const auto size = static_cast<int>(factor_->n);
    const int first = size - border_size_;
    const int* super = static_cast<const int*>(factor_->super);
    const int* row_start = static_cast<const int*>(factor_->pi);
    const int* value_start = static_cast<const int*>(factor_->px);
    const int* rows = static_cast<const int*>(factor_->s);
    const double* values = static_cast<const double*>(factor_->x);
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
  // Two of CHOLMOD's solve systems in a row (CHOLMOD_P then CHOLMOD_L, or CHOLMOD_Lt then
  // CHOLMOD_Pt), each on the previous one's result.
  Eigen::MatrixXd solve_steps(const Eigen::MatrixXd& rhs, int first_system,
                              int second_system) const {
    auto& common = const_cast<cholmod_common&>(common_);
    cholmod_dense view = dense_view(rhs);
    cholmod_dense* middle = cholmod_solve(first_system, factor_, &view, &common);
    cholmod_dense* result =
        middle != nullptr ? cholmod_solve(second_system, factor_, middle, &common) : nullptr;
    Eigen::MatrixXd solution;
    if (result != nullptr)
      solution = Eigen::Map<const Eigen::MatrixXd>(static_cast<const double*>(result->x),
                                                   rhs.rows(), rhs.cols());
    cholmod_free_dense(&middle, &common);
    cholmod_free_dense(&result, &common);
    return solution;
  }

  void release() {
    if (factor_ != nullptr) cholmod_free_factor(&factor_, &common_);
    factor_ = nullptr;
    factorized_ = false;
    flops_ = 0.0;
  }

  cholmod_common common_;
  cholmod_factor* factor_ = nullptr;
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
