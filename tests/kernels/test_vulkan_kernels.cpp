// Every Vulkan kernel against its Eigen twin (CpuBackend), on lavapipe with validation: SpMV (both
// variants, several right-hand sides, empty rows, rectangular, up to ~1M rows), dot, axpy, xpay,
// copy, scale, Jacobi; error bounds derived from fp32 rounding (declared next to each kernel);
// bit-identical results run to run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "fallback/cpu_backend.h"
#include "kernels/context_impl.h"
#include "kernels/device_arrays.h"
#include "kernels/kernel_test_data.h"
#include "kernels/reduction.h"
#include "kernels/spmv.h"
#include "kernels/vector_ops.h"
#include "kernels/vulkan_backend.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using detail::CpuBackend;
using vulkan::detail::VulkanBackend;
using vulkan::detail::VulkanMatrix;

bool bit_identical(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) == 0;
}

class VulkanKernels : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(vulkan_test_context());
  }
  // y = A x on both backends; every entry within spmv_error_bound of sum_j |a_ij x_j|.
  void expect_spmv_matches(const RowMajorSparse& a, int block_columns, std::uint32_t seed) {
    const Eigen::MatrixXd x = random_block(static_cast<int>(a.cols()), block_columns, seed);
    const auto matrix = gpu_->upload(a);
    const auto x_gpu = gpu_->upload(x);
    const auto y_gpu = gpu_->allocate(static_cast<int>(a.rows()), block_columns);
    gpu_->spmv(*matrix, *x_gpu, *y_gpu);
    const Eigen::MatrixXd y = y_gpu->download();

    const Eigen::MatrixXd expected = a * x;
    const Eigen::MatrixXd magnitude = a.cwiseAbs() * x.cwiseAbs();
    const double bound =
        vulkan::detail::spmv_error_bound(static_cast<const VulkanMatrix&>(*matrix).longest_row());
    double worst = 0.0;
    for (Eigen::Index c = 0; c < y.cols(); ++c) {
      for (Eigen::Index i = 0; i < y.rows(); ++i) {
        const double error = std::abs(y(i, c) - expected(i, c));
        worst = std::max(worst, magnitude(i, c) > 0.0 ? error / magnitude(i, c) : error);
        ASSERT_LE(error, bound * magnitude(i, c))
            << "row " << i << " column " << c << " of " << a.rows() << "x" << a.cols();
      }
    }
    // Same input, same bits.
    gpu_->spmv(*matrix, *x_gpu, *y_gpu);
    EXPECT_TRUE(bit_identical(y, y_gpu->download()));
  }

  std::unique_ptr<VulkanBackend> gpu_;
  CpuBackend cpu_;
};

TEST_F(VulkanKernels, WorkgroupShapeComesFromTheDevice) {
  const auto& impl = gpu_->context().impl();
  const std::uint32_t width = impl.workgroup_size;
  EXPECT_EQ(width & (width - 1), 0u) << "tree reductions need a power of two";
  EXPECT_LE(width, impl.limits.maxComputeWorkGroupSize[0]);
  EXPECT_LE(impl.lanes_per_row, std::min(impl.info.subgroup_size, 32u));
  EXPECT_EQ(width % impl.lanes_per_row, 0u);
  EXPECT_NE(gpu_->description().find("llvmpipe"), std::string::npos) << gpu_->description();
}

TEST_F(VulkanKernels, SpmvOneRowPerThreadOnRandomMatrices) {
  for (const int rows : {1, 2, 7, 255, 1001, 40009}) {
    const RowMajorSparse a = random_sparse(rows, rows, 4, 11u + static_cast<std::uint32_t>(rows));
    ASSERT_LT(static_cast<double>(a.nonZeros()) / rows,
              vulkan::detail::spmv_lanes_min_mean_row_length);
    for (const int k : {1, 2, 3}) expect_spmv_matches(a, k, 5u * static_cast<std::uint32_t>(k));
  }
}

TEST_F(VulkanKernels, SpmvOneSubgroupPerRowOnLongRows) {
  for (const int rows : {1, 5, 999, 20011}) {
    const RowMajorSparse a = random_sparse(rows, 997, 40, 3u + static_cast<std::uint32_t>(rows));
    if (rows > 1) {
      ASSERT_GE(static_cast<double>(a.nonZeros()) / rows,
                vulkan::detail::spmv_lanes_min_mean_row_length);
    }
    for (const int k : {1, 2}) expect_spmv_matches(a, k, 9u * static_cast<std::uint32_t>(k));
  }
}

TEST_F(VulkanKernels, SpmvRectangularAndEmptyRows) {
  RowMajorSparse a = random_sparse(301, 77, 3, 8u);
  // Every third row emptied: those entries of y must be exactly zero.
  for (int row = 0; row < a.rows(); row += 3) a.row(row) *= 0.0;
  a.prune(0.0);
  a.makeCompressed();
  expect_spmv_matches(a, 2, 4u);
  const auto matrix = gpu_->upload(a);
  const auto x = gpu_->upload(random_block(77, 2, 1u));
  const auto y = gpu_->allocate(301, 2);
  gpu_->spmv(*matrix, *x, *y);
  const Eigen::MatrixXd values = y->download();
  for (int row = 0; row < a.rows(); row += 3) EXPECT_EQ(values.row(row).norm(), 0.0) << row;
}

TEST_F(VulkanKernels, SpmvOnMeshLaplacians) {
  for (const int rings : {3, 40}) expect_spmv_matches(hemisphere_laplacian(rings), 2, 17u);
}

TEST_F(VulkanKernels, SpmvOnAMillionRowLaplacian) {
  const RowMajorSparse a = hemisphere_laplacian(577);  // 1 + 3 * 577 * 578 = 1,000,519 rows.
  ASSERT_GT(a.rows(), 1'000'000);
  expect_spmv_matches(a, 2, 23u);
}

TEST_F(VulkanKernels, DotMatchesEigenWithinTheTreeBound) {
  for (const int rows : {0, 1, 2, 255, 256, 257, 1001, 65537, 1'000'003}) {
    for (const int k : {1, 3}) {
      const Eigen::MatrixXd x = random_block(rows, k, 31u), y = random_block(rows, k, 37u);
      const auto x_gpu = gpu_->upload(x), y_gpu = gpu_->upload(y);
      const Eigen::VectorXd result = gpu_->dot(*x_gpu, *y_gpu);
      const Eigen::VectorXd expected = x.cwiseProduct(y).colwise().sum().transpose();
      const Eigen::VectorXd magnitude = x.cwiseAbs().cwiseProduct(y.cwiseAbs()).colwise().sum();
      const double bound =
          vulkan::detail::dot_error_bound(static_cast<std::uint64_t>(rows),
                                          vulkan::detail::reduction_shape(gpu_->context().impl()));
      ASSERT_EQ(result.size(), k);
      for (int c = 0; c < k; ++c)
        EXPECT_LE(std::abs(result[c] - expected[c]), bound * magnitude[c])
            << rows << " rows, column " << c;
      // The fixed reduction order gives the same bits every run.
      const Eigen::VectorXd again = gpu_->dot(*x_gpu, *y_gpu);
      EXPECT_TRUE(bit_identical(result, again)) << rows << " rows";
    }
  }
}

TEST_F(VulkanKernels, VectorUpdatesMatchEigen) {
  const double bound = vulkan::detail::linear_combination_error_bound;
  for (const int rows : {1, 3, 1000, 70001}) {
    const Eigen::MatrixXd x = random_block(rows, 2, 41u), y = random_block(rows, 2, 43u);
    const Eigen::Vector2d coefficients(0.75, -2.5);
    const auto x_gpu = gpu_->upload(x);
    const auto expect_near = [&](const Eigen::MatrixXd& result, const Eigen::MatrixXd& expected,
                                 const Eigen::MatrixXd& magnitude, const char* operation) {
      const Eigen::MatrixXd error = (result - expected).cwiseAbs();
      for (Eigen::Index k = 0; k < error.size(); ++k)
        ASSERT_LE(error.data()[k], bound * magnitude.data()[k]) << operation << " entry " << k;
    };
    auto y_gpu = gpu_->upload(y);
    gpu_->axpy(coefficients, *x_gpu, *y_gpu);
    expect_near(y_gpu->download(), y + x * coefficients.asDiagonal(),
                y.cwiseAbs() + x.cwiseAbs() * coefficients.cwiseAbs().asDiagonal(), "axpy");
    y_gpu = gpu_->upload(y);
    gpu_->xpay(*x_gpu, coefficients, *y_gpu);
    expect_near(y_gpu->download(), x + y * coefficients.asDiagonal(),
                x.cwiseAbs() + y.cwiseAbs() * coefficients.cwiseAbs().asDiagonal(), "xpay");
    y_gpu = gpu_->upload(y);
    gpu_->scale(coefficients, *y_gpu);
    expect_near(y_gpu->download(), y * coefficients.asDiagonal(),
                y.cwiseAbs() * coefficients.cwiseAbs().asDiagonal(), "scale");
    // copy rounds to float and nothing else.
    gpu_->copy(*x_gpu, *y_gpu);
    EXPECT_TRUE(bit_identical(y_gpu->download(), x.cast<float>().cast<double>()));
  }
}

TEST_F(VulkanKernels, JacobiMatchesEigen) {
  for (const int rings : {2, 30}) {
    RowMajorSparse a = hemisphere_laplacian(rings);
    // A zero diagonal entry: Jacobi leaves that row unscaled, as the CPU backend does.
    a.coeffRef(1, 1) = 0.0;
    const Eigen::MatrixXd r = random_block(static_cast<int>(a.rows()), 2, 47u);
    const auto a_gpu = gpu_->upload(a);
    const auto r_gpu = gpu_->upload(r);
    const auto z_gpu = gpu_->allocate(static_cast<int>(a.rows()), 2);
    gpu_->jacobi(*a_gpu, *r_gpu, *z_gpu);
    const auto a_cpu = cpu_.upload(a);
    const auto r_cpu = cpu_.upload(r);
    const auto z_cpu = cpu_.allocate(static_cast<int>(a.rows()), 2);
    cpu_.jacobi(*a_cpu, *r_cpu, *z_cpu);
    const Eigen::MatrixXd expected = z_cpu->download(), result = z_gpu->download();
    for (Eigen::Index k = 0; k < expected.size(); ++k)
      ASSERT_LE(std::abs(result.data()[k] - expected.data()[k]),
                vulkan::detail::jacobi_error_bound * std::abs(expected.data()[k]))
          << "entry " << k;
    EXPECT_EQ(result.row(1), r.row(1).cast<float>().cast<double>());
  }
}

TEST_F(VulkanKernels, UpdatedMatrixValuesAreUsed) {
  RowMajorSparse a = hemisphere_laplacian(6);
  const auto matrix = gpu_->upload(a);
  a *= 3.0;
  matrix->update_values(Eigen::Map<const Eigen::VectorXd>(a.valuePtr(), a.nonZeros()));
  expect_spmv_matches(a, 1, 3u);  // Reference check of the path itself.
  const auto x = gpu_->upload(random_block(static_cast<int>(a.rows()), 1, 5u));
  const auto y = gpu_->allocate(static_cast<int>(a.rows()), 1);
  gpu_->spmv(*matrix, *x, *y);
  const Eigen::VectorXd expected = a * x->download();
  EXPECT_LE((y->download().col(0) - expected).norm(), 1e-5 * expected.norm());
  EXPECT_THROW(matrix->update_values(Eigen::VectorXd::Zero(3)), std::invalid_argument);
}

TEST_F(VulkanKernels, DownloadKeepsDoublesUntilAKernelWrites) {
  const Eigen::MatrixXd values = random_block(33, 2, 53u);
  const auto block = gpu_->upload(values);
  EXPECT_TRUE(bit_identical(block->download(), values));  // The uploaded doubles.
  gpu_->scale(Eigen::Vector2d::Ones(), *block);           // A kernel writes it: fp32 now.
  EXPECT_TRUE(bit_identical(block->download(), values.cast<float>().cast<double>()));
}

TEST_F(VulkanKernels, EmptyBlocksAreHarmless) {
  const auto x = gpu_->allocate(0, 2), y = gpu_->allocate(0, 2);
  EXPECT_EQ(gpu_->dot(*x, *y), Eigen::Vector2d::Zero());
  gpu_->axpy(Eigen::Vector2d::Ones(), *x, *y);
  EXPECT_EQ(y->download().size(), 0);
}

}  // namespace
}  // namespace harmonia::testing
