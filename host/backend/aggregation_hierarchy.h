#pragma once
// Internal: the levels of smoothed-aggregation algebraic multigrid (Vanek, Mandel and Brezina,
// "Algebraic multigrid by smoothed aggregation", 1996), built on the host in double.
//
// Each level groups the unknowns of the one above into aggregates of strongly coupled rows; the
// tentative prolongation puts a constant on each aggregate (the near-kernel of a Laplacian), one
// damped-Jacobi step smooths it (P = (I - w D^-1 A) T), and the next level's matrix is the
// Galerkin product P^T A P. The coarsest level is small enough to invert densely. Everything a
// V-cycle needs is kept as sparse matrices, so that any backend applies it with its SpMV alone
// (host/backend/multilevel_preconditioner.h).

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "backend/backend.h"

namespace harmonia::detail {

struct AggregationSettings {
  // a_ij couples rows i and j strongly when a_ij^2 > threshold^2 |a_ii a_jj|. AMGCL's and
  // PyAMG's defaults lie at 0.08 and 0 (every connection): small values aggregate the
  // anisotropic meshes of long limbs along their short edges too, which keeps the coarse
  // levels' shape close to the fine one.
  double strength_threshold = 0.08;
  // Coarsening stops at this many rows; the last level is inverted densely (its inverse is
  // applied as a dense matrix: 500 rows are 250,000 entries).
  int coarsest_rows = 200;
  int max_levels = 25;
};

// One level above the coarsest: its matrix and what leads to the next level.
struct AggregationLevel {
  RowMajorSparse matrix;         // A_l, symmetric positive definite.
  RowMajorSparse smoother;       // w_l D_l^-1, the damped Jacobi smoother (diagonal).
  RowMajorSparse prolongation;   // P_l: rows(A_l) x rows(A_{l+1}).
  RowMajorSparse restriction;    // P_l^T.
  Eigen::VectorXi aggregate_of;  // The aggregate (row of the next level) of each row; -1: none.
};

class AggregationHierarchy {
 public:
  // Aggregates `matrix` (symmetric positive definite, square) level by level and computes every
  // level's numeric part. Throws harmonia::Error(numerical_failure) when a diagonal entry is not
  // positive and finite.
  AggregationHierarchy(const Eigen::SparseMatrix<double>& matrix,
                       const AggregationSettings& settings = {});

  // New values in the same pattern: keeps the aggregates and recomputes the smoothers,
  // prolongations, Galerkin products and the coarsest inverse. Returns false (and changes
  // nothing) when the pattern differs from the one aggregated; then build a new hierarchy.
  [[nodiscard]] bool refresh(const Eigen::SparseMatrix<double>& matrix);

  [[nodiscard]] const std::vector<AggregationLevel>& levels() const { return levels_; }
  // The inverse of the coarsest level's matrix, stored dense (every entry) in a sparse matrix.
  [[nodiscard]] const RowMajorSparse& coarsest_inverse() const { return coarsest_inverse_; }
  [[nodiscard]] int coarsest_rows() const { return static_cast<int>(coarsest_inverse_.rows()); }
  // Rows of every level (the finest first, the coarsest last).
  [[nodiscard]] std::vector<int> level_rows() const;
  // Stored entries of every level's matrix over the finest's (the memory a V-cycle touches).
  [[nodiscard]] double operator_complexity() const;

 private:
  void compute_numeric(const Eigen::SparseMatrix<double>& matrix);

  AggregationSettings settings_;
  Eigen::Index pattern_rows_ = 0, pattern_nonzeros_ = 0;
  std::vector<int> pattern_outer_, pattern_inner_;
  std::vector<AggregationLevel> levels_;
  RowMajorSparse coarsest_matrix_;
  RowMajorSparse coarsest_inverse_;
};

}  // namespace harmonia::detail
