// The backend-independent normal product M = B diag(d) B^T: computed on the host in double with
// Eigen's sparse product, scattered into the fixed pattern chosen at creation, and handed to the
// backend as new values of an uploaded matrix. Backends with a kernel for it override
// Backend::normal_product (Vulkan: kernels/normal_product.h).

#include <stdexcept>
#include <utility>

#include "backend/backend.h"
#include "backend/cpu_normal_product.h"

namespace harmonia::detail {
namespace {

// The fixed pattern of M: every pair of rows of B that share a column, plus the diagonal entry of
// every non-empty row (zero values).
RowMajorSparse normal_product_pattern(const RowMajorSparse& b) {
  RowMajorSparse ones = b;
  for (Eigen::Index k = 0; k < ones.nonZeros(); ++k) ones.valuePtr()[k] = 1.0;
  RowMajorSparse pattern = ones * ones.transpose();
  pattern.makeCompressed();
  for (Eigen::Index k = 0; k < pattern.nonZeros(); ++k) pattern.valuePtr()[k] = 0.0;
  return pattern;
}

class HostNormalProduct final : public DeviceNormalProduct {
 public:
  HostNormalProduct(Backend& backend, const RowMajorSparse& b,
                    const Eigen::Ref<const Eigen::VectorXd>& diagonal)
      : b_(b), values_(normal_product_pattern(b)) {
    b_.makeCompressed();
    compute(diagonal);
    matrix_ = backend.upload(values_);
  }

  void update(const Eigen::Ref<const Eigen::VectorXd>& b_values,
              const Eigen::Ref<const Eigen::VectorXd>& diagonal) override {
    if (b_values.size() != b_.nonZeros())
      throw std::invalid_argument("normal product: one value per entry of B's pattern is needed");
    std::copy(b_values.data(), b_values.data() + b_values.size(), b_.valuePtr());
    compute(diagonal);
    matrix_->update_values(Eigen::Map<const Eigen::VectorXd>(values_.valuePtr(),
                                                             values_.nonZeros()));
  }

  [[nodiscard]] const DeviceMatrix& matrix() const override { return *matrix_; }
  [[nodiscard]] RowMajorSparse download() const override { return values_; }

 private:
  // M's values into the fixed pattern; the product's pattern is a subset of it (Eigen may leave
  // out entries whose terms are all structurally absent, never add any).
  void compute(const Eigen::Ref<const Eigen::VectorXd>& diagonal) {
    const RowMajorSparse product = cpu_normal_product(b_, diagonal);
    for (Eigen::Index row = 0; row < values_.outerSize(); ++row) {
      RowMajorSparse::InnerIterator slot(values_, row);
      for (; slot; ++slot) slot.valueRef() = 0.0;
      RowMajorSparse::InnerIterator target(values_, row);
      for (RowMajorSparse::InnerIterator entry(product, row); entry; ++entry) {
        while (target && target.col() < entry.col()) ++target;
        if (!target || target.col() != entry.col())
          throw std::logic_error("normal product: an entry outside the pattern of B B^T");
        target.valueRef() = entry.value();
      }
    }
  }

  RowMajorSparse b_;
  RowMajorSparse values_;  // M in its fixed pattern.
  std::unique_ptr<DeviceMatrix> matrix_;
};

}  // namespace

std::unique_ptr<DeviceNormalProduct> Backend::normal_product(
    const RowMajorSparse& b, const Eigen::Ref<const Eigen::VectorXd>& diagonal) {
  if (diagonal.size() != b.cols())
    throw std::invalid_argument("normal product: one weight per column of B is needed");
  return std::make_unique<HostNormalProduct>(*this, b, diagonal);
}

}  // namespace harmonia::detail
