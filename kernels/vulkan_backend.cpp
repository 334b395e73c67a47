#include "kernels/vulkan_backend.h"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "kernels/block_pcg.h"
#include "kernels/context_impl.h"
#include "kernels/device_arrays.h"
#include "kernels/device_reals.h"
#include "kernels/minres.h"
#include "kernels/normal_product.h"
#include "kernels/normal_product_matrix.h"
#include "kernels/pcg.h"
#include "kernels/reduction.h"
#include "kernels/refinement.h"
#include "kernels/spmv.h"
#include "kernels/transfers.h"
#include "kernels/triangle_assembly.h"
#include "kernels/triangle_calculus.h"
#include "kernels/vector_ops.h"
#include "kernels/vulkan_triangle_operators.h"

namespace harmonia::vulkan::detail {
namespace {

using harmonia::detail::DeviceMatrix;
using harmonia::detail::DeviceVectors;
using harmonia::detail::Preconditioner;
using harmonia::detail::IterativeSettings;
using harmonia::detail::SolveStats;

// The backend only ever receives its own objects; anything else is a programming error.
const VulkanMatrix& device(const DeviceMatrix& matrix) {
  const auto* result = dynamic_cast<const VulkanMatrix*>(&matrix);
  if (result == nullptr) throw std::logic_error("vulkan backend: matrix from another backend");
  return *result;
}
const VulkanVectors& device(const DeviceVectors& vectors) {
  const auto* result = dynamic_cast<const VulkanVectors*>(&vectors);
  if (result == nullptr) throw std::logic_error("vulkan backend: vectors from another backend");
  return *result;
}
VulkanVectors& device(DeviceVectors& vectors) {
  auto* result = dynamic_cast<VulkanVectors*>(&vectors);
  if (result == nullptr) throw std::logic_error("vulkan backend: vectors from another backend");
  return *result;
}

void check_shapes(const DeviceVectors& x, const DeviceVectors& y, const char* operation) {
  if (x.rows() != y.rows() || x.cols() != y.cols())
    throw std::invalid_argument(std::string("vulkan backend: ") + operation +
                                ": block shapes differ");
}

void check_coefficients(const Eigen::VectorXd& values, const DeviceVectors& x,
                        const char* operation) {
  if (values.size() != x.cols())
    throw std::invalid_argument(std::string("vulkan backend: ") + operation +
                                ": one coefficient per column is needed");
}

}  // namespace

VulkanBackend::VulkanBackend(std::shared_ptr<Context> context, DevicePrecision precision)
    : context_(context ? std::move(context)
                       : throw std::invalid_argument("VulkanBackend: null context")),
      precision_(precision),
      recorder_(context_->impl()) {
  const DeviceInfo& device = context_->device();
  if (precision == DevicePrecision::float64 && !device.float64_enabled)
    throw Error(Status::unsupported,
                "fp64 on the Vulkan device \"" + device.name + "\" needs shaderFloat64, " +
                    (device.shader_float64
                         ? std::string("which the device has but the context did not enable "
                                       "(ContextOptions::enable_float64, or "
                                       "ExternalVulkan::float64_enabled for a borrowed device)")
                         : std::string("which the device does not support; use "
                                       "DevicePrecision::float32 or the CPU backend")));
}

std::string VulkanBackend::description() const {
  return "vulkan (" + context_->device().name + ", " + precision_name(precision_) + ")";
}

bool VulkanBackend::supports(harmonia::detail::Feature feature) const {
  switch (feature) {
    case harmonia::detail::Feature::float64:
      return precision_ == DevicePrecision::float64;
    case harmonia::detail::Feature::direct_factorization:
      return false;
  }
  return false;
}

std::unique_ptr<DeviceMatrix> VulkanBackend::upload(
    const harmonia::detail::RowMajorSparse& matrix) {
  return std::make_unique<VulkanMatrix>(recorder_, matrix, precision_);
}

std::unique_ptr<DeviceVectors> VulkanBackend::upload(
    const Eigen::Ref<const Eigen::MatrixXd>& values) {
  auto vectors = std::make_unique<VulkanVectors>(recorder_, static_cast<int>(values.rows()),
                                                 static_cast<int>(values.cols()), precision_);
  vectors->upload(values);
  return vectors;
}

std::unique_ptr<DeviceVectors> VulkanBackend::allocate(int rows, int cols) {
  return std::make_unique<VulkanVectors>(recorder_, rows, cols, precision_);
}

std::unique_ptr<harmonia::detail::TriangleOperators> VulkanBackend::triangle_operators(
    const Eigen::MatrixX3i& faces, int vertex_count) {
  return std::make_unique<VulkanTriangleOperators>(recorder_, faces, vertex_count, precision_);
}

std::unique_ptr<TriangleAssembly> VulkanBackend::triangle_assembly(const Eigen::MatrixX3i& faces,
                                                                   int vertex_count) {
  return std::make_unique<TriangleAssembly>(recorder_, faces, vertex_count, precision_);
}

std::unique_ptr<TriangleCalculus> VulkanBackend::triangle_calculus(
    const Eigen::MatrixX3i& faces, const Eigen::MatrixXd& positions) {
  return std::make_unique<TriangleCalculus>(recorder_, faces, positions, precision_);
}

std::unique_ptr<NormalProduct> VulkanBackend::normal_product(
    const harmonia::detail::RowMajorSparse& b) {
  return std::make_unique<NormalProduct>(recorder_, b, precision_);
}

std::unique_ptr<harmonia::detail::DeviceNormalProduct> VulkanBackend::normal_product(
    const harmonia::detail::RowMajorSparse& b, const Eigen::Ref<const Eigen::VectorXd>& diagonal) {
  if (diagonal.size() != b.cols())
    throw std::invalid_argument("normal product: one weight per column of B is needed");
  return std::make_unique<VulkanNormalProduct>(recorder_, b, diagonal, precision_);
}

void VulkanBackend::reserve_coefficients(int count) {
  const std::uint64_t bytes =
      real_bytes(precision_, static_cast<std::uint64_t>(std::max(count, 1)));
  if (!coefficients_ || coefficients_->bytes() < bytes)
    coefficients_ =
        std::make_unique<Buffer>(context_->impl(), bytes, BufferRole::device, "coefficients");
}

void VulkanBackend::reserve_reduction(int rows, int cols) {
  const std::uint64_t partial_bytes =
      real_bytes(precision_, dot_scratch_floats(rows, cols, reduction_shape(context_->impl())));
  if (!partials_ || partials_->bytes() < partial_bytes)
    partials_ = std::make_unique<Buffer>(context_->impl(), partial_bytes, BufferRole::device,
                                         "dot partials");
  const std::uint64_t result_bytes =
      real_bytes(precision_, static_cast<std::uint64_t>(std::max(cols, 1)));
  if (!results_ || results_->bytes() < result_bytes)
    results_ =
        std::make_unique<Buffer>(context_->impl(), result_bytes, BufferRole::device, "dot results");
}

void VulkanBackend::write_coefficients(const Eigen::VectorXd& values) {
  reserve_coefficients(static_cast<int>(values.size()));
  const std::vector<std::byte> converted = encode_reals(
      values.data(), static_cast<std::size_t>(values.size()), precision_, "coefficient");
  write_buffer(recorder_, *coefficients_, converted.data(), converted.size());
}

void VulkanBackend::spmv(const DeviceMatrix& a, const DeviceVectors& x, DeviceVectors& y) {
  recorder_.begin();
  record_spmv(recorder_, device(a), device(x), device(y));
  recorder_.end();
  recorder_.submit_and_wait();
}

Eigen::VectorXd VulkanBackend::dot(const DeviceVectors& x, const DeviceVectors& y) {
  check_shapes(x, y, "dot");
  reserve_reduction(x.rows(), x.cols());
  recorder_.begin();
  record_dot(recorder_, device(x), device(y), *partials_, *results_, 0);
  recorder_.end();
  recorder_.submit_and_wait();
  const auto cols = static_cast<std::size_t>(x.cols());
  std::vector<std::byte> results(real_bytes(precision_, cols));
  read_buffer(recorder_, *results_, results.data(), results.size());
  Eigen::VectorXd values(x.cols());
  decode_reals(results.data(), cols, precision_, values.data());
  return values;
}

void VulkanBackend::axpy(const Eigen::VectorXd& alpha, const DeviceVectors& x, DeviceVectors& y) {
  check_shapes(x, y, "axpy");
  check_coefficients(alpha, x, "axpy");
  write_coefficients(alpha);
  recorder_.begin();
  record_linear_combination(recorder_, *coefficients_, Coefficient{1.0f, 0u}, device(x),
                            Coefficient{1.0f, {}}, device(y));
  recorder_.end();
  recorder_.submit_and_wait();
}

void VulkanBackend::xpay(const DeviceVectors& x, const Eigen::VectorXd& beta, DeviceVectors& y) {
  check_shapes(x, y, "xpay");
  check_coefficients(beta, x, "xpay");
  write_coefficients(beta);
  recorder_.begin();
  record_linear_combination(recorder_, *coefficients_, Coefficient{1.0f, {}}, device(x),
                            Coefficient{1.0f, 0u}, device(y));
  recorder_.end();
  recorder_.submit_and_wait();
}

void VulkanBackend::copy(const DeviceVectors& x, DeviceVectors& y) {
  check_shapes(x, y, "copy");
  reserve_coefficients(1);
  recorder_.begin();
  record_linear_combination(recorder_, *coefficients_, Coefficient{1.0f, {}}, device(x),
                            std::nullopt, device(y));
  recorder_.end();
  recorder_.submit_and_wait();
}

void VulkanBackend::scale(const Eigen::VectorXd& alpha, DeviceVectors& y) {
  check_coefficients(alpha, y, "scale");
  write_coefficients(alpha);
  recorder_.begin();
  record_linear_combination(recorder_, *coefficients_, Coefficient{1.0f, 0u}, device(y),
                            std::nullopt, device(y));
  recorder_.end();
  recorder_.submit_and_wait();
}

void VulkanBackend::jacobi(const DeviceMatrix& a, const DeviceVectors& r, DeviceVectors& z) {
  check_shapes(r, z, "jacobi");
  recorder_.begin();
  record_jacobi(recorder_, device(a), device(r), device(z));
  recorder_.end();
  recorder_.submit_and_wait();
}

// Shapes checked, then iterative refinement in double around `solve_correction`
// (kernels/refinement.h) with work blocks of b's shape.
SolveStats VulkanBackend::refined(const DeviceMatrix& a, const DeviceVectors& b, DeviceVectors& x,
                                  const IterativeSettings& settings, const char* method,
                                  const CorrectionSolver& solve_correction) {
  check_shapes(b, x, method);
  VulkanVectors residual(recorder_, b.rows(), b.cols(), precision_);
  VulkanVectors correction(recorder_, b.rows(), b.cols(), precision_);
  return refine_in_double(device(a), device(b), device(x), residual, correction, settings, method,
                          solve_correction);
}

SolveStats VulkanBackend::pcg(const DeviceMatrix& a, const DeviceVectors& b, DeviceVectors& x,
                              const IterativeSettings& settings, const ProgressCallback& progress) {
  const VulkanMatrix& matrix = device(a);
  const auto solve_correction = [&](const VulkanVectors& r, VulkanVectors& d,
                                    const Eigen::VectorXd& tolerances, int max_iterations,
                                    int progress_offset) {
    // Absolute thresholds from the double residual the refinement just uploaded.
    const Eigen::VectorXd r_norms = r.download().colwise().norm().transpose();
    const DevicePcgResult result = run_device_pcg(
        context_->impl(), matrix, r, d, tolerances.cwiseProduct(r_norms), max_iterations,
        settings.check_every, progress, progress_offset, settings.max_iterations);
    SolveStats stats;
    stats.iterations = result.iterations;
    if (result.cancelled) {
      stats.status = Status::cancelled;
      stats.message = "cancelled during pcg";
    } else if (result.failure == PcgFailure::not_positive_definite) {
      stats.status = Status::numerical_failure;
      stats.message = "pcg: the matrix is not positive definite (p^T A p <= 0 in column " +
                      std::to_string(result.failed_column) + ")";
    } else if (result.failure == PcgFailure::not_finite) {
      stats.status = Status::numerical_failure;
      stats.message =
          "pcg: the residual is not finite (column " + std::to_string(result.failed_column) + ")";
    }
    return stats;
  };
  return refined(a, b, x, settings, "pcg", solve_correction);
}

// The multilevel preconditioner's V-cycle is made of this backend's primitives (the default
// Backend::multilevel_preconditioner), so the correction of each refinement round is the
// generic preconditioned loop of host/backend/krylov.cpp on the device, in its precision.
SolveStats VulkanBackend::preconditioned_pcg(const DeviceMatrix& a, Preconditioner& preconditioner,
                                             const DeviceVectors& b, DeviceVectors& x,
                                             const IterativeSettings& settings,
                                             const ProgressCallback& progress) {
  const auto solve_correction = [&](const VulkanVectors& r, VulkanVectors& d,
                                    const Eigen::VectorXd& tolerances, int max_iterations,
                                    int progress_offset) {
    IterativeSettings round = settings;
    round.relative_tolerance = tolerances.minCoeff();  // The strictest column's, for all.
    round.max_iterations = max_iterations;
    ProgressCallback shifted;
    if (progress)
      shifted = [&](const Progress& step) {
        return progress(Progress{step.stage, progress_offset + step.step, settings.max_iterations});
      };
    return Backend::preconditioned_pcg(a, preconditioner, r, d, round, shifted);
  };
  return refined(a, b, x, settings, "pcg", solve_correction);
}

SolveStats VulkanBackend::minres(const DeviceMatrix& a, const DeviceVectors& b, DeviceVectors& x,
                                 const IterativeSettings& settings,
                                 const ProgressCallback& progress) {
  const VulkanMatrix& matrix = device(a);
  // The refinement applies to MINRES as to PCG: the correction equation A d = r has the same
  // symmetric (indefinite, possibly singular) matrix, and for a consistent system r stays in the
  // range of A, so each round's fused device MINRES sees a consistent system too.
  const auto solve_correction = [&](const VulkanVectors& r, VulkanVectors& d,
                                    const Eigen::VectorXd& tolerances, int max_iterations,
                                    int progress_offset) {
    // Absolute thresholds from the double residual the refinement just uploaded.
    const Eigen::VectorXd r_norms = r.download().colwise().norm().transpose();
    const DeviceMinresResult result = run_device_minres(
        context_->impl(), matrix, r, d, tolerances.cwiseProduct(r_norms), max_iterations,
        settings.check_every, progress, progress_offset, settings.max_iterations);
    SolveStats stats;
    stats.iterations = result.iterations;
    if (result.cancelled) {
      stats.status = Status::cancelled;
      stats.message = "cancelled during minres";
    } else if (result.failure == MinresFailure::not_finite) {
      stats.status = Status::numerical_failure;
      stats.message = "minres: a Lanczos or rotation scalar is not finite (column " +
                      std::to_string(result.failed_column) + ")";
    }
    // Below the inner tolerance or not, the correction helps; the double residual decides.
    return stats;
  };
  return refined(a, b, x, settings, "minres", solve_correction);
}

harmonia::detail::BlockSolveStats VulkanBackend::block_pcg(
    const DeviceMatrix& a, const harmonia::detail::BlockRows& blocks, const DeviceVectors& b,
    DeviceVectors& x, const IterativeSettings& settings, const ProgressCallback& progress) {
  check_shapes(b, x, "block_pcg");
  return solve_block_pcg(recorder_, device(a), blocks, device(b), device(x), settings, progress);
}

}  // namespace harmonia::vulkan::detail
