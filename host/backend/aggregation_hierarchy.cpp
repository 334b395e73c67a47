#include "backend/aggregation_hierarchy.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "harmonia/types.h"
#include "mesh/number_text.h"

namespace harmonia::detail {
namespace {

// Above this many rows a coarsest level that stopped coarsening is not inverted densely (its
// inverse would not fit): the cycle then ends with a Jacobi step there.
constexpr int dense_inverse_limit = 2500;

constexpr int no_aggregate = -1;
constexpr int unassigned = -2;

// The diagonal of a row-major matrix; throws naming the first row whose diagonal entry is not
// positive and finite (no Jacobi smoother, so no multilevel preconditioner, exists then).
Eigen::VectorXd positive_diagonal(const RowMajorSparse& a) {
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(a.rows());
  for (Eigen::Index i = 0; i < a.outerSize(); ++i)
    for (RowMajorSparse::InnerIterator it(a, i); it; ++it)
      if (it.col() == i) diagonal[i] += it.value();
  for (Eigen::Index i = 0; i < diagonal.size(); ++i)
    if (!(diagonal[i] > 0.0) || !std::isfinite(diagonal[i]))
      throw Error(Status::numerical_failure,
                  "multilevel preconditioner: diagonal entry " + number_text(diagonal[i]) +
                      " of row " + std::to_string(i) +
                      " is not positive (the matrix is not positive definite)");
  return diagonal;
}

// Gershgorin's bound on the spectral radius of D^-1 A: the largest row sum of |a_ij| / a_ii.
// An upper bound, so the damping 4 / (3 rho) derived from it never makes Jacobi diverge.
double jacobi_radius_bound(const RowMajorSparse& a, const Eigen::VectorXd& diagonal) {
  double radius = 0.0;
  for (Eigen::Index i = 0; i < a.outerSize(); ++i) {
    double row_sum = 0.0;
    for (RowMajorSparse::InnerIterator it(a, i); it; ++it) row_sum += std::abs(it.value());
    radius = std::max(radius, row_sum / diagonal[i]);
  }
  return radius;
}

// Plain aggregation (the scheme of AMGCL's plain_aggregates, itself after Vanek et al.): an
// unassigned row whose strong neighbours are all free becomes the seed of an aggregate made of
// itself and those neighbours; their own strong neighbours join it provisionally, and keep it
// unless a later aggregate takes them as direct neighbours. A row without strong neighbours gets
// no aggregate: the smoother alone handles it. Returns the aggregate of every row and sets
// `count`.
Eigen::VectorXi aggregate(const RowMajorSparse& a, const Eigen::VectorXd& diagonal,
                          double threshold, int& count) {
  const Eigen::Index n = a.rows();
  const double threshold_squared = threshold * threshold;
  const auto strong = [&](Eigen::Index i, const RowMajorSparse::InnerIterator& it) {
    return it.col() != i &&
           it.value() * it.value() > threshold_squared * diagonal[i] * diagonal[it.col()];
  };
  Eigen::VectorXi aggregate_of = Eigen::VectorXi::Constant(n, unassigned);
  for (Eigen::Index i = 0; i < n; ++i) {
    bool has_strong = false;
    for (RowMajorSparse::InnerIterator it(a, i); it && !has_strong; ++it) has_strong = strong(i, it);
    if (!has_strong) aggregate_of[i] = no_aggregate;
  }
  count = 0;
  std::vector<Eigen::Index> members;
  for (Eigen::Index seed = 0; seed < n; ++seed) {
    if (aggregate_of[seed] != unassigned) continue;
    const int id = count++;
    aggregate_of[seed] = id;
    members.clear();
    for (RowMajorSparse::InnerIterator it(a, seed); it; ++it) {
      if (!strong(seed, it) || aggregate_of[it.col()] == no_aggregate) continue;
      aggregate_of[it.col()] = id;
      members.push_back(it.col());
    }
    for (const Eigen::Index member : members)
      for (RowMajorSparse::InnerIterator it(a, member); it; ++it)
        if (strong(member, it) && aggregate_of[it.col()] == unassigned) aggregate_of[it.col()] = id;
  }
  // Aggregates whose every member was taken by a later one are dropped; the rest renumbered.
  std::vector<int> renumbered(static_cast<std::size_t>(count), -1);
  int kept = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const int id = aggregate_of[i];
    if (id < 0) continue;
    if (renumbered[id] < 0) renumbered[id] = kept++;
    aggregate_of[i] = renumbered[id];
  }
  count = kept;
  return aggregate_of;
}

Eigen::SparseMatrix<double> diagonal_matrix(const Eigen::VectorXd& values) {
  Eigen::SparseMatrix<double> d(values.size(), values.size());
  d.reserve(Eigen::VectorXi::Ones(values.size()));
  for (Eigen::Index i = 0; i < values.size(); ++i) d.insert(i, i) = values[i];
  d.makeCompressed();
  return d;
}

// The numeric part of a level: smoother, smoothed prolongation, restriction. Returns the next
// level's matrix P^T A P.
RowMajorSparse compute_level(const RowMajorSparse& a, AggregationLevel& level, int count) {
  level.matrix = a;
  const Eigen::VectorXd diagonal = positive_diagonal(a);
  const double damping = 4.0 / (3.0 * jacobi_radius_bound(a, diagonal));
  const Eigen::VectorXd damped_inverse = damping * diagonal.cwiseInverse();
  level.smoother = RowMajorSparse(diagonal_matrix(damped_inverse));

  // Tentative prolongation T: 1 in the column of each row's aggregate.
  Eigen::SparseMatrix<double, Eigen::RowMajor, int> tentative(a.rows(), count);
  tentative.reserve(Eigen::VectorXi::Ones(a.rows()));
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    if (level.aggregate_of[i] >= 0) tentative.insert(i, level.aggregate_of[i]) = 1.0;
  tentative.makeCompressed();

  // P = T - w D^-1 A T (one damped Jacobi step on each constant).
  const RowMajorSparse a_tentative = a * tentative;
  RowMajorSparse prolongation = tentative - RowMajorSparse(level.smoother * a_tentative);
  prolongation.prune(0.0);
  level.prolongation = prolongation;
  level.restriction = RowMajorSparse(prolongation.transpose());
  const RowMajorSparse galerkin = level.restriction * RowMajorSparse(a * level.prolongation);
  // Symmetric up to rounding; made exactly so for the dense Cholesky of the coarsest level.
  RowMajorSparse coarse = 0.5 * (galerkin + RowMajorSparse(galerkin.transpose()));
  coarse.makeCompressed();
  return coarse;
}

// The inverse of a small symmetric positive definite matrix as a dense-pattern sparse matrix
// (Cholesky; a semidefinite one falls back to the pseudo-inverse of its eigen-decomposition).
// Past dense_inverse_limit rows: the damped Jacobi inverse of the diagonal.
RowMajorSparse coarsest_inverse_of(const RowMajorSparse& a) {
  const Eigen::VectorXd diagonal = positive_diagonal(a);
  if (a.rows() > dense_inverse_limit) {
    const double damping = 4.0 / (3.0 * jacobi_radius_bound(a, diagonal));
    return RowMajorSparse(diagonal_matrix(damping * diagonal.cwiseInverse()));
  }
  const Eigen::MatrixXd dense = Eigen::MatrixXd(a);
  Eigen::MatrixXd inverse;
  const Eigen::LLT<Eigen::MatrixXd> cholesky(dense);
  if (cholesky.info() == Eigen::Success) {
    inverse = cholesky.solve(Eigen::MatrixXd::Identity(a.rows(), a.cols()));
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(dense);
    const Eigen::VectorXd values = eigen.eigenvalues();
    const double cutoff = values.cwiseAbs().maxCoeff() * 1e-12 * static_cast<double>(a.rows());
    Eigen::VectorXd inverted = Eigen::VectorXd::Zero(values.size());
    for (Eigen::Index k = 0; k < values.size(); ++k)
      if (values[k] > cutoff) inverted[k] = 1.0 / values[k];
    inverse = eigen.eigenvectors() * inverted.asDiagonal() * eigen.eigenvectors().transpose();
  }
  inverse = 0.5 * (inverse + inverse.transpose());
  RowMajorSparse stored(a.rows(), a.cols());
  stored.reserve(Eigen::VectorXi::Constant(a.rows(), static_cast<int>(a.cols())));
  for (Eigen::Index i = 0; i < a.rows(); ++i)
    for (Eigen::Index j = 0; j < a.cols(); ++j) stored.insert(i, j) = inverse(i, j);
  stored.makeCompressed();
  return stored;
}

}  // namespace

AggregationHierarchy::AggregationHierarchy(const Eigen::SparseMatrix<double>& matrix,
                                           const AggregationSettings& settings)
    : settings_(settings) {
  if (matrix.rows() != matrix.cols())
    throw Error(Status::invalid_input, "multilevel preconditioner: the matrix is not square");
  RowMajorSparse a(matrix);
  a.makeCompressed();
  pattern_rows_ = a.rows();
  pattern_nonzeros_ = a.nonZeros();
  pattern_outer_.assign(a.outerIndexPtr(), a.outerIndexPtr() + a.rows() + 1);
  pattern_inner_.assign(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros());
  while (a.rows() > settings_.coarsest_rows &&
         static_cast<int>(levels_.size()) + 1 < settings_.max_levels) {
    int count = 0;
    AggregationLevel level;
    level.aggregate_of = aggregate(a, positive_diagonal(a), settings_.strength_threshold, count);
    // A level that barely coarsens would only add cost: stop and treat this one as coarsest.
    if (count == 0 || count > (a.rows() * 9) / 10) break;
    RowMajorSparse next = compute_level(a, level, count);
    levels_.push_back(std::move(level));
    a = std::move(next);
  }
  coarsest_matrix_ = a;
  coarsest_inverse_ = coarsest_inverse_of(a);
}

bool AggregationHierarchy::refresh(const Eigen::SparseMatrix<double>& matrix) {
  RowMajorSparse a(matrix);
  a.makeCompressed();
  if (a.rows() != pattern_rows_ || a.cols() != pattern_rows_ || a.nonZeros() != pattern_nonzeros_ ||
      !std::equal(pattern_outer_.begin(), pattern_outer_.end(), a.outerIndexPtr()) ||
      !std::equal(pattern_inner_.begin(), pattern_inner_.end(), a.innerIndexPtr()))
    return false;
  std::vector<AggregationLevel> levels = levels_;
  for (AggregationLevel& level : levels) {
    const int count = level.aggregate_of.size() == 0 ? 0 : level.aggregate_of.maxCoeff() + 1;
    a = compute_level(a, level, count);
  }
  RowMajorSparse inverse = coarsest_inverse_of(a);
  levels_ = std::move(levels);
  coarsest_matrix_ = std::move(a);
  coarsest_inverse_ = std::move(inverse);
  return true;
}

std::vector<int> AggregationHierarchy::level_rows() const {
  std::vector<int> rows;
  for (const AggregationLevel& level : levels_) rows.push_back(static_cast<int>(level.matrix.rows()));
  rows.push_back(static_cast<int>(coarsest_matrix_.rows()));
  return rows;
}

double AggregationHierarchy::operator_complexity() const {
  const double finest = static_cast<double>(
      levels_.empty() ? coarsest_matrix_.nonZeros() : levels_.front().matrix.nonZeros());
  double total = static_cast<double>(coarsest_matrix_.nonZeros());
  for (const AggregationLevel& level : levels_) total += static_cast<double>(level.matrix.nonZeros());
  return finest > 0.0 ? total / finest : 1.0;
}

}  // namespace harmonia::detail
