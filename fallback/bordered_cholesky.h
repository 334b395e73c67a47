#pragma once
// Internal: a sparse Cholesky factorization A = P^T R R^T P whose last unknowns (the "border")
// are eliminated last, with the pieces a block elimination on that border needs: the forward and
// backward triangular solves apart, and the border's dense diagonal block R_BB of the factor.
//
// Why: with A = [A_II A_IB; A_BI A_BB] in elimination order, R_BB R_BB^T is the Schur complement
// A_BB - A_BI A_II^-1 A_IB, so a system that couples two copies of A only on the border (LSCM and
// the least-squares reconstruction from angles: [L N; N^T L], N on the boundary) can be solved with
// one factorization of A and a small dense system on the border (uv_system_solver.cpp).
//
// CHOLMOD's factor on the CPU, the matrix renumbered in its elimination order: as CHOLMOD chooses for a
// small matrix (kCholmodSimplicialBelowRows, direct_solvers.h), else supernodal (and split on two
// threads where that pays); unavailable (make_bordered_cholesky returns nullptr) in
// builds without CHOLMOD.

#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace harmonia::detail {

enum class StoredTriangle { lower, upper };

class BorderedCholesky {
 public:
  virtual ~BorderedCholesky() = default;

  //! Symbolic analysis of the symmetric `lower` (its lower triangle is read) in the elimination
  //! order `ordering` (ordering[k]: the unknown eliminated k-th), whose last `border_size`
  //! entries are the border. False when the analysis failed or could not keep the border last.
  [[nodiscard]] virtual bool analyze(const Eigen::SparseMatrix<double>& lower,
                                     const std::vector<int>& ordering, int border_size) = 0;
  //! The same for a matrix already numbered in elimination order (a postordered fill-reducing
  //! ordering whose last `border_size` rows are the border): factorized as it is stored, with no
  //! permutation of its own. `triangle`: the one stored, then and in factorize() (the upper one is
  //! read without CHOLMOD's transpose).
  [[nodiscard]] virtual bool analyze_in_elimination_order(const Eigen::SparseMatrix<double>& matrix,
                                                          int border_size,
                                                          StoredTriangle triangle) = 0;
  //! Floating-point operations of the numeric factorization (after analyze).
  [[nodiscard]] virtual double factorization_flops() const = 0;
  //! Numeric factorization of a matrix with the analyzed pattern (and triangle); false when it is
  //! not positive definite.
  [[nodiscard]] virtual bool factorize(const Eigen::SparseMatrix<double>& matrix) = 0;
  //! y = R^-1 P b: rows of y in elimination order (the border's last).
  [[nodiscard]] virtual Eigen::MatrixXd forward(const Eigen::MatrixXd& b) const = 0;
  //! x = P^T R^-T y: the inverse of forward() composed with R^T, rows of x in the original order.
  [[nodiscard]] virtual Eigen::MatrixXd backward(const Eigen::MatrixXd& y) const = 0;
  //! The numeric factor's storage, allocated now where factorize() has not run yet (contents
  //! undefined until it does), for another thread to map in while this one factorizes
  //! (page_prefault.h): pointer and bytes; {nullptr, 0} where there is none to share (a split
  //! factorization, no analysis).
  [[nodiscard]] virtual std::pair<void*, std::size_t> allocate_factor_storage() = 0;
  //! Whether the factorization and solves run on two threads (subtree_parallel_cholesky.h).
  [[nodiscard]] virtual bool on_two_threads() const = 0;
  //! The factorization's name: "cholmod-simplicial-llt" or "cholmod-supernodal-llt".
  [[nodiscard]] virtual const char* name() const = 0;
  //! R_BB, the border's block of the factor (dense, lower triangular, border_size square), rows
  //! and columns in elimination order.
  [[nodiscard]] virtual Eigen::MatrixXd border_factor() const = 0;
};

//! CHOLMOD's supernodal LL^T; nullptr without CHOLMOD.
[[nodiscard]] std::unique_ptr<BorderedCholesky> make_bordered_cholesky();

}  // namespace harmonia::detail
