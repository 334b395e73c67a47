// The Vulkan backend's per-triangle operators (vulkan_triangle_operators.h).

#include "kernels/vulkan_triangle_operators.h"

#include <stdexcept>
#include <string>

#include "kernels/device_arrays.h"
#include "kernels/triangle_assembly.h"
#include "kernels/triangle_calculus.h"

namespace harmonia::vulkan::detail {

VulkanTriangleOperators::VulkanTriangleOperators(CommandRecorder& recorder,
                                                 const Eigen::MatrixX3i& faces, int vertex_count,
                                                 DevicePrecision precision)
    : recorder_(recorder),
      precision_(precision),
      faces_(faces),
      vertex_count_(vertex_count),
      assembly_(std::make_unique<TriangleAssembly>(recorder, faces, vertex_count, precision)) {}

VulkanTriangleOperators::~VulkanTriangleOperators() = default;

Eigen::SparseMatrix<double> VulkanTriangleOperators::assembled() const {
  return Eigen::SparseMatrix<double>(assembly_->download());
}

Eigen::SparseMatrix<double> VulkanTriangleOperators::cotangent(const Eigen::MatrixX3d& positions) {
  assembly_->assemble_cotangent(positions);
  return assembled();
}

Eigen::SparseMatrix<double> VulkanTriangleOperators::tensor_cotangent(
    const Eigen::MatrixX2d& uv, const harmonia::detail::TriangleTensorRows& tensors) {
  assembly_->assemble_tensor(uv, tensors);
  return assembled();
}

harmonia::detail::QuasiHarmonicOperator VulkanTriangleOperators::quasi_harmonic(
    const Eigen::MatrixX3d& positions, const Eigen::MatrixX2d& uv) {
  assembly_->assemble_quasi_harmonic(positions, uv);
  harmonia::detail::QuasiHarmonicOperator result;
  result.tensors = assembly_->download_tensors();
  result.matrix = assembled();
  return result;
}

Eigen::MatrixXd VulkanTriangleOperators::fragment_poisson_rhs(const Eigen::MatrixX3d& positions,
                                                              const Eigen::MatrixXd& fragments) {
  if (positions.rows() != vertex_count_)
    throw std::invalid_argument("vulkan fragment rhs: " + std::to_string(positions.rows()) +
                                " positions for " + std::to_string(vertex_count_) + " vertices");
  if (calculus_)
    calculus_->set_positions(positions);
  else
    calculus_ = std::make_unique<TriangleCalculus>(recorder_, faces_, positions, precision_);
  VulkanVectors on_device(recorder_, static_cast<int>(fragments.rows()),
                          static_cast<int>(fragments.cols()), precision_);
  on_device.upload(fragments);
  VulkanVectors rhs(recorder_, calculus_->vertex_count(), static_cast<int>(fragments.cols()),
                    precision_);
  calculus_->fragment_poisson_rhs(on_device, rhs);
  return rhs.download();
}

}  // namespace harmonia::vulkan::detail
