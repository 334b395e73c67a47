#pragma once
// Internal: the Backend (host/backend/backend.h) on a Vulkan device, in fp32 (the default) or in
// fp64 (DevicePrecision::float64, on a context with shaderFloat64 enabled): every kernel exists
// in both precisions (shaders/common/real.glsl) and all of a backend's buffers hold one type.
//
// Every primitive is one submission that the call waits for. In fp32 values are rounded from
// double on upload. pcg() runs the fused device PCG (kernels/pcg.h), minres() the fused device
// MINRES (kernels/minres.h), block_pcg() the batched block-diagonal PCG (kernels/block_pcg.h):
// several iterations per submission, the flags read back every IterativeSettings::check_every
// iterations. All three are wrapped in iterative refinement in double on the host
// (kernels/refinement.h; per block for block_pcg): the residual b - A x is formed in double, the
// correction is solved on the device in fp32, so the requested tolerance is met even below
// fp32's reach and the reported residual is the true one in double. In fp64 the device solve
// reaches the tolerance itself and the host only confirms the residual in double.
//
// Not thread-safe: one thread at a time per backend (several backends may share a Context).

#include <memory>
#include <string>

#include "backend/backend.h"
#include "harmonia/vulkan_context.h"
#include "kernels/buffer.h"
#include "kernels/recorder.h"
#include "kernels/refinement.h"

namespace harmonia::vulkan::detail {

class VulkanMatrix;
class VulkanVectors;
class TriangleAssembly;
class TriangleCalculus;
class NormalProduct;

class VulkanBackend final : public harmonia::detail::Backend {
 public:
  // The context must not be null; the backend shares its ownership.
  // DevicePrecision::float64 needs a context with float64_enabled (else harmonia::Error,
  // Status::unsupported, saying why).
  explicit VulkanBackend(std::shared_ptr<Context> context,
                         DevicePrecision precision = DevicePrecision::float32);

  [[nodiscard]] BackendKind kind() const override { return BackendKind::vulkan; }
  [[nodiscard]] std::string description() const override;  // "vulkan (<device>, fp32|fp64)".
  [[nodiscard]] bool supports(harmonia::detail::Feature feature) const override;

  [[nodiscard]] std::unique_ptr<harmonia::detail::DeviceMatrix> upload(
      const harmonia::detail::RowMajorSparse& matrix) override;
  [[nodiscard]] std::unique_ptr<harmonia::detail::DeviceVectors> upload(
      const Eigen::Ref<const Eigen::MatrixXd>& values) override;
  [[nodiscard]] std::unique_ptr<harmonia::detail::DeviceVectors> allocate(int rows,
                                                                          int cols) override;

  void spmv(const harmonia::detail::DeviceMatrix& a, const harmonia::detail::DeviceVectors& x,
            harmonia::detail::DeviceVectors& y) override;
  [[nodiscard]] Eigen::VectorXd dot(const harmonia::detail::DeviceVectors& x,
                                    const harmonia::detail::DeviceVectors& y) override;
  void axpy(const Eigen::VectorXd& alpha, const harmonia::detail::DeviceVectors& x,
            harmonia::detail::DeviceVectors& y) override;
  void xpay(const harmonia::detail::DeviceVectors& x, const Eigen::VectorXd& beta,
            harmonia::detail::DeviceVectors& y) override;
  void copy(const harmonia::detail::DeviceVectors& x, harmonia::detail::DeviceVectors& y) override;
  void jacobi(const harmonia::detail::DeviceMatrix& a, const harmonia::detail::DeviceVectors& r,
              harmonia::detail::DeviceVectors& z) override;
  // y = alpha y per column (not part of the Backend interface).
  void scale(const Eigen::VectorXd& alpha, harmonia::detail::DeviceVectors& y);

  harmonia::detail::SolveStats pcg(const harmonia::detail::DeviceMatrix& a,
                                   const harmonia::detail::DeviceVectors& b,
                                   harmonia::detail::DeviceVectors& x,
                                   const harmonia::detail::IterativeSettings& settings,
                                   const ProgressCallback& progress) override;
  // PCG with a preconditioner this backend made, refined in double as pcg() is.
  harmonia::detail::SolveStats preconditioned_pcg(
      const harmonia::detail::DeviceMatrix& a, harmonia::detail::Preconditioner& preconditioner,
      const harmonia::detail::DeviceVectors& b, harmonia::detail::DeviceVectors& x,
      const harmonia::detail::IterativeSettings& settings,
      const ProgressCallback& progress) override;
  harmonia::detail::SolveStats minres(const harmonia::detail::DeviceMatrix& a,
                                      const harmonia::detail::DeviceVectors& b,
                                      harmonia::detail::DeviceVectors& x,
                                      const harmonia::detail::IterativeSettings& settings,
                                      const ProgressCallback& progress) override;
  // The batched block-diagonal PCG on the device (kernels/block_pcg.h), refined in double per
  // system as pcg() is per column.
  harmonia::detail::BlockSolveStats block_pcg(const harmonia::detail::DeviceMatrix& a,
                                              const harmonia::detail::BlockRows& blocks,
                                              const harmonia::detail::DeviceVectors& b,
                                              harmonia::detail::DeviceVectors& x,
                                              const harmonia::detail::IterativeSettings& settings,
                                              const ProgressCallback& progress) override;

  // Backend::triangle_operators: the assembly and corner kernels below, each call one submission
  // (kernels/vulkan_triangle_operators.h); it must not outlive the backend.
  [[nodiscard]] std::unique_ptr<harmonia::detail::TriangleOperators> triangle_operators(
      const Eigen::MatrixX3i& faces, int vertex_count) override;

  // Per-triangle assembly of cotangent or tensor-cotangent operators of this connectivity into a
  // fixed CSR pattern on the device (kernels/triangle_assembly.h); it submits on this backend's
  // recorder, so it must not outlive the backend.
  [[nodiscard]] std::unique_ptr<TriangleAssembly> triangle_assembly(const Eigen::MatrixX3i& faces,
                                                                    int vertex_count);

  // Per-triangle gradient, divergence and fragment Poisson right-hand sides on this mesh
  // (kernels/triangle_calculus.h); same lifetime rule. positions: #V x 2 or #V x 3.
  [[nodiscard]] std::unique_ptr<TriangleCalculus> triangle_calculus(
      const Eigen::MatrixX3i& faces, const Eigen::MatrixXd& positions);

  // The weighted normal product B D B^T with the pattern of `b`, refreshed on the device
  // (kernels/normal_product.h); same lifetime rule.
  [[nodiscard]] std::unique_ptr<NormalProduct> normal_product(
      const harmonia::detail::RowMajorSparse& b);
  // Backend::normal_product: M refreshed by the kernel into a device matrix that spmv, jacobi,
  // pcg and minres use directly (kernels/normal_product_matrix.h); same lifetime rule.
  [[nodiscard]] std::unique_ptr<harmonia::detail::DeviceNormalProduct> normal_product(
      const harmonia::detail::RowMajorSparse& b,
      const Eigen::Ref<const Eigen::VectorXd>& diagonal) override;

  [[nodiscard]] DevicePrecision precision() const { return precision_; }

  [[nodiscard]] Context& context() const { return *context_; }
  // GPU time of the last primitive's submission in seconds (0 without timestamps).
  [[nodiscard]] double last_gpu_seconds() const { return recorder_.last_gpu_seconds(); }

 private:
  // Checks the shapes and runs iterative refinement in double around solve_correction.
  harmonia::detail::SolveStats refined(const harmonia::detail::DeviceMatrix& a,
                                       const harmonia::detail::DeviceVectors& b,
                                       harmonia::detail::DeviceVectors& x,
                                       const harmonia::detail::IterativeSettings& settings,
                                       const char* method, const CorrectionSolver& solve_correction);
  // Makes the coefficient and reduction scratch buffers at least this large.
  void reserve_coefficients(int count);
  void reserve_reduction(int rows, int cols);
  void write_coefficients(const Eigen::VectorXd& values);

  std::shared_ptr<Context> context_;
  DevicePrecision precision_;
  CommandRecorder recorder_;
  std::unique_ptr<Buffer> coefficients_, partials_, results_;
};

}  // namespace harmonia::vulkan::detail
