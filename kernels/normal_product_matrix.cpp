#include "kernels/normal_product_matrix.h"

#include <stdexcept>
#include <string>

#include "backend/cpu_normal_product.h"
#include "kernels/transfers.h"

namespace harmonia::vulkan::detail {
namespace {

harmonia::detail::RowMajorSparse compressed(const harmonia::detail::RowMajorSparse& b) {
  harmonia::detail::RowMajorSparse copy = b;
  copy.makeCompressed();
  return copy;
}

}  // namespace

VulkanNormalProduct::VulkanNormalProduct(CommandRecorder& recorder,
                                         const harmonia::detail::RowMajorSparse& b,
                                         const Eigen::Ref<const Eigen::VectorXd>& diagonal,
                                         DevicePrecision precision)
    : recorder_(recorder),
      product_(recorder, compressed(b), precision),
      matrix_(recorder, product_.map().pattern, precision),
      b_(compressed(b)) {
  update(Eigen::Map<const Eigen::VectorXd>(b_.valuePtr(), b_.nonZeros()), diagonal);
}

void VulkanNormalProduct::update(const Eigen::Ref<const Eigen::VectorXd>& b_values,
                                 const Eigen::Ref<const Eigen::VectorXd>& diagonal) {
  if (b_values.size() != b_.nonZeros() || diagonal.size() != b_.cols())
    throw std::invalid_argument("normal product: " + std::to_string(b_values.size()) +
                                " values and " + std::to_string(diagonal.size()) +
                                " weights for a B with " + std::to_string(b_.nonZeros()) +
                                " entries and " + std::to_string(b_.cols()) + " columns");
  product_.upload(b_values, diagonal);  // Checks the range before the host copies change.
  Eigen::Map<Eigen::VectorXd>(b_.valuePtr(), b_.nonZeros()) = b_values;
  diagonal_ = diagonal;
  recorder_.begin();
  product_.record(recorder_, matrix_.values());
  matrix_.record_inverse_diagonal(recorder_);
  recorder_.end();
  recorder_.submit_and_wait();
  matrix_.values_written_on_device(
      [this](Eigen::Ref<Eigen::VectorXd> csr_values) { host_values(csr_values); });
}

harmonia::detail::RowMajorSparse VulkanNormalProduct::download() const {
  return read_pattern_values(recorder_, matrix_.values(), product_.map().pattern,
                             matrix_.precision());
}

void VulkanNormalProduct::host_values(Eigen::Ref<Eigen::VectorXd> csr_values) const {
  const harmonia::detail::RowMajorSparse& pattern = product_.map().pattern;
  const harmonia::detail::RowMajorSparse product =
      harmonia::detail::cpu_normal_product(b_, diagonal_);
  csr_values.setZero();
  // The product's pattern is a subset of the fixed one (both rows-sharing-a-column).
  for (int row = 0; row < pattern.rows(); ++row) {
    int slot = pattern.outerIndexPtr()[row];
    const int end = pattern.outerIndexPtr()[row + 1];
    for (harmonia::detail::RowMajorSparse::InnerIterator entry(product, row); entry; ++entry) {
      while (slot < end && pattern.innerIndexPtr()[slot] < entry.col()) ++slot;
      if (slot == end || pattern.innerIndexPtr()[slot] != entry.col())
        throw std::logic_error("normal product: an entry outside the pattern of B B^T");
      csr_values[slot] = entry.value();
    }
  }
}

}  // namespace harmonia::vulkan::detail
