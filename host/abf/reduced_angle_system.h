#pragma once
// Internal: the weighted least-norm / saddle-point solve at the heart of both angle methods, with
// the triangle rows eliminated face by face (the algebraic step of ABF++), so that the system
// left has only the vertex and wheel rows (two per interior vertex) plus active boundary rows.
//
// Solves, for a diagonal W > 0 (one weight per corner) and a constraint Jacobian J whose rows are
// ordered as in angle_constraints.h:
//     [ W^-1  J^T ] [ dx     ]   [ r ]
//     [ J     0   ] [ lambda ] = [ s ]
// i.e. (J W J^T) lambda = J W r - s and dx = W (r - J^T lambda).
//   Linear ABF (3.9-3.13): W = alpha^2, r = 0, s = b: dx = e = W J^T (J W J^T)^-1 b.
//   An ABF Newton step (2.10) with a positive diagonal Hessian H: W = H^-1, r = -grad L, s = -h.
//
// The triangle rows of J touch disjoint corner triples, so J_T W J_T^T is diagonal and the Schur
// complement on the remaining rows R is J_R P J_R^T with P block diagonal per face:
// P_f = W_f - W_f 1 1^T W_f / (1^T W_f 1), a rank-2 PSD 3x3 block. P_f = Q_f Q_f^T with Q_f 3x2,
// so the reduced matrix is the plain normal product (J_R Q)(J_R Q)^T: a backend's
// normal_product with unit weights (the Vulkan B D B^T kernel), factorized by CHOLMOD on the CPU
// and solved by Jacobi-PCG on devices.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "abf/angle_constraints.h"
#include "backend/backend.h"

namespace harmonia::detail {

class SeparatorFirstOrdering;

class ReducedAngleSystem {
 public:
  // `backend` must outlive this object. `settings`: tolerances of the iterative path.
  ReducedAngleSystem(Backend& backend, const AngleTopology& topology,
                     const IterativeSettings& settings, const ProgressCallback& progress);
  ~ReducedAngleSystem();

  // Solves the system above. `jacobian`: all rows of angle_constraints.h (triangle rows first).
  // Pattern changes between calls (a different active boundary set) are detected and handled.
  // dx and lambda (all rows, triangle multipliers recovered too) are outputs.
  [[nodiscard]] SolveStats solve(const RowMajorSparse& jacobian, const Eigen::VectorXd& weights,
                                 const Eigen::VectorXd& r, const Eigen::VectorXd& s,
                                 Eigen::VectorXd& dx, Eigen::VectorXd& lambda);

  // The same in three steps, for callers that time them apart (linear ABF's phases):
  // assemble the reduced matrix (CPU) or B' and its normal product (devices) for `jacobian` and
  // `weights`; factorize it (CPU; nothing on devices); solve for r and s. `jacobian` must stay
  // alive and unchanged until solve_assembled returns.
  void assemble(const RowMajorSparse& jacobian, const Eigen::VectorXd& weights);
  // `meanwhile` (if any): the caller's own work, run once on this thread during the factorization
  // where a separator-first ordering leaves it waiting for the second half, else first.
  [[nodiscard]] SolveStats factorize(const std::function<void()>& meanwhile = {});
  [[nodiscard]] SolveStats solve_assembled(const Eigen::VectorXd& r, const Eigen::VectorXd& s,
                                           Eigen::VectorXd& dx, Eigen::VectorXd& lambda);

  // The assembled system for a caller that solves it elsewhere (linear_abf_batch.h places many as
  // the diagonal blocks of one matrix), after assemble(): the reduced matrix R P R^T (both
  // triangles; the pattern may hold explicit zeros); for r and s, its right-hand side
  // R y - s_R of the file comment, or zero where it is at the rounding level of the constraint
  // values (nu = 0 answers it to that precision, as solve_assembled does); and dx and lambda from
  // a solution nu, as solve_assembled finishes.
  [[nodiscard]] RowMajorSparse reduced_matrix() const;
  [[nodiscard]] Eigen::VectorXd reduced_right_hand_side(const Eigen::VectorXd& r,
                                                        const Eigen::VectorXd& s) const;
  void back_substitute(const Eigen::VectorXd& r, const Eigen::VectorXd& s,
                       const Eigen::VectorXd& nu, Eigen::VectorXd& dx,
                       Eigen::VectorXd& lambda) const;

  // A fill-reducing ordering of all the mesh's vertices (e.g. operator_pattern's, which the
  // caller computes anyway for the reconstruction) to order the reduced rows by, instead of an
  // AMD ordering of their own (CPU; the next analysis uses it). Empty: back to that.
  void use_vertex_ordering(std::vector<int> vertex_ordering);

  // The same ordering still being computed, top separator first (separator_first_ordering.h; it
  // must outlive the next factorize()): the first analysis factorizes the rows of side 0 while
  // side 1 is ordered (SparseSystemSolver::factorize_in_halves).
  void use_vertex_ordering(const SeparatorFirstOrdering& staged_ordering);

  // e.g. "cholmod-supernodal-llt (reduced, 2 per interior vertex)" or "pcg-jacobi (reduced)".
  [[nodiscard]] std::string solver_name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace harmonia::detail
