// The batched block-diagonal PCG on the device (kernels/block_pcg.h, VulkanBackend::block_pcg)
// against the CPU reference (Backend::block_pcg: PCG on each block alone) on lavapipe with the
// validation layer on: the same batch solved to the same per-block tolerance, solutions within the
// tolerance times each block's condition number, iteration counts per block like the CPU's (equal
// in fp64 up to the order of the sums; in fp32 up to the rounding of the recurrences), a block that
// is not positive definite failing alone, the block structure checked, the cross-check backend
// forwarding the solve, and 200 small blocks iterating together, one submission per check
// interval.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>

#include "backend/backend.h"
#include "backend/block_diagonal_systems.h"
#include "fallback/cpu_backend.h"
#include "kernels/block_pcg.h"
#include "kernels/float64_test_context.h"
#include "kernels/vulkan_backend.h"
#include "solve/cross_check_backend.h"
#include "support/conditioning.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

using detail::Backend;
using detail::BlockSolveStats;
using detail::IterativeSettings;
using detail::RowMajorSparse;
using vulkan::detail::VulkanBackend;

constexpr double eps = std::numeric_limits<double>::epsilon();

struct BlockRun {
  BlockSolveStats stats;
  Eigen::MatrixXd x;
};

BlockRun block_pcg(Backend& backend, const BlockBatch& batch, const IterativeSettings& settings,
                   const RowMajorSparse* matrix = nullptr) {
  const auto a = backend.upload(matrix != nullptr ? *matrix : batch.matrix);
  const auto b = backend.upload(batch.rhs);
  const auto x =
      backend.allocate(static_cast<int>(batch.rhs.rows()), static_cast<int>(batch.rhs.cols()));
  BlockRun run;
  run.stats = backend.block_pcg(*a, batch.rows, *b, *x, settings, {});
  run.x = x->download();
  return run;
}

// ||b_k - A_kk x_k|| / ||b_k|| of block k, column c, in double.
double block_residual(const BlockBatch& batch, const Eigen::MatrixXd& x, int k, int c) {
  const Eigen::VectorXd b = batch.segment(batch.rhs, k).col(c);
  const Eigen::VectorXd r = b - batch.blocks[k] * batch.segment(x, k).col(c);
  return r.norm() / b.norm();
}

// Both solutions are within cond(A_k) (tolerance + rounding) of the exact one.
double agreement_bound(const BlockBatch& batch, int k, double tolerance) {
  return 2.0 * condition_bound(batch.blocks[k]) * (tolerance + 8 * eps);
}

// Checks a device run against the CPU reference block by block.
void expect_matches_reference(const BlockBatch& batch, const BlockRun& device,
                              const BlockRun& reference, double tolerance) {
  ASSERT_EQ(device.stats.status, Status::ok) << device.stats.message;
  ASSERT_EQ(reference.stats.status, Status::ok) << reference.stats.message;
  for (int k = 0; k < batch.count(); ++k) {
    if (batch.rows.size(k) == 0) continue;
    for (int c = 0; c < batch.rhs.cols(); ++c) {
      EXPECT_EQ(device.stats.system(k, c).status, Status::ok) << device.stats.system(k, c).message;
      if (batch.segment(batch.rhs, k).col(c).norm() == 0.0) {
        EXPECT_EQ(batch.segment(device.x, k).col(c).cwiseAbs().maxCoeff(), 0.0) << "block " << k;
        continue;
      }
      const Eigen::MatrixXd b = batch.segment(batch.rhs, k).col(c);
      const Eigen::MatrixXd x = batch.segment(device.x, k).col(c);
      EXPECT_LE(block_residual(batch, device.x, k, c),
                tolerance + residual_rounding(batch.blocks[k], x, b))
          << "block " << k << ", column " << c;
      const Eigen::VectorXd expected = batch.segment(reference.x, k).col(c);
      EXPECT_LE((x.col(0) - expected).norm() / expected.norm(),
                agreement_bound(batch, k, tolerance))
          << "block " << k << ", column " << c;
    }
  }
}

class VulkanBlockPcg : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(vulkan_test_context());
  }
  std::unique_ptr<VulkanBackend> gpu_;
  detail::CpuBackend cpu_;
};

TEST_F(VulkanBlockPcg, MatchesTheCpuReferenceBelowFloat32Reach) {
  const BlockBatch batch = mixed_batch(2);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;  // Refinement in double per block gets there.
  const BlockRun device = block_pcg(*gpu_, batch, settings);
  const BlockRun reference = block_pcg(cpu_, batch, settings);
  expect_matches_reference(batch, device, reference, settings.relative_tolerance);
}

TEST_F(VulkanBlockPcg, IteratesLikeTheCpuWithinFloat32Reach) {
  const BlockBatch batch = mixed_batch(2);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-5;  // One device round: the counts compare directly.
  const BlockRun device = block_pcg(*gpu_, batch, settings);
  const BlockRun reference = block_pcg(cpu_, batch, settings);
  expect_matches_reference(batch, device, reference, settings.relative_tolerance);
  for (int k = 0; k < batch.count(); ++k) {
    // How far fp32 rounding can lead the recurrences astray: u times the condition number of the
    // Jacobi-preconditioned block, the matrix PCG actually iterates with.
    const double drift = 0x1p-24 * jacobi_condition_bound(batch.blocks[k]);
    for (int c = 0; c < 2; ++c) {
      const int cpu = reference.stats.system(k, c).iterations;
      const int gpu = device.stats.system(k, c).iterations;
      if (drift <= 1e-3) {
        // Rounding only shifts where a residual crosses its threshold, by a step or two.
        EXPECT_NEAR(gpu, cpu, 2 + 0.1 * cpu) << "block " << k << ", column " << c;
      } else {
        // The ill-conditioned grid (u cond about 1e-2): fp32 CG loses orthogonality and converges
        // later (1.7 to 1.9 times the steps on lavapipe), but it is a delay, not a stall.
        EXPECT_GE(gpu, cpu - 2) << "block " << k << ", column " << c;
        EXPECT_LE(gpu, 3 * cpu) << "block " << k << ", column " << c;
      }
    }
  }
  // Per-block step lengths: the 1 x 1 and the diagonal block take one step each, as on the CPU.
  EXPECT_EQ(device.stats.system(2).iterations, 1);
  EXPECT_EQ(device.stats.system(5).iterations, 1);
}

TEST_F(VulkanBlockPcg, ABlockThatIsNotPositiveDefiniteFailsAlone) {
  BlockBatch batch = mixed_batch(1);
  batch.blocks[6] = -batch.blocks[6];
  batch = assemble_batch(batch.blocks, batch.rhs);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-9;
  const BlockRun device = block_pcg(*gpu_, batch, settings);
  EXPECT_EQ(device.stats.status, Status::numerical_failure);
  EXPECT_NE(device.stats.message.find("block 6"), std::string::npos) << device.stats.message;
  EXPECT_NE(device.stats.message.find("not positive definite"), std::string::npos)
      << device.stats.message;
  const BlockRun reference = block_pcg(cpu_, batch, settings);
  EXPECT_EQ(reference.stats.status, Status::numerical_failure);
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(device.stats.system(k).status, Status::ok) << device.stats.system(k).message;
    if (batch.rows.size(k) == 0 || batch.segment(batch.rhs, k).norm() == 0.0) continue;
    const Eigen::VectorXd expected = batch.segment(reference.x, k);
    EXPECT_LE((batch.segment(device.x, k) - expected).norm() / expected.norm(),
              agreement_bound(batch, k, settings.relative_tolerance))
        << "block " << k;
  }
}

TEST_F(VulkanBlockPcg, RejectsAnEntryOutsideItsBlock) {
  const BlockBatch batch = mixed_batch(1);
  RowMajorSparse coupled = batch.matrix;
  coupled.coeffRef(5, 30) = -0.1;
  coupled.coeffRef(30, 5) = -0.1;
  coupled.makeCompressed();
  const BlockRun device = block_pcg(*gpu_, batch, {}, &coupled);
  EXPECT_EQ(device.stats.status, Status::invalid_input);
  EXPECT_NE(device.stats.message.find("entry (row 5, column 30) lies outside block 0 (rows 0..19)"),
            std::string::npos)
      << device.stats.message;
}

TEST_F(VulkanBlockPcg, IsBitIdenticalForEveryCheckInterval) {
  const BlockBatch batch = mixed_batch(2);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-8;
  const BlockRun every_eight = block_pcg(*gpu_, batch, settings);
  settings.check_every = 1;  // Converged blocks are frozen on the device, so the batch length
  const BlockRun every_one = block_pcg(*gpu_, batch, settings);  // does not change a bit.
  ASSERT_EQ(every_eight.stats.status, Status::ok) << every_eight.stats.message;
  EXPECT_EQ(std::memcmp(every_eight.x.data(), every_one.x.data(),
                        sizeof(double) * static_cast<std::size_t>(every_one.x.size())),
            0);
  for (std::size_t s = 0; s < every_one.stats.systems.size(); ++s)
    EXPECT_EQ(every_eight.stats.systems[s].iterations, every_one.stats.systems[s].iterations);
}

TEST_F(VulkanBlockPcg, TheCrossCheckBackendComparesIt) {
  const BlockBatch batch = mixed_batch(1);
  detail::CrossCheckBackend checked(std::make_unique<VulkanBackend>(vulkan_test_context()));
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;
  const BlockRun run = block_pcg(checked, batch, settings);
  ASSERT_EQ(run.stats.status, Status::ok) << run.stats.message;
  // Both solve to 1e-10; the worst block (condition about 8e4 with margin) bounds the difference.
  double worst = 0.0;
  for (int k = 0; k < batch.count(); ++k)
    if (batch.rows.size(k) > 0) worst = std::max(worst, agreement_bound(batch, k, 1e-10));
  EXPECT_GT(checked.cross_check_error(), 0.0);
  EXPECT_LE(checked.cross_check_error(), worst);
}

// 200 charts' worth of systems: one device solve (no refinement), counting submissions.
TEST_F(VulkanBlockPcg, TwoHundredBlocksShareOneSubmissionPerCheckInterval) {
  const BlockBatch batch = many_small_blocks(200, 1, 7);
  const double tolerance = 1e-5;
  const auto a = gpu_->upload(batch.matrix);
  const auto b = gpu_->upload(batch.rhs);
  const auto& matrix = dynamic_cast<const vulkan::detail::VulkanMatrix&>(*a);
  const auto& rhs = dynamic_cast<const vulkan::detail::VulkanVectors&>(*b);
  vulkan::Context::Impl& context = gpu_->context().impl();
  vulkan::detail::CommandRecorder transfers(context);
  const vulkan::detail::DeviceBlocks blocks(transfers, batch.rows, batch.matrix.rows());
  Eigen::VectorXd thresholds(batch.count());
  for (int k = 0; k < batch.count(); ++k)
    thresholds[k] = tolerance * batch.segment(batch.rhs, k).norm();
  const bool unified = gpu_->context().device().unified_memory;
  for (const int check_every : {1, 8}) {
    const auto x = gpu_->allocate(static_cast<int>(batch.rhs.rows()), 1);
    auto& solution = dynamic_cast<vulkan::detail::VulkanVectors&>(*x);
    const std::uint64_t before = context.submission_count();
    const vulkan::detail::DeviceBlockPcgResult result = vulkan::detail::run_device_block_pcg(
        context, matrix, blocks, rhs, solution, thresholds, 1000, check_every, {}, 0, 1000);
    const std::uint64_t submissions = context.submission_count() - before;
    ASSERT_FALSE(result.cancelled);
    ASSERT_GT(result.iterations, 8);
    const std::uint64_t batches = (result.iterations + check_every - 1) / check_every;
    // One submission starts the solve and one runs each batch of check_every iterations, for all
    // 200 blocks at once (lavapipe has unified memory; elsewhere the staging copies of the
    // read-backs come on top).
    if (unified)
      EXPECT_EQ(submissions, 1 + batches) << "check_every " << check_every;
    else
      EXPECT_LE(submissions, 2 * (1 + batches) + 2) << "check_every " << check_every;
    // Every block converged by itself, each after its own number of steps.
    int fewest = result.iterations;
    const Eigen::MatrixXd xs = solution.download();
    for (int k = 0; k < batch.count(); ++k) {
      EXPECT_EQ(result.system_failures[k], vulkan::detail::PcgFailure::none);
      fewest = std::min(fewest, result.system_iterations[k]);
      // The recursive fp32 residual reached the tolerance; the true one in double may differ by
      // the fp32 rounding of the recurrences, about u cond(A_k).
      EXPECT_LE(block_residual(batch, xs, k, 0),
                tolerance + 64 * 0x1p-24 * condition_bound(batch.blocks[k]))
          << "block " << k;
    }
    EXPECT_LT(fewest, result.iterations);
  }
}

class VulkanBlockPcgFloat64 : public ::testing::Test {
 protected:
  void SetUp() override {
    HARMONIA_REQUIRE_FLOAT64_TEST_DEVICE();
    gpu_ = std::make_unique<VulkanBackend>(float64_test_context(), DevicePrecision::float64);
  }
  std::unique_ptr<VulkanBackend> gpu_;
  detail::CpuBackend cpu_;
};

TEST_F(VulkanBlockPcgFloat64, IteratesAsTheCpuBlockByBlock) {
  const BlockBatch batch = mixed_batch(2);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;
  const BlockRun device = block_pcg(*gpu_, batch, settings);
  const BlockRun reference = block_pcg(cpu_, batch, settings);
  expect_matches_reference(batch, device, reference, settings.relative_tolerance);
  // The same recurrences in the same arithmetic, up to the order of the sums in the dot products,
  // which moves no residual across its threshold: the same number of steps, block by block.
  for (std::size_t s = 0; s < device.stats.systems.size(); ++s)
    EXPECT_EQ(device.stats.systems[s].iterations, reference.stats.systems[s].iterations)
        << "system " << s;
}

}  // namespace
}  // namespace harmonia::testing
