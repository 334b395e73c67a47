#include "kernels/device_arrays.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "harmonia/types.h"
#include "kernels/device_reals.h"
#include "kernels/recorder.h"
#include "kernels/transfers.h"

namespace harmonia::vulkan::detail {
namespace {

std::uint64_t word_bytes(std::uint64_t count) { return count * 4; }

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
                           const harmonia::detail::RowMajorSparse& matrix,
                           DevicePrecision precision)
    : transfers_(transfers),
      precision_(precision),
      host_(matrix),
      row_offsets_(transfers.context(), (static_cast<std::uint64_t>(matrix.rows()) + 1) * 4,
                   BufferRole::device, "matrix row offsets"),
      columns_(transfers.context(), word_bytes(matrix.nonZeros()), BufferRole::device,
               "matrix column indices"),
      values_(transfers.context(), real_bytes(precision, matrix.nonZeros()), BufferRole::device,
              "matrix values"),
      inverse_diagonal_(transfers.context(), real_bytes(precision, matrix.rows()),
                        BufferRole::device, "Jacobi inverse diagonal") {
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
  stale_host_values_ = nullptr;
  upload_values();
}

VulkanMatrix::~VulkanMatrix() = default;

const harmonia::detail::RowMajorSparse& VulkanMatrix::host() const {
  if (stale_host_values_) {
    stale_host_values_(Eigen::Map<Eigen::VectorXd>(host_.valuePtr(), host_.nonZeros()));
    stale_host_values_ = nullptr;
  }
  return host_;
}

void VulkanMatrix::values_written_on_device(HostValues host_values) {
  stale_host_values_ = std::move(host_values);
}

// Values as device reals, and the inverse diagonal formed in double first (1 where the diagonal
// is zero or absent, as the CPU backend does).
void VulkanMatrix::upload_values() {
  const std::vector<std::byte> values = encode_reals(
      host_.valuePtr(), static_cast<std::size_t>(host_.nonZeros()), precision_, "matrix value");
  write_buffer(transfers_, values_, values.data(), values.size());
  std::vector<double> inverse(static_cast<std::size_t>(host_.rows()), 1.0);
  for (int row = 0; row < host_.outerSize(); ++row) {
    for (harmonia::detail::RowMajorSparse::InnerIterator entry(host_, row); entry; ++entry)
      if (entry.col() == row && entry.value() != 0.0) inverse[row] = 1.0 / entry.value();
  }
  const std::vector<std::byte> inverse_reals =
      encode_reals(inverse.data(), inverse.size(), precision_, "inverse diagonal");
  write_buffer(transfers_, inverse_diagonal_, inverse_reals.data(), inverse_reals.size());
}

double VulkanMatrix::mean_row_length() const {
  return host_.rows() > 0 ? static_cast<double>(host_.nonZeros()) / host_.rows() : 0.0;
}

VulkanVectors::VulkanVectors(CommandRecorder& transfers, int rows, int cols,
                             DevicePrecision precision)
    : transfers_(transfers),
      rows_(rows),
      cols_(cols),
      precision_(precision),
      buffer_(transfers.context(),
              real_bytes(precision, static_cast<std::uint64_t>(std::max(rows, 0)) *
                                        static_cast<std::uint64_t>(std::max(cols, 0))),
              BufferRole::device,
              "vector block (" + std::to_string(rows) + " x " + std::to_string(cols) + ")") {
  if (rows < 0 || cols < 0) throw std::invalid_argument("vulkan backend: negative block shape");
  upload(Eigen::MatrixXd::Zero(rows, cols));
}

void VulkanVectors::upload(const Eigen::Ref<const Eigen::MatrixXd>& values) {
  if (values.rows() != rows_ || values.cols() != cols_)
    throw std::invalid_argument("vulkan backend: upload: block shape differs");
  const Eigen::MatrixXd contiguous = values;  // Column-major, no stride: the device layout.
  const std::vector<std::byte> converted = encode_reals(
      contiguous.data(), static_cast<std::size_t>(contiguous.size()), precision_, "vector");
  write_buffer(transfers_, buffer_, converted.data(), converted.size());
  host_copy_ = contiguous;
}

Eigen::MatrixXd VulkanVectors::download() const {
  if (host_copy_) return *host_copy_;
  return download_device();
}

Eigen::MatrixXd VulkanVectors::download_device() const {
  const auto count = static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_);
  std::vector<std::byte> bytes(real_bytes(precision_, count));
  read_buffer(transfers_, buffer_, bytes.data(), bytes.size());
  Eigen::MatrixXd values(rows_, cols_);
  decode_reals(bytes.data(), count, precision_, values.data());
  return values;
}

}  // namespace harmonia::vulkan::detail
