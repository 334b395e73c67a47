// The Krylov solvers every backend gets for free: preconditioned conjugate gradients (SPD
// systems; Jacobi, or a preconditioner the backend made) and MINRES (symmetric, possibly
// indefinite systems), written once on the coarse primitives of Backend. Every column of the block is an independent system; a column that has
// converged is frozen by giving it a zero step length, so one dispatch still serves all columns.

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>

#include "backend/backend.h"
#include "mesh/number_text.h"

namespace harmonia::detail {
namespace {

// a / b, or 0 where b is 0 (or where the column is frozen): keeps frozen columns free of NaN.
double safe_divide(double a, double b) { return b != 0.0 ? a / b : 0.0; }

Eigen::VectorXd column_norms(Backend& backend, const DeviceVectors& x) {
  return backend.dot(x, x).cwiseMax(0.0).cwiseSqrt();
}

// r = b - A x, returns the largest relative residual over the columns (columns with b = 0 use
// the absolute residual).
double true_residual(Backend& backend, const DeviceMatrix& a, const DeviceVectors& b,
                     const DeviceVectors& x, DeviceVectors& r, const Eigen::VectorXd& b_norms) {
  backend.spmv(a, x, r);
  backend.xpay(b, -1.0 * Eigen::VectorXd::Ones(b.cols()), r);  // r = b - A x
  const Eigen::VectorXd r_norms = column_norms(backend, r);
  double worst = 0.0;
  for (Eigen::Index c = 0; c < r_norms.size(); ++c) {
    const double relative = b_norms[c] > 0.0 ? r_norms[c] / b_norms[c] : r_norms[c];
    worst = std::max(worst,
                     std::isfinite(relative) ? relative : std::numeric_limits<double>::infinity());
  }
  return worst;
}

// Calls the progress callback every `check_every` iterations; false means cancel.
bool keep_going(const ProgressCallback& progress, std::string_view stage, int iteration, int cap,
                int check_every) {
  if (!progress || iteration % std::max(1, check_every) != 0) return true;
  return progress(Progress{stage, iteration, cap});
}

// Sets to zero the columns of x whose right-hand side is zero (their solution is exactly zero).
void zero_columns_with_zero_rhs(Backend& backend, const Eigen::VectorXd& b_norms,
                                DeviceVectors& x) {
  if ((b_norms.array() > 0.0).all()) return;
  const auto zeros = backend.allocate(x.rows(), x.cols());
  const Eigen::VectorXd keep = (b_norms.array() > 0.0).cast<double>();
  backend.xpay(*zeros, keep, x);  // x = 0 + keep .* x
}

// z = M r: the preconditioner step of the conjugate gradients below.
using PreconditionerStep = std::function<void(const DeviceVectors& r, DeviceVectors& z)>;

// Preconditioned CG. Restarts from the current iterate when the recursive residual claims
// convergence but the true residual (recomputed) does not, which guards against drift.
SolveStats conjugate_gradients(Backend& backend, const DeviceMatrix& a,
                               const PreconditionerStep& precondition, const DeviceVectors& b,
                               DeviceVectors& x, const IterativeSettings& settings,
                               const ProgressCallback& progress) {
  SolveStats stats;
  const int cols = b.cols(), rows = b.rows();
  const Eigen::VectorXd b_norms = column_norms(backend, b);
  zero_columns_with_zero_rhs(backend, b_norms, x);

  auto r = backend.allocate(rows, cols), z = backend.allocate(rows, cols);
  auto p = backend.allocate(rows, cols), q = backend.allocate(rows, cols);
  stats.relative_residual = true_residual(backend, a, b, x, *r, b_norms);
  const double tolerance = settings.relative_tolerance;

  while (stats.relative_residual > tolerance && stats.iterations < settings.max_iterations) {
    // (Re)start: r holds b - A x.
    precondition(*r, *z);
    backend.copy(*z, *p);
    Eigen::VectorXd rz = backend.dot(*r, *z);
    Eigen::VectorXd r_norms = column_norms(backend, *r);
    const auto active = [&](Eigen::Index c) {
      return b_norms[c] > 0.0 && r_norms[c] > tolerance * b_norms[c];
    };
    bool any_active = true;
    while (any_active && stats.iterations < settings.max_iterations) {
      backend.spmv(a, *p, *q);
      const Eigen::VectorXd pq = backend.dot(*p, *q);
      Eigen::VectorXd alpha = Eigen::VectorXd::Zero(cols);
      for (Eigen::Index c = 0; c < cols; ++c) {
        if (!active(c)) continue;
        if (!(pq[c] > 0.0) || !std::isfinite(pq[c])) {
          stats.status = Status::numerical_failure;
          stats.message =
              "pcg: the matrix is not positive definite (p^T A p = " + detail::number_text(pq[c]) +
              " in column " + std::to_string(c) + ")";
          return stats;
        }
        alpha[c] = rz[c] / pq[c];
      }
      backend.axpy(alpha, *p, x);
      backend.axpy(-alpha, *q, *r);
      ++stats.iterations;
      r_norms = column_norms(backend, *r);
      any_active = false;
      for (Eigen::Index c = 0; c < cols; ++c) any_active = any_active || active(c);
      if (!keep_going(progress, "pcg", stats.iterations, settings.max_iterations,
                      settings.check_every)) {
        stats.status = Status::cancelled;
        stats.message = "cancelled during pcg";
        return stats;
      }
      if (!any_active) break;
      precondition(*r, *z);
      const Eigen::VectorXd rz_next = backend.dot(*r, *z);
      Eigen::VectorXd beta(cols);
      for (Eigen::Index c = 0; c < cols; ++c)
        beta[c] = active(c) ? safe_divide(rz_next[c], rz[c]) : 0.0;
      backend.xpay(*z, beta, *p);  // p = z + beta p
      rz = rz_next;
    }
    const double previous = stats.relative_residual;
    stats.relative_residual = true_residual(backend, a, b, x, *r, b_norms);
    if (!std::isfinite(stats.relative_residual)) break;
    // A restart that gains nothing means the attainable accuracy is reached.
    if (stats.relative_residual > tolerance && stats.relative_residual >= 0.5 * previous &&
        !any_active)
      break;
  }
  if (!std::isfinite(stats.relative_residual)) {
    stats.status = Status::numerical_failure;
    stats.message = "pcg: the residual is not finite";
  } else if (stats.relative_residual > tolerance) {
    stats.status = Status::not_converged;
    stats.message = "pcg stopped after " + std::to_string(stats.iterations) +
                    " iterations at relative residual " + detail::scientific_text(stats.relative_residual) +
                    " (tolerance " + detail::scientific_text(tolerance) + ")";
  }
  return stats;
}

}  // namespace

SolveStats Backend::pcg(const DeviceMatrix& a, const DeviceVectors& b, DeviceVectors& x,
                        const IterativeSettings& settings, const ProgressCallback& progress) {
  return conjugate_gradients(
      *this, a, [&](const DeviceVectors& r, DeviceVectors& z) { jacobi(a, r, z); }, b, x, settings,
      progress);
}

SolveStats Backend::preconditioned_pcg(const DeviceMatrix& a, Preconditioner& preconditioner,
                                       const DeviceVectors& b, DeviceVectors& x,
                                       const IterativeSettings& settings,
                                       const ProgressCallback& progress) {
  return conjugate_gradients(
      *this, a, [&](const DeviceVectors& r, DeviceVectors& z) { preconditioner.apply(r, z); }, b,
      x, settings, progress);
}

// MINRES after Paige and Saunders (1975): Lanczos tridiagonalization of A on the Krylov space of
// the initial residual, with the tridiagonal least-squares problem solved by Givens rotations as
// it grows. Unpreconditioned (a Jacobi preconditioner must be SPD, which a diagonal of an
// indefinite matrix need not be). |phibar| is the residual norm of the current iterate.
SolveStats Backend::minres(const DeviceMatrix& a, const DeviceVectors& b, DeviceVectors& x,
                           const IterativeSettings& settings, const ProgressCallback& progress) {
  SolveStats stats;
  const int cols = b.cols(), rows = b.rows();
  const Eigen::VectorXd b_norms = column_norms(*this, b);
  zero_columns_with_zero_rhs(*this, b_norms, x);
  const double tolerance = settings.relative_tolerance;
  const auto zeros = allocate(rows, cols);
  auto r1 = allocate(rows, cols), r2 = allocate(rows, cols), y = allocate(rows, cols);
  auto v = allocate(rows, cols), w = allocate(rows, cols), w1 = allocate(rows, cols);
  auto w2 = allocate(rows, cols);

  stats.relative_residual = true_residual(*this, a, b, x, *r2, b_norms);
  while (stats.relative_residual > tolerance && stats.iterations < settings.max_iterations) {
    // (Re)start from r2 = b - A x.
    copy(*r2, *r1);
    copy(*zeros, *w);
    copy(*zeros, *w2);
    Eigen::VectorXd beta = column_norms(*this, *r2);
    Eigen::VectorXd old_beta = Eigen::VectorXd::Zero(cols), dbar = Eigen::VectorXd::Zero(cols);
    Eigen::VectorXd epsilon = Eigen::VectorXd::Zero(cols), phibar = beta;
    Eigen::VectorXd cs = -Eigen::VectorXd::Ones(cols), sn = Eigen::VectorXd::Zero(cols);
    Eigen::VectorXi active(cols);
    for (int c = 0; c < cols; ++c) active[c] = b_norms[c] > 0.0 && beta[c] > tolerance * b_norms[c];
    int lanczos_step = 0;
    while (active.any() && stats.iterations < settings.max_iterations) {
      Eigen::VectorXd scale(cols);
      for (int c = 0; c < cols; ++c) scale[c] = active[c] ? safe_divide(1.0, beta[c]) : 0.0;
      copy(*r2, *v);
      xpay(*zeros, scale, *v);  // v = r2 / beta
      spmv(a, *v, *y);
      if (lanczos_step > 0) {
        Eigen::VectorXd coefficient(cols);
        for (int c = 0; c < cols; ++c) coefficient[c] = -safe_divide(beta[c], old_beta[c]);
        axpy(coefficient, *r1, *y);
      }
      const Eigen::VectorXd alpha = dot(*v, *y);
      Eigen::VectorXd coefficient(cols);
      for (int c = 0; c < cols; ++c) coefficient[c] = -safe_divide(alpha[c], beta[c]);
      axpy(coefficient, *r2, *y);
      std::swap(r1, r2);  // r1 = old r2
      std::swap(r2, y);   // r2 = new Lanczos residual; y is scratch again
      old_beta = beta;
      beta = column_norms(*this, *r2);
      ++lanczos_step;

      Eigen::VectorXd delta(cols), gamma(cols), phi(cols), denominator(cols), old_epsilon = epsilon;
      for (int c = 0; c < cols; ++c) {
        delta[c] = cs[c] * dbar[c] + sn[c] * alpha[c];
        const double gbar = sn[c] * dbar[c] - cs[c] * alpha[c];
        epsilon[c] = sn[c] * beta[c];
        dbar[c] = -cs[c] * beta[c];
        gamma[c] = std::max(std::hypot(gbar, beta[c]), std::numeric_limits<double>::min());
        cs[c] = gbar / gamma[c];
        sn[c] = beta[c] / gamma[c];
        phi[c] = active[c] ? cs[c] * phibar[c] : 0.0;
        phibar[c] = sn[c] * phibar[c];
        denominator[c] = active[c] ? 1.0 / gamma[c] : 0.0;
      }
      // w_new = (v - old_epsilon w1 - delta w2) / gamma, rotating the three direction buffers.
      std::swap(w1, w2);  // w1 = old w2
      std::swap(w2, w);   // w2 = old w; w holds old w1 and is overwritten now
      copy(*v, *w);
      axpy(-old_epsilon, *w1, *w);
      axpy(-delta, *w2, *w);
      xpay(*zeros, denominator, *w);
      axpy(phi, *w, x);
      ++stats.iterations;
      for (int c = 0; c < cols; ++c) {
        if (active[c] && (std::abs(phibar[c]) <= tolerance * b_norms[c] || !(beta[c] > 0.0)))
          active[c] = 0;
      }
      if (!keep_going(progress, "minres", stats.iterations, settings.max_iterations,
                      settings.check_every)) {
        stats.status = Status::cancelled;
        stats.message = "cancelled during minres";
        return stats;
      }
    }
    const double previous = stats.relative_residual;
    stats.relative_residual = true_residual(*this, a, b, x, *r2, b_norms);
    if (!std::isfinite(stats.relative_residual)) break;
    if (stats.relative_residual > tolerance && stats.relative_residual >= 0.5 * previous &&
        !active.any())
      break;
  }
  if (!std::isfinite(stats.relative_residual)) {
    stats.status = Status::numerical_failure;
    stats.message = "minres: the residual is not finite";
  } else if (stats.relative_residual > tolerance) {
    stats.status = Status::not_converged;
    stats.message = "minres stopped after " + std::to_string(stats.iterations) +
                    " iterations at relative residual " + detail::scientific_text(stats.relative_residual) +
                    " (tolerance " + detail::scientific_text(tolerance) + ")";
  }
  return stats;
}

}  // namespace harmonia::detail
