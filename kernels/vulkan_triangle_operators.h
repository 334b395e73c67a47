#pragma once
// Internal: the Vulkan backend's per-triangle operators (TriangleOperators, backend/backend.h):
// the cotangent, tensor-cotangent and quasi-harmonic operators assembled by the triangle kernels
// (kernels/triangle_assembly.h, kernels/triangle_tensors.h), the fragment right-hand side gathered
// by the corner kernels (kernels/triangle_calculus.h). Each call is one submission, waited for;
// its result is read back in double (the device's reals widened). The Eigen twins are the CPU
// backend's (fallback/cpu_triangle_operators.h); each device result is within the error bounds
// declared next to its kernel.
//
// Made by VulkanBackend::triangle_operators; it submits on that backend's recorder, so it must
// not outlive the backend. One thread at a time, like the backend.

#include <memory>

#include "backend/backend.h"
#include "harmonia/solver_options.h"

namespace harmonia::vulkan::detail {

class CommandRecorder;
class TriangleAssembly;
class TriangleCalculus;

class VulkanTriangleOperators final : public harmonia::detail::TriangleOperators {
 public:
  // Throws harmonia::Error(invalid_input) naming a face with an index outside [0, vertex_count).
  VulkanTriangleOperators(CommandRecorder& recorder, const Eigen::MatrixX3i& faces,
                          int vertex_count, DevicePrecision precision);
  ~VulkanTriangleOperators() override;

  [[nodiscard]] Eigen::SparseMatrix<double> cotangent(const Eigen::MatrixX3d& positions) override;
  [[nodiscard]] Eigen::SparseMatrix<double> tensor_cotangent(
      const Eigen::MatrixX2d& uv, const harmonia::detail::TriangleTensorRows& tensors) override;
  [[nodiscard]] harmonia::detail::QuasiHarmonicOperator quasi_harmonic(
      const Eigen::MatrixX3d& positions, const Eigen::MatrixX2d& uv) override;
  [[nodiscard]] Eigen::MatrixXd fragment_poisson_rhs(const Eigen::MatrixX3d& positions,
                                                     const Eigen::MatrixXd& fragments) override;

 private:
  // The assembled operator, in the column-major layout of the host operators.
  [[nodiscard]] Eigen::SparseMatrix<double> assembled() const;

  CommandRecorder& recorder_;
  DevicePrecision precision_;
  Eigen::MatrixX3i faces_;
  int vertex_count_;
  std::unique_ptr<TriangleAssembly> assembly_;
  std::unique_ptr<TriangleCalculus> calculus_;  // Made with the first right-hand side's positions.
};

}  // namespace harmonia::vulkan::detail
