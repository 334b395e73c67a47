// The weighted normal product B D B^T refreshed on the device (kernels/normal_product.h) against
// its Eigen twin (host/backend/cpu_normal_product.h), on lavapipe with validation: random B from 1x1 to
// tens of thousands of rows, odd sizes, empty rows, positive and mixed-sign weights; repeated
// refreshes with new values on the same pattern. Every entry within the declared fp32 bound of
// sum_k |b_ik d_k b_jk| (both directions: no entry of the twin missing from the pattern); exact
// symmetry; the same bits run to run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "backend/cpu_normal_product.h"
#include "kernels/kernel_test_data.h"
#include "kernels/normal_product.h"
#include "kernels/vulkan_backend.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using vulkan::detail::NormalProduct;
using vulkan::detail::VulkanBackend;

class VulkanNormalProduct : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(vulkan_test_context());
  }

  void expect_matches(NormalProduct& product, const RowMajorSparse& b, const Eigen::VectorXd& d) {
    const Eigen::Map<const Eigen::VectorXd> b_values(b.valuePtr(), b.nonZeros());
    product.update(b_values, d);
    const RowMajorSparse actual = product.download();
    const RowMajorSparse expected = detail::cpu_normal_product(b, d);
    const RowMajorSparse magnitude = detail::cpu_normal_product(b.cwiseAbs(), d.cwiseAbs());
    const auto& map = product.map();
    for (int row = 0; row < actual.rows(); ++row) {
      for (int slot = actual.outerIndexPtr()[row]; slot < actual.outerIndexPtr()[row + 1]; ++slot) {
        const int col = actual.innerIndexPtr()[slot];
        const int terms = static_cast<int>(map.slot_offsets[static_cast<std::size_t>(slot) + 1] -
                                           map.slot_offsets[static_cast<std::size_t>(slot)]);
        ASSERT_GE(terms, 1) << "every stored entry has a product behind it";
        ASSERT_LE(std::abs(actual.valuePtr()[slot] - expected.coeff(row, col)),
                  vulkan::detail::normal_product_error_bound(terms) * magnitude.coeff(row, col))
            << "entry (" << row << ", " << col << ") of " << actual.rows();
      }
    }
    for (int row = 0; row < expected.rows(); ++row) {
      const int* begin = actual.innerIndexPtr() + actual.outerIndexPtr()[row];
      const int* end = actual.innerIndexPtr() + actual.outerIndexPtr()[row + 1];
      for (RowMajorSparse::InnerIterator entry(expected, row); entry; ++entry) {
        ASSERT_TRUE(std::binary_search(begin, end, static_cast<int>(entry.col())))
            << "entry (" << row << ", " << entry.col() << ") is missing from the pattern";
      }
    }
    const RowMajorSparse transposed = actual.transpose();
    EXPECT_EQ((actual - transposed).norm(), 0.0) << "M(i, j) and M(j, i) are the same bits";
    product.update(b_values, d);
    const RowMajorSparse again = product.download();
    EXPECT_EQ(0, std::memcmp(actual.valuePtr(), again.valuePtr(),
                             sizeof(double) * static_cast<std::size_t>(actual.nonZeros())));
  }

  std::unique_ptr<VulkanBackend> gpu_;
};

Eigen::VectorXd random_weights(Eigen::Index size, bool positive, std::uint32_t seed) {
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> value(positive ? 0.1 : -1.0, positive ? 10.0 : 1.0);
  Eigen::VectorXd weights(size);
  for (Eigen::Index k = 0; k < size; ++k) weights[k] = value(generator);
  return weights;
}

TEST_F(VulkanNormalProduct, SmallAndOddShapes) {
  std::uint32_t seed = 1;
  for (const auto& [rows, cols, mean] :
       {std::tuple{1, 1, 1}, std::tuple{7, 13, 3}, std::tuple{13, 7, 2}, std::tuple{301, 977, 5}}) {
    const RowMajorSparse b = random_sparse(rows, cols, mean, seed++);
    auto product = gpu_->normal_product(b);
    expect_matches(*product, b, random_weights(cols, true, seed++));
    expect_matches(*product, b, random_weights(cols, false, seed++));
  }
}

TEST_F(VulkanNormalProduct, EmptyRowsGiveEmptyRowsAndColumns) {
  RowMajorSparse b(3, 4);
  b.insert(0, 1) = 2.0;
  b.insert(2, 1) = 3.0;
  b.insert(2, 3) = -1.0;
  b.makeCompressed();
  auto product = gpu_->normal_product(b);
  const Eigen::Vector4d d(1.0, 0.5, 7.0, 2.0);
  expect_matches(*product, b, d);
  const RowMajorSparse m = product->download();
  EXPECT_EQ(m.nonZeros(), 4) << "(0,0), (0,2), (2,0), (2,2); row 1 is empty";
  EXPECT_EQ(m.coeff(0, 2), 2.0 * 0.5 * 3.0);
  EXPECT_EQ(m.coeff(2, 2), 3.0 * 0.5 * 3.0 + 2.0);
}

TEST_F(VulkanNormalProduct, NewValuesOnTheSamePatternEveryStep) {
  // Like a Newton loop: the pattern is fixed, B's values and the weights change each step.
  RowMajorSparse b = random_sparse(20011, 60013, 3, 99);
  auto product = gpu_->normal_product(b);
  for (std::uint32_t step = 0; step < 3; ++step) {
    const Eigen::VectorXd fresh = random_block(static_cast<int>(b.nonZeros()), 1, 200 + step);
    Eigen::Map<Eigen::VectorXd>(b.valuePtr(), b.nonZeros()) = fresh;
    expect_matches(*product, b, random_weights(b.cols(), true, 300 + step));
  }
}

TEST_F(VulkanNormalProduct, WrongSizesAreRefused) {
  const RowMajorSparse b = random_sparse(5, 6, 2, 4);
  auto product = gpu_->normal_product(b);
  EXPECT_THROW(product->update(Eigen::VectorXd::Zero(b.nonZeros()), Eigen::VectorXd::Zero(5)),
               std::invalid_argument);
}

}  // namespace
}  // namespace harmonia::testing
