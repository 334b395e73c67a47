#pragma once
// Internal: the Vulkan backend's Backend::normal_product. M = B D B^T is refreshed by the
// normal product kernel (kernels/normal_product.h) straight into the value buffer of a
// VulkanMatrix with M's fixed pattern, followed by the Jacobi inverse diagonal on the device, in
// one submission: the backend's spmv, jacobi, pcg and minres then use the new M without a host
// round trip. M in double is only formed on the host (from the B and d given to update) when a
// refined solve needs its residual in double.
// Host twin: host/backend/host_normal_product.cpp.

#include <Eigen/Core>

#include "backend/backend.h"
#include "kernels/device_arrays.h"
#include "kernels/normal_product.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

class VulkanNormalProduct final : public harmonia::detail::DeviceNormalProduct {
 public:
  // `b` gives the pattern and the first values of B, `diagonal` the first d (one per column of
  // B); M is computed at once. Submits on `recorder`, which must outlive this object.
  VulkanNormalProduct(CommandRecorder& recorder, const harmonia::detail::RowMajorSparse& b,
                      const Eigen::Ref<const Eigen::VectorXd>& diagonal, DevicePrecision precision);

  void update(const Eigen::Ref<const Eigen::VectorXd>& b_values,
              const Eigen::Ref<const Eigen::VectorXd>& diagonal) override;
  [[nodiscard]] const harmonia::detail::DeviceMatrix& matrix() const override { return matrix_; }
  // M as the kernel left it (device reals widened to double), in M's fixed pattern.
  [[nodiscard]] harmonia::detail::RowMajorSparse download() const override;

 private:
  // M = B D B^T in double from the host copies of B and d, in the fixed pattern's CSR order.
  void host_values(Eigen::Ref<Eigen::VectorXd> csr_values) const;

  CommandRecorder& recorder_;
  NormalProduct product_;
  VulkanMatrix matrix_;
  harmonia::detail::RowMajorSparse b_;  // The latest B (pattern fixed).
  Eigen::VectorXd diagonal_;            // The latest d.
};

}  // namespace harmonia::vulkan::detail
