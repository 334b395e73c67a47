#pragma once
// Spectral bounds of symmetric positive definite systems, so that a test's tolerance can be
// derived from the problem it solves (machine epsilon times the system's conditioning) instead
// of from the value one machine printed.

#include <algorithm>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace harmonia::testing {

//! The extreme eigenvalues of a symmetric positive definite matrix.
struct SpdSpectrum {
  //! The largest absolute row sum: an upper bound of the largest eigenvalue (Gershgorin).
  double largest = 0.0;
  //! The smallest eigenvalue, estimated by inverse iteration: the Rayleigh quotient of the last
  //! iterate, once two successive quotients agree to 1e-6 (at most 300 iterations). Inverse
  //! iteration approaches the smallest eigenvalue from above, so a bound built on it takes a
  //! margin (SpdSpectrum::kEstimateMargin).
  double smallest = 0.0;
  //! The factor a bound divided by `smallest` is multiplied by, for the estimate's slack.
  static constexpr double kEstimateMargin = 2.0;
  [[nodiscard]] double condition() const { return largest / smallest; }
};

//! The spectrum of `matrix` (symmetric positive definite; both triangles stored). Throws
//! std::runtime_error when it cannot be factorized (not positive definite).
[[nodiscard]] SpdSpectrum spd_spectrum(const Eigen::SparseMatrix<double>& matrix);

//! `matrix` without the rows and columns listed in `removed` (e.g. pinned unknowns).
[[nodiscard]] Eigen::SparseMatrix<double> without_rows_and_columns(
    const Eigen::SparseMatrix<double>& matrix, const std::vector<int>& removed);

//! `vector` without the entries listed in `removed`.
[[nodiscard]] Eigen::VectorXd without_entries(const Eigen::VectorXd& vector,
                                              const std::vector<int>& removed);

//! An upper bound of the rounding error of the product matrix * x computed in double: each entry
//! sums at most k products (k: the most entries of a row), so its error is at most
//! k eps (|matrix| |x|) entrywise (Higham, Accuracy and Stability, 3.5); returned as a 2-norm.
[[nodiscard]] double product_rounding_bound(const Eigen::SparseMatrix<double>& matrix,
                                            const Eigen::VectorXd& x);

//! How far rounding can move a relative residual |b - A x| / |b| computed in double (the largest
//! over the columns): the product A x rounds by at most k eps (|A| |x|) entrywise (k: the most
//! entries of a row) and the subtraction by eps |b - A x|, so a column's computed value lies
//! within (k + 1) eps |(|A| |x| + |b|)| / |b| of the exact one. Twice that: two computations of the
//! same residual in different orders (a solver's and a test's) may differ by this much.
template <typename Sparse>
[[nodiscard]] double residual_rounding(const Sparse& a, const Eigen::MatrixXd& x,
                                       const Eigen::MatrixXd& rhs) {
  const Sparse magnitude = a.cwiseAbs();
  int most_entries = 1;
  for (Eigen::Index outer = 0; outer < a.outerSize(); ++outer)
    most_entries = std::max(most_entries, static_cast<int>(a.innerVector(outer).nonZeros()));
  double worst = 0.0;
  for (Eigen::Index c = 0; c < rhs.cols(); ++c) {
    const Eigen::VectorXd bound = magnitude * x.col(c).cwiseAbs() + rhs.col(c).cwiseAbs();
    const double norm = rhs.col(c).norm();
    if (norm > 0.0) worst = std::max(worst, bound.norm() / norm);
  }
  return 2.0 * (most_entries + 1) * std::numeric_limits<double>::epsilon() * worst;
}

}  // namespace harmonia::testing
