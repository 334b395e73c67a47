#pragma once
// Internal: a sparse Cholesky factorization on two threads, for an SPD matrix already numbered in
// a postordered nested-dissection elimination order (SparseSystemSolver::
// analyze_in_elimination_order).
//
// Why: CHOLMOD's supernodal factorization works through the supernodes one at a time and leaves
// parallelism to BLAS, but the supernodes of a mesh's system are mostly too small for OpenBLAS's
// threads: in the reduced angle system of the 827K-face mesh the second core spun idle through
// about 80 % of the factorization.
//
// How: the elimination tree of a nested-dissection order ends in the top separator S, a path of
// single-child nodes; the subtrees below it share no entry. Grouped into two halves H_0 and H_1
// (rows in that order, S last),
//     A = [ A_00   0     A_0S ]
//         [ 0      A_11  A_1S ]
//         [ A_S0   A_S1  A_SS ].
// Each bordered half B_i = [A_ii A_iS; A_Si A_SS] is factorized on its own thread with S last
// (bordered_cholesky.h): its rows above S are the full factor's own, and its border block R_i
// satisfies R_i R_i^T = A_SS - A_Si A_ii^-1 A_iS. The full factor's separator block L_S is then
// the Cholesky factor of the Schur complement
//     A_SS - A_S0 A_00^-1 A_0S - A_S1 A_11^-1 A_1S = R_0 R_0^T + R_1 R_1^T - A_SS,
// a dense matrix of the separator's size (1224 rows for the 827K-row system, 4 % of the work).
// A solve runs the halves' forward solves side by side, the separator's dense solve, then the
// halves' backward solves side by side.
//
// While the halves run, OpenBLAS is held to one thread per call (single_threaded_blas.h): two
// callers of its thread pool queue for it and spin. The split is therefore only made where that
// hold is possible (OpenBLAS) and allowed (the caller's BlasThreadPolicy, harmonia/blas_threads.h:
// the count is process-wide), and the machine has a second hardware thread.

#include <functional>
#include <future>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace harmonia::detail {

class SubtreeParallelCholesky {
 public:
  //! Below this many rows a factorization takes milliseconds and one thread does it.
  static constexpr int kDefaultMinimumRows = 20000;

  //! The two halves and the separator (rows), and the arithmetic of the halves' factorizations
  //! (flops; the dense separator adds about separator_rows^3).
  struct Shape {
    int half_rows[2] = {0, 0};
    int separator_rows = 0;
    double half_flops[2] = {0.0, 0.0};
  };

  //! Symbolic analysis of `lower` (its lower triangle is read) in the elimination order `order`
  //! (order[k]: the row eliminated k-th; a postordered fill-reducing order), or as it is numbered
  //! when `order` is empty. nullptr when the split does not pay: fewer than `minimum_rows` rows,
  //! one hardware thread, a BLAS other than OpenBLAS or a policy that leaves its thread count
  //! alone (harmonia/blas_threads.h), an order that is not a postorder of its
  //! elimination tree, a tree without two halves of at least a sixth of the rows each below its
  //! top path, or a separator whose dense work is not small next to the halves'. `border_rows`:
  //! the last rows of the order that a caller needs in the separator (a BorderedCholesky's
  //! border); no split when the top path is shorter.
  [[nodiscard]] static std::unique_ptr<SubtreeParallelCholesky> analyze(
      const Eigen::SparseMatrix<double>& lower, const std::vector<int>& order = {},
      int minimum_rows = kDefaultMinimumRows, int border_rows = 0);

  //! The split given ahead instead of found in the elimination tree: `separator` (rows of
  //! `lower`, any order) separates `first_half` from the rows of `second_half` (each a postordered
  //! elimination order of its half's rows), as the top separator of a separator-first nested
  //! dissection does (separator_first_ordering.h). Analyzes and factorizes half 0 on this thread
  //! while half 1's order may still be computed elsewhere, and half 1 on a second thread once it
  //! is ready; `meanwhile`, if any, runs on this thread after half 0 and after mapping in the
  //! pages of half 1's factor (page_prefault.h) (it is run in every case
  //! that gets that far, and not at all when nullptr is returned before). Returns the
  //! factorization, or nullptr under the conditions of analyze() (rows,
  //! threads, BLAS, the separator's work against a half's) and when an entry joins the halves,
  //! the rows are not a permutation, or a half is not positive definite.
  [[nodiscard]] static std::unique_ptr<SubtreeParallelCholesky> factorize_halves(
      const Eigen::SparseMatrix<double>& lower, const std::vector<int>& separator,
      const std::vector<int>& first_half, const std::shared_future<std::vector<int>>& second_half,
      const std::function<void()>& meanwhile = {}, int minimum_rows = kDefaultMinimumRows);

  ~SubtreeParallelCholesky();
  SubtreeParallelCholesky(const SubtreeParallelCholesky&) = delete;
  SubtreeParallelCholesky& operator=(const SubtreeParallelCholesky&) = delete;

  //! Numeric factorization A = L L^T of a matrix with the analyzed pattern; false when it is not
  //! positive definite.
  [[nodiscard]] bool factorize(const Eigen::SparseMatrix<double>& lower);
  //! A^-1 rhs (any number of columns, rows as the matrix's) with the last factorization; empty
  //! when a solve failed.
  [[nodiscard]] Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) const;
  //! y = L^-1 b and x = L^-T y, the two halves of solve(), rows in elimination order; empty when
  //! a solve failed.
  [[nodiscard]] Eigen::MatrixXd forward(const Eigen::MatrixXd& b) const;
  [[nodiscard]] Eigen::MatrixXd backward(const Eigen::MatrixXd& y) const;
  //! The last `rows` rows and columns of L (dense, lower triangular); `rows` at most the
  //! separator's.
  [[nodiscard]] Eigen::MatrixXd trailing_factor(int rows) const;

  [[nodiscard]] Shape shape() const;

 private:
  struct Impl;
  explicit SubtreeParallelCholesky(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace harmonia::detail
