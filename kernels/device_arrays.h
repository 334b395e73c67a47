#pragma once
// Internal: the Vulkan backend's DeviceMatrix and DeviceVectors, in fp32 (the default) or fp64
// on the device (kernels/device_reals.h).
//
// Values arrive in double; in fp32 they are rounded to float on upload (a value beyond float's
// range is refused). A VulkanVectors block remembers the double values it was last given on the
// host (upload, or the result of a refined solve) until a kernel writes it: download() then
// returns those doubles, so iterative refinement on the host is not lost to a final rounding.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "backend/backend.h"
#include "kernels/buffer.h"

namespace harmonia::vulkan::detail {

class CommandRecorder;

// CSR (row offsets, column indices, values) plus the Jacobi inverse diagonal; the
// double-precision matrix stays on the host for residuals in double.
//
// Values may also be written by a kernel (kernels/normal_product.h): the owner records into
// values() and then record_inverse_diagonal(), and says so with values_written_on_device(),
// handing a function that gives the same values in double on the host. That function is only
// called when host() is needed (the residual of a refined solve), so a refresh costs no host
// round trip.
class VulkanMatrix final : public harmonia::detail::DeviceMatrix {
 public:
  // Exact double values of the stored entries, in CSR order.
  using HostValues = std::function<void(Eigen::Ref<Eigen::VectorXd> csr_values)>;

  VulkanMatrix(CommandRecorder& transfers, const harmonia::detail::RowMajorSparse& matrix,
               DevicePrecision precision = DevicePrecision::float32);
  ~VulkanMatrix() override;
  [[nodiscard]] int rows() const override { return static_cast<int>(host_.rows()); }
  [[nodiscard]] int cols() const override { return static_cast<int>(host_.cols()); }
  void update_values(const Eigen::Ref<const Eigen::VectorXd>& csr_values) override;

  // The matrix in double (refreshed through HostValues after a device write).
  [[nodiscard]] const harmonia::detail::RowMajorSparse& host() const override;
  [[nodiscard]] DevicePrecision precision() const { return precision_; }
  [[nodiscard]] const Buffer& row_offsets() const { return row_offsets_; }
  [[nodiscard]] const Buffer& columns() const { return columns_; }
  [[nodiscard]] const Buffer& values() const { return values_; }
  [[nodiscard]] Buffer& values() { return values_; }
  [[nodiscard]] const Buffer& inverse_diagonal() const { return inverse_diagonal_; }
  [[nodiscard]] double mean_row_length() const;
  [[nodiscard]] int longest_row() const { return longest_row_; }

  // Records inverse_diagonal = 1 ./ diag(values) on the device (1 where the diagonal is zero or
  // absent; shaders/inverse_diagonal.comp), after a kernel wrote values().
  void record_inverse_diagonal(CommandRecorder& recorder);
  // The values on the device are newer than the host copy; `host_values` gives them in double.
  void values_written_on_device(HostValues host_values);

 private:
  void upload_values();
  CommandRecorder& transfers_;
  DevicePrecision precision_;
  mutable harmonia::detail::RowMajorSparse host_;
  mutable HostValues stale_host_values_;  // Set while host_'s values are out of date.
  Buffer row_offsets_, columns_, values_, inverse_diagonal_;
  std::unique_ptr<Buffer> diagonal_slots_;  // For record_inverse_diagonal, built on first use.
  int longest_row_ = 0;
};

// A column-major rows x cols block of vectors of device reals.
class VulkanVectors final : public harmonia::detail::DeviceVectors {
 public:
  VulkanVectors(CommandRecorder& transfers, int rows, int cols,
                DevicePrecision precision = DevicePrecision::float32);  // Zeros.
  [[nodiscard]] int rows() const override { return rows_; }
  [[nodiscard]] int cols() const override { return cols_; }
  void upload(const Eigen::Ref<const Eigen::MatrixXd>& values) override;
  [[nodiscard]] Eigen::MatrixXd download() const override;

  [[nodiscard]] DevicePrecision precision() const { return precision_; }
  [[nodiscard]] const Buffer& buffer() const { return buffer_; }
  [[nodiscard]] Buffer& buffer() { return buffer_; }
  // Called by every kernel that writes the block: the host copy no longer matches.
  void written_on_device() { host_copy_.reset(); }
  // Stores `values` on the device and keeps them as the block's double-precision value.
  void set_refined(const Eigen::MatrixXd& values) { upload(values); }
  // The device contents as written by the kernels, widened to double (ignores the host copy).
  [[nodiscard]] Eigen::MatrixXd download_device() const;

 private:
  CommandRecorder& transfers_;
  int rows_, cols_;
  DevicePrecision precision_;
  Buffer buffer_;
  std::optional<Eigen::MatrixXd> host_copy_;
};

// Rounds to float, refusing finite values beyond float's range (they would become infinite).
// `what` names the data in the message.
[[nodiscard]] std::vector<float> to_float(const double* values, std::size_t count,
                                          const char* what);

}  // namespace harmonia::vulkan::detail
