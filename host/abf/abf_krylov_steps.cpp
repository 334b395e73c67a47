// The Krylov solvers of an ABF Newton step (thesis section 2.4): MINRES on the decoupled system,
// the modified Uzawa iteration, MINRES and CGNR on the full saddle-point matrix. All of them use
// only the Backend primitives, so the same code runs on the CPU and on devices.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/SparseCore>

#include "abf/abf_step_solvers.h"
#include "mesh/number_text.h"

namespace harmonia::detail {

bool same_pattern_or_record(const RowMajorSparse& matrix, std::vector<int>& outer,
                            std::vector<int>& inner) {
  const int* outer_begin = matrix.outerIndexPtr();
  const int* inner_begin = matrix.innerIndexPtr();
  const std::size_t outer_size = static_cast<std::size_t>(matrix.outerSize()) + 1;
  const std::size_t inner_size = static_cast<std::size_t>(matrix.nonZeros());
  const bool same = outer.size() == outer_size && inner.size() == inner_size &&
                    std::equal(outer.begin(), outer.end(), outer_begin) &&
                    std::equal(inner.begin(), inner.end(), inner_begin);
  if (!same) {
    outer.assign(outer_begin, outer_begin + outer_size);
    inner.assign(inner_begin, inner_begin + inner_size);
  }
  return same;
}

namespace {

Eigen::Map<const Eigen::VectorXd> csr_values(const RowMajorSparse& matrix) {
  return {matrix.valuePtr(), static_cast<Eigen::Index>(matrix.nonZeros())};
}

// A warm start of the right length, or zeros.
Eigen::VectorXd warm_start(const Eigen::VectorXd& guess, Eigen::Index size) {
  return guess.size() == size ? guess : Eigen::VectorXd::Zero(size);
}

// Keeps an uploaded matrix in step with a host matrix: uploads when the pattern changes,
// refreshes the values otherwise.
class UploadedMatrix {
 public:
  const DeviceMatrix& refresh(Backend& backend, const RowMajorSparse& matrix) {
    if (device_ && same_pattern_or_record(matrix, outer_, inner_)) {
      device_->update_values(csr_values(matrix));
    } else {
      same_pattern_or_record(matrix, outer_, inner_);
      device_ = backend.upload(matrix);
    }
    return *device_;
  }

 private:
  std::unique_ptr<DeviceMatrix> device_;
  std::vector<int> outer_, inner_;
};

RowMajorSparse diagonal_matrix(const Eigen::VectorXd& diagonal) {
  RowMajorSparse matrix(diagonal.size(), diagonal.size());
  matrix.reserve(Eigen::VectorXi::Ones(diagonal.size()));
  for (Eigen::Index i = 0; i < diagonal.size(); ++i) matrix.insert(i, i) = diagonal[i];
  matrix.makeCompressed();
  return matrix;
}

// ---------------------------------------------------------------------------------------------
// (a) The decoupled system (2.12-2.13): M lambda = J H^-1 r - s, M = J H^-1 J^T by MINRES.
// M is positive semidefinite for H > 0 and definite when J has full row rank (a disk mesh's
// triangle, vertex and wheel rows are independent); MINRES also copes with the semidefinite case.
class SchurMinresStep final : public AbfStepSolver {
 public:
  SchurMinresStep(Backend& backend, const IterativeSettings& settings,
                  const ProgressCallback& progress)
      : backend_(backend), settings_(settings), progress_(progress) {}

  SolveStats solve(const RowMajorSparse& jacobian, const Eigen::VectorXd& hessian,
                   const Eigen::VectorXd& r, const Eigen::VectorXd& s, Eigen::VectorXd& dx,
                   Eigen::VectorXd& lambda) override {
    const Eigen::VectorXd inverse_hessian = hessian.cwiseInverse();
    // M's values are refreshed every step (on the backend where it has a normal-product kernel);
    // a new active set changes its pattern and needs a new product.
    if (product_ && same_pattern_or_record(jacobian, outer_, inner_)) {
      product_->update(csr_values(jacobian), inverse_hessian);
    } else {
      same_pattern_or_record(jacobian, outer_, inner_);
      product_ = backend_.normal_product(jacobian, inverse_hessian);
    }
    const Eigen::VectorXd rhs = jacobian * inverse_hessian.cwiseProduct(r) - s;
    const auto device_rhs = backend_.upload(rhs);
    const auto device_lambda = backend_.upload(warm_start(lambda, jacobian.rows()));
    const SolveStats stats =
        backend_.minres(product_->matrix(), *device_rhs, *device_lambda, settings_, progress_);
    lambda = device_lambda->download().col(0);
    dx = inverse_hessian.cwiseProduct(r - jacobian.transpose() * lambda);
    return stats;
  }

  [[nodiscard]] std::string name() const override { return "schur-minres"; }

 private:
  Backend& backend_;
  IterativeSettings settings_;
  ProgressCallback progress_;
  std::unique_ptr<DeviceNormalProduct> product_;
  std::vector<int> outer_, inner_;
};

// ---------------------------------------------------------------------------------------------
// (b) The modified Uzawa algorithm with conjugate directions (section 2.4.2). With
// x(lambda) = H^-1 (r - J^T lambda), the residual of the Schur system M lambda = J H^-1 r - s is
// J x - s = -q, so conjugate gradients on it need only products with J^T (p = J^T d), H^-1
// (h = H^-1 p: a Jacobi step with the diagonal matrix H, which is exact) and J, and x is updated
// alongside lambda. The thesis' direction update has the sign of the recursion reversed; here
// the standard conjugate-gradient update is used, on e = -d to save negations:
//   e_0 = q_0,  p = J^T e,  h = H^-1 p,  alpha = <q,q> / <p,h>,
//   lambda -= alpha e,  x += alpha h,  q -= alpha J h,  e = q + (<q',q'> / <q,q>) e.
class UzawaStep final : public AbfStepSolver {
 public:
  UzawaStep(Backend& backend, const IterativeSettings& settings, const ProgressCallback& progress)
      : backend_(backend), settings_(settings), progress_(progress) {}

  SolveStats solve(const RowMajorSparse& jacobian, const Eigen::VectorXd& hessian,
                   const Eigen::VectorXd& r, const Eigen::VectorXd& s, Eigen::VectorXd& dx,
                   Eigen::VectorXd& lambda) override {
    const RowMajorSparse transpose = jacobian.transpose();
    const DeviceMatrix& j = jacobian_.refresh(backend_, jacobian);
    const DeviceMatrix& jt = transpose_.refresh(backend_, transpose);
    const DeviceMatrix& h_matrix = hessian_.refresh(backend_, diagonal_matrix(hessian));
    const Eigen::Index rows = jacobian.rows(), cols = jacobian.cols();
    const Eigen::VectorXd one = Eigen::VectorXd::Ones(1);

    const auto f = backend_.upload(r);
    const auto g = backend_.upload(s);
    const auto lam = backend_.upload(warm_start(lambda, rows));
    const auto x = backend_.allocate(static_cast<int>(cols), 1);
    const auto p = backend_.allocate(static_cast<int>(cols), 1);
    const auto h = backend_.allocate(static_cast<int>(cols), 1);
    const auto q = backend_.allocate(static_cast<int>(rows), 1);
    const auto e = backend_.allocate(static_cast<int>(rows), 1);
    const auto jh = backend_.allocate(static_cast<int>(rows), 1);

    // x = H^-1 (r - J^T lambda), q = s - J x.
    backend_.spmv(jt, *lam, *p);
    backend_.xpay(*f, -one, *p);  // p = r - J^T lambda
    backend_.jacobi(h_matrix, *p, *x);
    backend_.spmv(j, *x, *jh);
    backend_.copy(*g, *q);
    backend_.axpy(-one, *jh, *q);
    backend_.copy(*q, *e);

    // Relative to the Schur right-hand side J H^-1 r - s (the residual at lambda = 0).
    const double reference = (jacobian * r.cwiseQuotient(hessian) - s).norm();
    SolveStats stats;
    double q_squared = backend_.dot(*q, *q)[0];
    const double target = settings_.relative_tolerance * reference;
    while (std::sqrt(q_squared) > target) {
      if (stats.iterations >= settings_.max_iterations) {
        stats.status = Status::not_converged;
        stats.message = "uzawa stopped after " + std::to_string(stats.iterations) +
                        " iterations at relative residual " +
                        detail::scientific_text(std::sqrt(q_squared) / reference);
        break;
      }
      if (progress_ && stats.iterations % 64 == 0 &&
          !progress_(Progress{"uzawa", stats.iterations, settings_.max_iterations})) {
        stats.status = Status::cancelled;
        stats.message = "cancelled during uzawa";
        break;
      }
      backend_.spmv(jt, *e, *p);
      backend_.jacobi(h_matrix, *p, *h);
      const double curvature = backend_.dot(*p, *h)[0];
      if (!(curvature > 0.0) || !std::isfinite(curvature)) {
        stats.status = Status::numerical_failure;
        stats.message = "uzawa: the Schur complement is not positive definite";
        break;
      }
      const double alpha = q_squared / curvature;
      backend_.axpy(-alpha * one, *e, *lam);
      backend_.axpy(alpha * one, *h, *x);
      backend_.spmv(j, *h, *jh);
      backend_.axpy(-alpha * one, *jh, *q);
      const double next_q_squared = backend_.dot(*q, *q)[0];
      backend_.xpay(*q, (next_q_squared / q_squared) * one, *e);
      q_squared = next_q_squared;
      ++stats.iterations;
    }
    dx = x->download().col(0);
    lambda = lam->download().col(0);
    // The true residual of the Schur system (the recursion may drift).
    const double true_residual = (jacobian * dx - s).norm();
    stats.relative_residual = reference > 0.0 ? true_residual / reference : true_residual;
    return stats;
  }

  [[nodiscard]] std::string name() const override { return "uzawa-cg"; }

 private:
  Backend& backend_;
  IterativeSettings settings_;
  ProgressCallback progress_;
  UploadedMatrix jacobian_, transpose_, hessian_;
};

// ---------------------------------------------------------------------------------------------
// The full symmetric matrix S = [H J^T; J 0] of (2.10). Its pattern depends only on J's, so it is
// uploaded once per active set and refreshed every step.
RowMajorSparse saddle_point_matrix(const RowMajorSparse& jacobian,
                                   const Eigen::VectorXd& hessian) {
  const Eigen::Index cols = jacobian.cols(), rows = jacobian.rows();
  const RowMajorSparse transpose = jacobian.transpose();
  RowMajorSparse matrix(cols + rows, cols + rows);
  Eigen::VectorXi row_sizes(cols + rows);
  for (Eigen::Index i = 0; i < cols; ++i)
    row_sizes[i] = 1 + static_cast<int>(transpose.outerIndexPtr()[i + 1] -
                                        transpose.outerIndexPtr()[i]);
  for (Eigen::Index i = 0; i < rows; ++i)
    row_sizes[cols + i] =
        static_cast<int>(jacobian.outerIndexPtr()[i + 1] - jacobian.outerIndexPtr()[i]);
  matrix.reserve(row_sizes);
  for (Eigen::Index i = 0; i < cols; ++i) {
    matrix.insert(i, i) = hessian[i];
    for (RowMajorSparse::InnerIterator entry(transpose, i); entry; ++entry)
      matrix.insert(i, cols + entry.col()) = entry.value();
  }
  for (Eigen::Index i = 0; i < rows; ++i)
    for (RowMajorSparse::InnerIterator entry(jacobian, i); entry; ++entry)
      matrix.insert(cols + i, entry.col()) = entry.value();
  matrix.makeCompressed();
  return matrix;
}

class FullSystemStep : public AbfStepSolver {
 public:
  FullSystemStep(Backend& backend, const IterativeSettings& settings,
                 const ProgressCallback& progress)
      : backend_(backend), settings_(settings), progress_(progress) {}

  SolveStats solve(const RowMajorSparse& jacobian, const Eigen::VectorXd& hessian,
                   const Eigen::VectorXd& r, const Eigen::VectorXd& s, Eigen::VectorXd& dx,
                   Eigen::VectorXd& lambda) override {
    const Eigen::Index cols = jacobian.cols(), rows = jacobian.rows();
    const DeviceMatrix& matrix =
        saddle_point_.refresh(backend_, saddle_point_matrix(jacobian, hessian));
    Eigen::VectorXd rhs(cols + rows), start(cols + rows);
    rhs << r, s;
    start << Eigen::VectorXd::Zero(cols), warm_start(lambda, rows);
    const auto device_rhs = backend_.upload(rhs);
    const auto device_solution = backend_.upload(start);
    const SolveStats stats = solve_full(matrix, *device_rhs, *device_solution);
    const Eigen::VectorXd solution = device_solution->download().col(0);
    dx = solution.head(cols);
    lambda = solution.tail(rows);
    return stats;
  }

 protected:
  virtual SolveStats solve_full(const DeviceMatrix& matrix, const DeviceVectors& rhs,
                                DeviceVectors& solution) = 0;

  Backend& backend_;
  IterativeSettings settings_;
  ProgressCallback progress_;

 private:
  UploadedMatrix saddle_point_;
};

// (c) MINRES on S directly: S is symmetric and indefinite (H > 0 block, zero block).
class FullMinresStep final : public FullSystemStep {
 public:
  using FullSystemStep::FullSystemStep;
  [[nodiscard]] std::string name() const override { return "full-minres"; }

 protected:
  SolveStats solve_full(const DeviceMatrix& matrix, const DeviceVectors& rhs,
                        DeviceVectors& solution) override {
    return backend_.minres(matrix, rhs, solution, settings_, progress_);
  }
};

// (c) CGNR: conjugate gradients on S^T S z = S^T b with S^T = S, in the CGLS form that keeps
// the residual b - S z (whose norm it reduces monotonically) instead of forming S^2.
class FullCgnrStep final : public FullSystemStep {
 public:
  using FullSystemStep::FullSystemStep;
  [[nodiscard]] std::string name() const override { return "full-cgnr"; }

 protected:
  SolveStats solve_full(const DeviceMatrix& matrix, const DeviceVectors& rhs,
                        DeviceVectors& solution) override {
    const int size = rhs.rows();
    const Eigen::VectorXd one = Eigen::VectorXd::Ones(1);
    const auto residual = backend_.allocate(size, 1);  // b - S z
    const auto normal_residual = backend_.allocate(size, 1);  // S (b - S z)
    const auto direction = backend_.allocate(size, 1);
    const auto image = backend_.allocate(size, 1);  // S direction
    backend_.spmv(matrix, solution, *residual);
    backend_.xpay(rhs, -one, *residual);
    backend_.spmv(matrix, *residual, *normal_residual);
    backend_.copy(*normal_residual, *direction);
    const double rhs_norm = std::sqrt(backend_.dot(rhs, rhs)[0]);
    double gamma = backend_.dot(*normal_residual, *normal_residual)[0];
    double residual_norm = std::sqrt(backend_.dot(*residual, *residual)[0]);
    SolveStats stats;
    const double target = settings_.relative_tolerance * rhs_norm;
    while (residual_norm > target) {
      if (stats.iterations >= settings_.max_iterations) {
        stats.status = Status::not_converged;
        stats.message = "cgnr stopped after " + std::to_string(stats.iterations) +
                        " iterations at relative residual " +
                        detail::scientific_text(residual_norm / rhs_norm);
        break;
      }
      if (progress_ && stats.iterations % 64 == 0 &&
          !progress_(Progress{"cgnr", stats.iterations, settings_.max_iterations})) {
        stats.status = Status::cancelled;
        stats.message = "cancelled during cgnr";
        break;
      }
      backend_.spmv(matrix, *direction, *image);
      const double image_squared = backend_.dot(*image, *image)[0];
      if (!(image_squared > 0.0) || !std::isfinite(image_squared)) {
        stats.status = Status::numerical_failure;
        stats.message = "cgnr: breakdown (S d = 0)";
        break;
      }
      const double alpha = gamma / image_squared;
      backend_.axpy(alpha * one, *direction, solution);
      backend_.axpy(-alpha * one, *image, *residual);
      backend_.spmv(matrix, *residual, *normal_residual);
      const double next_gamma = backend_.dot(*normal_residual, *normal_residual)[0];
      backend_.xpay(*normal_residual, (next_gamma / gamma) * one, *direction);
      gamma = next_gamma;
      residual_norm = std::sqrt(backend_.dot(*residual, *residual)[0]);
      ++stats.iterations;
    }
    stats.relative_residual = rhs_norm > 0.0 ? residual_norm / rhs_norm : residual_norm;
    return stats;
  }
};

}  // namespace

std::unique_ptr<AbfStepSolver> make_schur_minres_step(Backend& backend,
                                                      const IterativeSettings& settings,
                                                      const ProgressCallback& progress) {
  return std::make_unique<SchurMinresStep>(backend, settings, progress);
}

std::unique_ptr<AbfStepSolver> make_uzawa_step(Backend& backend, const IterativeSettings& settings,
                                               const ProgressCallback& progress) {
  return std::make_unique<UzawaStep>(backend, settings, progress);
}

std::unique_ptr<AbfStepSolver> make_full_minres_step(Backend& backend,
                                                     const IterativeSettings& settings,
                                                     const ProgressCallback& progress) {
  return std::make_unique<FullMinresStep>(backend, settings, progress);
}

std::unique_ptr<AbfStepSolver> make_full_cgnr_step(Backend& backend,
                                                   const IterativeSettings& settings,
                                                   const ProgressCallback& progress) {
  return std::make_unique<FullCgnrStep>(backend, settings, progress);
}

}  // namespace harmonia::detail
