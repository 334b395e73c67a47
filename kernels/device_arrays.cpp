#include "kernels/device_arrays.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "harmonia/types.h"
#include "kernels/recorder.h"
#include "kernels/transfers.h"

namespace harmonia::vulkan::detail {
namespace {

std::uint64_t float_bytes(std::uint64_t count) { return count * sizeof(float); }

}  // namespace

std::vector<float> to_float(const double* values, std::size_t count, const char* what) {
  std::vector<float> result(count);
  constexpr double largest = std::numeric_limits<float>::max();
  for (std::size_t k = 0; k < count; ++k) {
    if (std::isfinite(values[k]) && std::abs(values[k]) > largest)
      throw Error(Status::unsupported,
                  std::string(what) + " entry " + std::to_string(k) + " (" +
                      std::to_string(values[k]) +
                      ") is beyond the float32 range of the Vulkan backend; use the CPU backend");
    result[k] = static_cast<float>(values[k]);
  }
  return result;
}

VulkanMatrix::VulkanMatrix(CommandRecorder& transfers,
                           const harmonia::detail::RowMajorSparse& matrix)
    : transfers_(transfers),
      host_(matrix),
      row_offsets_(transfers.context(), (static_cast<std::uint64_t>(matrix.rows()) + 1) * 4,
                   BufferRole::device, "matrix row offsets"),
      columns_(transfers.context(), float_bytes(matrix.nonZeros()), BufferRole::device,
               "matrix column indices"),
      values_(transfers.context(), float_bytes(matrix.nonZeros()), BufferRole::device,
              "matrix values"),
      inverse_diagonal_(transfers.context(), float_bytes(matrix.rows()), BufferRole::device,
                        "Jacobi inverse diagonal") {
  host_.makeCompressed();
  const auto rows = static_cast<std::size_t>(host_.rows());
  std::vector<std::uint32_t> offsets(rows + 1, 0);
  for (std::size_t row = 0; row < rows; ++row) {
    offsets[row + 1] = static_cast<std::uint32_t>(host_.outerIndexPtr()[row + 1]);
    longest_row_ =
        std::max(longest_row_, host_.outerIndexPtr()[row + 1] - host_.outerIndexPtr()[row]);
  }
  const std::vector<std::uint32_t> indices(host_.innerIndexPtr(),
                                           host_.innerIndexPtr() + host_.nonZeros());
  write_buffer(transfers_, row_offsets_, offsets.data(), offsets.size() * 4);
  write_buffer(transfers_, columns_, indices.data(), indices.size() * 4);
  upload_values();
}

void VulkanMatrix::update_values(const Eigen::Ref<const Eigen::VectorXd>& csr_values) {
  if (csr_values.size() != host_.nonZeros())
    throw std::invalid_argument(
        "vulkan backend: update_values: " + std::to_string(csr_values.size()) +
        " values for a pattern of " + std::to_string(host_.nonZeros()));
  Eigen::Map<Eigen::VectorXd>(host_.valuePtr(), host_.nonZeros()) = csr_values;
  upload_values();
}

// Values in fp32, and the inverse diagonal formed in double first (1 where the diagonal is zero
// or absent, as the CPU backend does).
void VulkanMatrix::upload_values() {
  const std::vector<float> values =
      to_float(host_.valuePtr(), static_cast<std::size_t>(host_.nonZeros()), "matrix value");
  write_buffer(transfers_, values_, values.data(), values.size() * 4);
  std::vector<double> inverse(static_cast<std::size_t>(host_.rows()), 1.0);
  for (int row = 0; row < host_.outerSize(); ++row) {
    for (harmonia::detail::RowMajorSparse::InnerIterator entry(host_, row); entry; ++entry)
      if (entry.col() == row && entry.value() != 0.0) inverse[row] = 1.0 / entry.value();
  }
  const std::vector<float> inverse_float =
      to_float(inverse.data(), inverse.size(), "inverse diagonal");
  write_buffer(transfers_, inverse_diagonal_, inverse_float.data(), inverse_float.size() * 4);
}

double VulkanMatrix::mean_row_length() const {
  return host_.rows() > 0 ? static_cast<double>(host_.nonZeros()) / host_.rows() : 0.0;
}

VulkanVectors::VulkanVectors(CommandRecorder& transfers, int rows, int cols)
    : transfers_(transfers),
      rows_(rows),
      cols_(cols),
      buffer_(transfers.context(),
              float_bytes(static_cast<std::uint64_t>(rows) * static_cast<std::uint64_t>(cols)),
              BufferRole::device,
              "vector block (" + std::to_string(rows) + " x " + std::to_string(cols) + ")") {
  if (rows < 0 || cols < 0) throw std::invalid_argument("vulkan backend: negative block shape");
  upload(Eigen::MatrixXd::Zero(rows, cols));
}

void VulkanVectors::upload(const Eigen::Ref<const Eigen::MatrixXd>& values) {
  if (values.rows() != rows_ || values.cols() != cols_)
    throw std::invalid_argument("vulkan backend: upload: block shape differs");
  const Eigen::MatrixXd contiguous = values;  // Column-major, no stride: the device layout.
  const std::vector<float> converted =
      to_float(contiguous.data(), static_cast<std::size_t>(contiguous.size()), "vector");
  write_buffer(transfers_, buffer_, converted.data(), converted.size() * 4);
  host_copy_ = contiguous;
}

Eigen::MatrixXd VulkanVectors::download() const {
  if (host_copy_) return *host_copy_;
  return download_device();
}

Eigen::MatrixXd VulkanVectors::download_device() const {
  Eigen::MatrixXf values(rows_, cols_);
  read_buffer(transfers_, buffer_, values.data(), static_cast<std::uint64_t>(values.size()) * 4);
  return values.cast<double>();
}

}  // namespace harmonia::vulkan::detail
