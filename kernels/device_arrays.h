#pragma once
// Internal: the Vulkan backend's DeviceMatrix and DeviceVectors, in fp32 on the device.
//
// Values arrive in double and are rounded to float on upload (a value beyond float's range is
// refused). A VulkanVectors block remembers the double values it was last given on the host
// (upload, or the result of a refined solve) until a kernel writes it: download() then returns
// those doubles, so iterative refinement on the host is not lost to a final rounding.

#include <cstdint>
#include <optional>
#include <vector>

#include "detail/backend.h"
#include "kernels/buffer.h"

namespace harmonia::vulkan::detail {

class CommandRecorder;

// CSR in fp32 (row offsets, column indices, values) plus the Jacobi inverse diagonal; the
// double-precision matrix stays on the host for residuals in double.
class VulkanMatrix final : public harmonia::detail::DeviceMatrix {
 public:
  VulkanMatrix(CommandRecorder& transfers, const harmonia::detail::RowMajorSparse& matrix);
  [[nodiscard]] int rows() const override { return static_cast<int>(host_.rows()); }
  [[nodiscard]] int cols() const override { return static_cast<int>(host_.cols()); }
  void update_values(const Eigen::Ref<const Eigen::VectorXd>& csr_values) override;

  [[nodiscard]] const harmonia::detail::RowMajorSparse& host() const { return host_; }
  [[nodiscard]] const Buffer& row_offsets() const { return row_offsets_; }
  [[nodiscard]] const Buffer& columns() const { return columns_; }
  [[nodiscard]] const Buffer& values() const { return values_; }
  [[nodiscard]] const Buffer& inverse_diagonal() const { return inverse_diagonal_; }
  [[nodiscard]] double mean_row_length() const;
  [[nodiscard]] int longest_row() const { return longest_row_; }

 private:
  void upload_values();
  CommandRecorder& transfers_;
  harmonia::detail::RowMajorSparse host_;
  Buffer row_offsets_, columns_, values_, inverse_diagonal_;
  int longest_row_ = 0;
};

// A column-major rows x cols block of fp32 vectors.
class VulkanVectors final : public harmonia::detail::DeviceVectors {
 public:
  VulkanVectors(CommandRecorder& transfers, int rows, int cols);  // Zeros.
  [[nodiscard]] int rows() const override { return rows_; }
  [[nodiscard]] int cols() const override { return cols_; }
  void upload(const Eigen::Ref<const Eigen::MatrixXd>& values) override;
  [[nodiscard]] Eigen::MatrixXd download() const override;

  [[nodiscard]] const Buffer& buffer() const { return buffer_; }
  [[nodiscard]] Buffer& buffer() { return buffer_; }
  // Called by every kernel that writes the block: the host copy no longer matches.
  void written_on_device() { host_copy_.reset(); }
  // Stores `values` on the device and keeps them as the block's double-precision value.
  void set_refined(const Eigen::MatrixXd& values) { upload(values); }
  // The fp32 contents as written by the kernels (ignores the host copy).
  [[nodiscard]] Eigen::MatrixXd download_device() const;

 private:
  CommandRecorder& transfers_;
  int rows_, cols_;
  Buffer buffer_;
  std::optional<Eigen::MatrixXd> host_copy_;
};

// Rounds to float, refusing finite values beyond float's range (they would become infinite).
// `what` names the data in the message.
[[nodiscard]] std::vector<float> to_float(const double* values, std::size_t count,
                                          const char* what);

}  // namespace harmonia::vulkan::detail
