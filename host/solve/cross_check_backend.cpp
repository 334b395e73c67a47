// CrossCheckBackend: every operation on the primary backend and on a CPU twin, compared.

#include "solve/cross_check_backend.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <utility>

#include "fallback/cpu_backend.h"

namespace harmonia::detail {
namespace {

// A difference measured against a scale; 0/0 is agreement, x/0 total disagreement.
double relative(double difference, double scale) {
  if (difference == 0.0) return 0.0;
  if (!(scale > 0.0)) return std::numeric_limits<double>::infinity();
  return difference / scale;
}

// A matrix on both backends, with its values in double on the host (for the spmv scale |A||x|).
class CheckedMatrix final : public DeviceMatrix {
 public:
  CheckedMatrix(std::unique_ptr<DeviceMatrix> primary, std::unique_ptr<DeviceMatrix> twin,
                RowMajorSparse host)
      : owned_primary_(std::move(primary)),
        owned_twin_(std::move(twin)),
        primary_(owned_primary_.get()),
        twin_(owned_twin_.get()),
        host_(std::move(host)) {}
  // A view of matrices owned elsewhere (a normal product's M).
  CheckedMatrix(const DeviceMatrix& primary, const DeviceMatrix& twin, RowMajorSparse host)
      : primary_(&primary), twin_(&twin), host_(std::move(host)) {}

  [[nodiscard]] int rows() const override { return primary_->rows(); }
  [[nodiscard]] int cols() const override { return primary_->cols(); }
  void update_values(const Eigen::Ref<const Eigen::VectorXd>& csr_values) override {
    if (!owned_primary_) throw std::logic_error("a normal product's matrix is updated through it");
    owned_primary_->update_values(csr_values);
    owned_twin_->update_values(csr_values);
    std::copy(csr_values.data(), csr_values.data() + csr_values.size(), host_.valuePtr());
  }

  [[nodiscard]] const DeviceMatrix& primary() const { return *primary_; }
  [[nodiscard]] const DeviceMatrix& twin() const { return *twin_; }
  [[nodiscard]] const RowMajorSparse& host() const override { return host_; }
  void set_host(RowMajorSparse host) { host_ = std::move(host); }

 private:
  std::unique_ptr<DeviceMatrix> owned_primary_, owned_twin_;
  const DeviceMatrix* primary_;
  const DeviceMatrix* twin_;
  RowMajorSparse host_;
};

// A vector block on both backends; what it holds is the primary's.
class CheckedVectors final : public DeviceVectors {
 public:
  CheckedVectors(std::unique_ptr<DeviceVectors> primary, std::unique_ptr<DeviceVectors> twin)
      : primary_(std::move(primary)), twin_(std::move(twin)) {}
  [[nodiscard]] int rows() const override { return primary_->rows(); }
  [[nodiscard]] int cols() const override { return primary_->cols(); }
  void upload(const Eigen::Ref<const Eigen::MatrixXd>& values) override {
    primary_->upload(values);
    twin_->upload(values);
  }
  [[nodiscard]] Eigen::MatrixXd download() const override { return primary_->download(); }

  [[nodiscard]] DeviceVectors& primary() const { return *primary_; }
  [[nodiscard]] DeviceVectors& twin() const { return *twin_; }

 private:
  std::unique_ptr<DeviceVectors> primary_, twin_;
};

// M = B diag(d) B^T on both backends, compared after every update.
class CheckedNormalProduct final : public DeviceNormalProduct {
 public:
  CheckedNormalProduct(std::unique_ptr<DeviceNormalProduct> primary,
                       std::unique_ptr<DeviceNormalProduct> twin)
      : primary_(std::move(primary)),
        twin_(std::move(twin)),
        matrix_(primary_->matrix(), twin_->matrix(), twin_->download()) {}

  void update(const Eigen::Ref<const Eigen::VectorXd>& b_values,
              const Eigen::Ref<const Eigen::VectorXd>& diagonal) override {
    primary_->update(b_values, diagonal);
    twin_->update(b_values, diagonal);
    matrix_.set_host(twin_->download());
  }
  [[nodiscard]] const DeviceMatrix& matrix() const override { return matrix_; }
  [[nodiscard]] RowMajorSparse download() const override { return primary_->download(); }

  // max |M_p - M_t| / max |M_t| over the entries of the fixed pattern.
  [[nodiscard]] double difference() const {
    const RowMajorSparse on_primary = primary_->download();
    const RowMajorSparse& on_twin = matrix_.host();
    const Eigen::Map<const Eigen::VectorXd> p(on_primary.valuePtr(), on_primary.nonZeros());
    const Eigen::Map<const Eigen::VectorXd> t(on_twin.valuePtr(), on_twin.nonZeros());
    if (p.size() != t.size()) return std::numeric_limits<double>::infinity();
    if (t.size() == 0) return 0.0;
    return relative((p - t).cwiseAbs().maxCoeff(), t.cwiseAbs().maxCoeff());
  }

 private:
  std::unique_ptr<DeviceNormalProduct> primary_, twin_;
  CheckedMatrix matrix_;
};

// max |p - t| / max |t| over the stored entries; infinite when the patterns differ.
double matrix_difference(const Eigen::SparseMatrix<double>& primary,
                         const Eigen::SparseMatrix<double>& twin) {
  const auto same = [](const int* a, const int* b, Eigen::Index count) {
    return std::equal(a, a + count, b);
  };
  if (primary.rows() != twin.rows() || primary.cols() != twin.cols() ||
      primary.nonZeros() != twin.nonZeros() || !primary.isCompressed() || !twin.isCompressed() ||
      !same(primary.outerIndexPtr(), twin.outerIndexPtr(), twin.outerSize() + 1) ||
      !same(primary.innerIndexPtr(), twin.innerIndexPtr(), twin.nonZeros()))
    return std::numeric_limits<double>::infinity();
  if (twin.nonZeros() == 0) return 0.0;
  const Eigen::Map<const Eigen::VectorXd> p(primary.valuePtr(), primary.nonZeros());
  const Eigen::Map<const Eigen::VectorXd> t(twin.valuePtr(), twin.nonZeros());
  return relative((p - t).cwiseAbs().maxCoeff(), t.cwiseAbs().maxCoeff());
}

// max |p - t| / max |t| over the finite entries; infinite when the non-finite entries differ.
double dense_difference(const Eigen::MatrixXd& primary, const Eigen::MatrixXd& twin) {
  if (primary.rows() != twin.rows() || primary.cols() != twin.cols())
    return std::numeric_limits<double>::infinity();
  double difference = 0.0, scale = 0.0;
  for (Eigen::Index k = 0; k < twin.size(); ++k) {
    const double p = primary.data()[k], t = twin.data()[k];
    if (std::isfinite(p) != std::isfinite(t)) return std::numeric_limits<double>::infinity();
    if (!std::isfinite(t)) continue;
    difference = std::max(difference, std::abs(p - t));
    scale = std::max(scale, std::abs(t));
  }
  return relative(difference, scale);
}

// The per-triangle operators on both backends; every result compared, the primary's returned.
class CheckedTriangleOperators final : public TriangleOperators {
 public:
  CheckedTriangleOperators(std::unique_ptr<TriangleOperators> primary,
                           std::unique_ptr<TriangleOperators> twin,
                           std::function<void(double)> record)
      : primary_(std::move(primary)), twin_(std::move(twin)), record_(std::move(record)) {}

  Eigen::SparseMatrix<double> cotangent(const Eigen::MatrixX3d& positions) override {
    Eigen::SparseMatrix<double> result = primary_->cotangent(positions);
    record_(matrix_difference(result, twin_->cotangent(positions)));
    return result;
  }
  Eigen::SparseMatrix<double> tensor_cotangent(const Eigen::MatrixX2d& uv,
                                               const TriangleTensorRows& tensors) override {
    Eigen::SparseMatrix<double> result = primary_->tensor_cotangent(uv, tensors);
    record_(matrix_difference(result, twin_->tensor_cotangent(uv, tensors)));
    return result;
  }
  QuasiHarmonicOperator quasi_harmonic(const Eigen::MatrixX3d& positions,
                                       const Eigen::MatrixX2d& uv) override {
    QuasiHarmonicOperator result = primary_->quasi_harmonic(positions, uv);
    const QuasiHarmonicOperator on_twin = twin_->quasi_harmonic(positions, uv);
    record_(dense_difference(result.tensors, on_twin.tensors));
    record_(matrix_difference(result.matrix, on_twin.matrix));
    return result;
  }
  Eigen::MatrixXd fragment_poisson_rhs(const Eigen::MatrixX3d& positions,
                                       const Eigen::MatrixXd& fragments) override {
    Eigen::MatrixXd result = primary_->fragment_poisson_rhs(positions, fragments);
    record_(dense_difference(result, twin_->fragment_poisson_rhs(positions, fragments)));
    return result;
  }

 private:
  std::unique_ptr<TriangleOperators> primary_, twin_;
  std::function<void(double)> record_;
};

// A preconditioner made on both backends; applying it applies both (each on its own copy of
// the vectors) and `compare` measures and resyncs the result.
class CheckedPreconditioner final : public Preconditioner {
 public:
  CheckedPreconditioner(std::unique_ptr<Preconditioner> primary,
                        std::unique_ptr<Preconditioner> twin,
                        std::function<void(DeviceVectors&)> compare)
      : primary_(std::move(primary)), twin_(std::move(twin)), compare_(std::move(compare)) {}
  void apply(const DeviceVectors& r, DeviceVectors& z) override;
  [[nodiscard]] Preconditioner& primary() const { return *primary_; }
  [[nodiscard]] Preconditioner& twin() const { return *twin_; }

 private:
  std::unique_ptr<Preconditioner> primary_, twin_;
  std::function<void(DeviceVectors&)> compare_;
};

const CheckedMatrix& checked(const DeviceMatrix& matrix) {
  const auto* pair = dynamic_cast<const CheckedMatrix*>(&matrix);
  if (pair == nullptr)
    throw std::logic_error("CrossCheckBackend: a matrix from another backend was passed");
  return *pair;
}

CheckedVectors& checked(const DeviceVectors& vectors) {
  const auto* pair = dynamic_cast<const CheckedVectors*>(&vectors);
  if (pair == nullptr)
    throw std::logic_error("CrossCheckBackend: vectors from another backend were passed");
  return const_cast<CheckedVectors&>(*pair);  // Both halves are owned; constness is the block's.
}

CheckedPreconditioner& checked(Preconditioner& preconditioner) {
  auto* pair = dynamic_cast<CheckedPreconditioner*>(&preconditioner);
  if (pair == nullptr)
    throw std::logic_error("CrossCheckBackend: a preconditioner from another backend was passed");
  return *pair;
}

void CheckedPreconditioner::apply(const DeviceVectors& r, DeviceVectors& z) {
  primary_->apply(checked(r).primary(), checked(z).primary());
  twin_->apply(checked(r).twin(), checked(z).twin());
  compare_(z);
}

}  // namespace

CrossCheckBackend::CrossCheckBackend(std::unique_ptr<Backend> primary)
    : primary_(std::move(primary)), twin_(std::make_unique<CpuBackend>()) {
  if (!primary_) throw std::invalid_argument("CrossCheckBackend: no primary backend");
}

CrossCheckBackend::~CrossCheckBackend() = default;

std::string CrossCheckBackend::description() const {
  return primary_->description() + ", cross-checked against " + twin_->description();
}

bool CrossCheckBackend::supports(Feature feature) const { return primary_->supports(feature); }

void CrossCheckBackend::record(double error) {
  if (std::isnan(error)) error = std::numeric_limits<double>::infinity();
  if (error > worst_error_) worst_error_ = error;
}

void CrossCheckBackend::settle_twin_solve(const SolveStats& primary, const SolveStats& twin,
                                          DeviceVectors& x) {
  if (primary.status == Status::ok && twin.status == Status::ok)
    compare_and_resync(x);
  else
    checked(x).twin().upload(checked(x).primary().download());
}

void CrossCheckBackend::compare_and_resync(DeviceVectors& result) {
  CheckedVectors& pair = checked(result);
  const Eigen::MatrixXd on_primary = pair.primary().download();
  const Eigen::MatrixXd on_twin = pair.twin().download();
  if (on_twin.size() > 0)
    record(relative((on_primary - on_twin).cwiseAbs().maxCoeff(), on_twin.cwiseAbs().maxCoeff()));
  pair.twin().upload(on_primary);
}

std::unique_ptr<DeviceMatrix> CrossCheckBackend::upload(const RowMajorSparse& matrix) {
  return std::make_unique<CheckedMatrix>(primary_->upload(matrix), twin_->upload(matrix), matrix);
}

std::unique_ptr<DeviceVectors> CrossCheckBackend::upload(
    const Eigen::Ref<const Eigen::MatrixXd>& values) {
  return std::make_unique<CheckedVectors>(primary_->upload(values), twin_->upload(values));
}

std::unique_ptr<DeviceVectors> CrossCheckBackend::allocate(int rows, int cols) {
  return std::make_unique<CheckedVectors>(primary_->allocate(rows, cols),
                                          twin_->allocate(rows, cols));
}

void CrossCheckBackend::spmv(const DeviceMatrix& a, const DeviceVectors& x, DeviceVectors& y) {
  const CheckedMatrix& matrix = checked(a);
  const CheckedVectors& input = checked(x);
  CheckedVectors& output = checked(y);
  primary_->spmv(matrix.primary(), input.primary(), output.primary());
  twin_->spmv(matrix.twin(), input.twin(), output.twin());
  const Eigen::MatrixXd on_primary = output.primary().download();
  const Eigen::MatrixXd on_twin = output.twin().download();
  if (on_twin.size() > 0) {
    const Eigen::MatrixXd rounding_scale =
        matrix.host().cwiseAbs() * input.twin().download().cwiseAbs();
    record(relative((on_primary - on_twin).cwiseAbs().maxCoeff(), rounding_scale.maxCoeff()));
  }
  output.twin().upload(on_primary);
}

Eigen::VectorXd CrossCheckBackend::dot(const DeviceVectors& x, const DeviceVectors& y) {
  const CheckedVectors& left = checked(x);
  const CheckedVectors& right = checked(y);
  const Eigen::VectorXd on_primary = primary_->dot(left.primary(), right.primary());
  const Eigen::VectorXd on_twin = twin_->dot(left.twin(), right.twin());
  const Eigen::VectorXd left_norms = twin_->dot(left.twin(), left.twin()).cwiseSqrt();
  const Eigen::VectorXd right_norms = twin_->dot(right.twin(), right.twin()).cwiseSqrt();
  for (Eigen::Index column = 0; column < on_twin.size(); ++column)
    record(relative(std::abs(on_primary[column] - on_twin[column]),
                    left_norms[column] * right_norms[column]));
  return on_primary;
}

void CrossCheckBackend::axpy(const Eigen::VectorXd& alpha, const DeviceVectors& x,
                             DeviceVectors& y) {
  primary_->axpy(alpha, checked(x).primary(), checked(y).primary());
  twin_->axpy(alpha, checked(x).twin(), checked(y).twin());
}

void CrossCheckBackend::xpay(const DeviceVectors& x, const Eigen::VectorXd& beta,
                             DeviceVectors& y) {
  primary_->xpay(checked(x).primary(), beta, checked(y).primary());
  twin_->xpay(checked(x).twin(), beta, checked(y).twin());
}

void CrossCheckBackend::copy(const DeviceVectors& x, DeviceVectors& y) {
  primary_->copy(checked(x).primary(), checked(y).primary());
  twin_->copy(checked(x).twin(), checked(y).twin());
}

void CrossCheckBackend::jacobi(const DeviceMatrix& a, const DeviceVectors& r, DeviceVectors& z) {
  primary_->jacobi(checked(a).primary(), checked(r).primary(), checked(z).primary());
  twin_->jacobi(checked(a).twin(), checked(r).twin(), checked(z).twin());
}

std::unique_ptr<DeviceNormalProduct> CrossCheckBackend::normal_product(
    const RowMajorSparse& b, const Eigen::Ref<const Eigen::VectorXd>& diagonal) {
  auto product = std::make_unique<CheckedNormalProduct>(primary_->normal_product(b, diagonal),
                                                        twin_->normal_product(b, diagonal));
  record(product->difference());
  // Later updates are compared by the products they feed (spmv); a wrapper keeps this one's.
  class Recording final : public DeviceNormalProduct {
   public:
    Recording(std::unique_ptr<CheckedNormalProduct> product, CrossCheckBackend& backend)
        : product_(std::move(product)), backend_(backend) {}
    void update(const Eigen::Ref<const Eigen::VectorXd>& b_values,
                const Eigen::Ref<const Eigen::VectorXd>& diagonal) override {
      product_->update(b_values, diagonal);
      backend_.record(product_->difference());
    }
    [[nodiscard]] const DeviceMatrix& matrix() const override { return product_->matrix(); }
    [[nodiscard]] RowMajorSparse download() const override { return product_->download(); }

   private:
    std::unique_ptr<CheckedNormalProduct> product_;
    CrossCheckBackend& backend_;
  };
  return std::make_unique<Recording>(std::move(product), *this);
}

std::unique_ptr<TriangleOperators> CrossCheckBackend::triangle_operators(
    const Eigen::MatrixX3i& faces, int vertex_count) {
  return std::make_unique<CheckedTriangleOperators>(
      primary_->triangle_operators(faces, vertex_count),
      twin_->triangle_operators(faces, vertex_count), [this](double error) { record(error); });
}

SolveStats CrossCheckBackend::pcg(const DeviceMatrix& a, const DeviceVectors& b,
                                  DeviceVectors& x, const IterativeSettings& settings,
                                  const ProgressCallback& progress) {
  const SolveStats stats =
      primary_->pcg(checked(a).primary(), checked(b).primary(), checked(x).primary(), settings,
                    progress);
  // The twin solves from the same warm start; only converged solutions are meant to agree.
  const SolveStats twin_stats = twin_->pcg(checked(a).twin(), checked(b).twin(),
                                           checked(x).twin(), settings, ProgressCallback{});
  settle_twin_solve(stats, twin_stats, x);
  return stats;
}

std::unique_ptr<Preconditioner> CrossCheckBackend::multilevel_preconditioner(
    const AggregationHierarchy& hierarchy) {
  return std::make_unique<CheckedPreconditioner>(
      primary_->multilevel_preconditioner(hierarchy), twin_->multilevel_preconditioner(hierarchy),
      [this](DeviceVectors& result) { compare_and_resync(result); });
}

SolveStats CrossCheckBackend::preconditioned_pcg(const DeviceMatrix& a,
                                                 Preconditioner& preconditioner,
                                                 const DeviceVectors& b, DeviceVectors& x,
                                                 const IterativeSettings& settings,
                                                 const ProgressCallback& progress) {
  const CheckedPreconditioner& pair = checked(preconditioner);
  const SolveStats stats =
      primary_->preconditioned_pcg(checked(a).primary(), pair.primary(), checked(b).primary(),
                                   checked(x).primary(), settings, progress);
  // The twin solves from the same warm start; only converged solutions are meant to agree.
  const SolveStats twin_stats =
      twin_->preconditioned_pcg(checked(a).twin(), pair.twin(), checked(b).twin(),
                                checked(x).twin(), settings, ProgressCallback{});
  settle_twin_solve(stats, twin_stats, x);
  return stats;
}

SolveStats CrossCheckBackend::minres(const DeviceMatrix& a, const DeviceVectors& b,
                                     DeviceVectors& x, const IterativeSettings& settings,
                                     const ProgressCallback& progress) {
  const SolveStats stats =
      primary_->minres(checked(a).primary(), checked(b).primary(), checked(x).primary(),
                       settings, progress);
  const SolveStats twin_stats = twin_->minres(checked(a).twin(), checked(b).twin(),
                                              checked(x).twin(), settings, ProgressCallback{});
  settle_twin_solve(stats, twin_stats, x);
  return stats;
}

BlockSolveStats CrossCheckBackend::block_pcg(const DeviceMatrix& a, const BlockRows& blocks,
                                             const DeviceVectors& b, DeviceVectors& x,
                                             const IterativeSettings& settings,
                                             const ProgressCallback& progress) {
  const BlockSolveStats stats = primary_->block_pcg(
      checked(a).primary(), blocks, checked(b).primary(), checked(x).primary(), settings, progress);
  // The twin solves from the same warm start; only converged solutions are meant to agree.
  const BlockSolveStats twin_stats =
      twin_->block_pcg(checked(a).twin(), blocks, checked(b).twin(), checked(x).twin(), settings,
                       ProgressCallback{});
  settle_twin_solve(stats, twin_stats, x);
  return stats;
}

}  // namespace harmonia::detail
