// The batched PCG of block-diagonal systems on the CPU backend (Backend::block_pcg, the reference
// the device version is tested against): every block solved to its own relative tolerance and
// matching a direct solve within the tolerance times its condition number; each block iterating
// exactly as PCG on that block alone (per-block step lengths: a 1 x 1 block takes one step however
// slow its neighbours are, which one PCG over the whole matrix cannot do); the block structure
// checked before anything runs; a block that is not positive definite failing alone.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "backend/backend.h"
#include "backend/block_diagonal_systems.h"
#include "fallback/cpu_backend.h"

namespace harmonia::testing {
namespace {

using detail::BlockSolveStats;
using detail::CpuBackend;
using detail::IterativeSettings;
using detail::RowMajorSparse;
using detail::SolveStats;

constexpr double eps = std::numeric_limits<double>::epsilon();

struct BlockRun {
  BlockSolveStats stats;
  Eigen::MatrixXd x;
};

BlockRun block_pcg(const RowMajorSparse& matrix, const detail::BlockRows& rows,
                   const Eigen::MatrixXd& rhs, const Eigen::MatrixXd& start,
                   const IterativeSettings& settings, const ProgressCallback& progress = {}) {
  CpuBackend backend;
  const auto a = backend.upload(matrix);
  const auto b = backend.upload(rhs);
  const auto x = backend.upload(start);
  BlockRun run;
  run.stats = backend.block_pcg(*a, rows, *b, *x, settings, progress);
  run.x = x->download();
  return run;
}

// PCG on one block and one column alone.
struct SeparateRun {
  SolveStats stats;
  Eigen::VectorXd x;
};
SeparateRun separate_pcg(const Sparse& block, const Eigen::VectorXd& rhs,
                         const IterativeSettings& settings) {
  CpuBackend backend;
  const auto a = backend.upload(RowMajorSparse(block));
  const auto b = backend.upload(rhs);
  const auto x = backend.allocate(static_cast<int>(rhs.size()), 1);
  SeparateRun run;
  run.stats = backend.pcg(*a, *b, *x, settings, {});
  run.x = x->download();
  return run;
}

double relative_error(const Eigen::MatrixXd& x, const Eigen::MatrixXd& reference) {
  return (x - reference).norm() / reference.norm();
}

TEST(BlockPcg, EveryBlockMatchesItsDirectSolve) {
  const BlockBatch batch = mixed_batch(2);
  const Eigen::MatrixXd reference = direct_solutions(batch);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;
  // A warm start of ones: the zero right-hand side block must still come back exactly zero.
  const BlockRun run = block_pcg(batch.matrix, batch.rows, batch.rhs,
                                 Eigen::MatrixXd::Ones(batch.rhs.rows(), 2), settings);
  ASSERT_EQ(run.stats.status, Status::ok) << run.stats.message;
  ASSERT_EQ(run.stats.block_count, batch.count());
  ASSERT_EQ(run.stats.systems.size(), static_cast<std::size_t>(2 * batch.count()));
  for (int k = 0; k < batch.count(); ++k) {
    for (int c = 0; c < 2; ++c) {
      const detail::BlockSystemStats& system = run.stats.system(k, c);
      EXPECT_EQ(system.status, Status::ok) << "block " << k << ": " << system.message;
      EXPECT_LE(system.relative_residual, settings.relative_tolerance) << "block " << k;
    }
    if (batch.rows.size(k) == 0) continue;
    const Eigen::MatrixXd x = batch.segment(run.x, k), expected = batch.segment(reference, k);
    if (batch.segment(batch.rhs, k).norm() == 0.0) {
      EXPECT_EQ(x.cwiseAbs().maxCoeff(), 0.0) << "block " << k;
      EXPECT_EQ(run.stats.system(k).iterations, 0);
      continue;
    }
    // ||x - x*|| / ||x*|| <= cond(A_k) ||r|| / ||b||; the direct solve adds its own rounding.
    const double bound = condition_bound(batch.blocks[k]) * (settings.relative_tolerance + 8 * eps);
    EXPECT_LE(relative_error(x, expected), bound) << "block " << k;
  }
  EXPECT_LE(run.stats.relative_residual, settings.relative_tolerance);
}

TEST(BlockPcg, EveryBlockIteratesAsPcgOnThatBlockAlone) {
  const BlockBatch batch = mixed_batch(2);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;
  const Eigen::MatrixXd zeros = Eigen::MatrixXd::Zero(batch.rhs.rows(), 2);
  const BlockRun run = block_pcg(batch.matrix, batch.rows, batch.rhs, zeros, settings);
  ASSERT_EQ(run.stats.status, Status::ok) << run.stats.message;
  int most = 0;
  for (int k = 0; k < batch.count(); ++k) {
    if (batch.rows.size(k) == 0) continue;
    for (int c = 0; c < 2; ++c) {
      const SeparateRun alone =
          separate_pcg(batch.blocks[k], batch.segment(batch.rhs, k).col(c), settings);
      ASSERT_EQ(alone.stats.status, Status::ok) << alone.stats.message;
      EXPECT_EQ(run.stats.system(k, c).iterations, alone.stats.iterations) << "block " << k;
      EXPECT_EQ(batch.segment(run.x, k).col(c), alone.x) << "block " << k;
      most = std::max(most, alone.stats.iterations);
    }
  }
  EXPECT_EQ(run.stats.iterations, most);
  // Per-block step lengths at work: the 1 x 1 block and the diagonal one are done in one step,
  // the ill-conditioned grid takes many more ...
  EXPECT_EQ(run.stats.system(2).iterations, 1);
  EXPECT_EQ(run.stats.system(5).iterations, 1);
  EXPECT_GT(run.stats.system(1).iterations, 20);
  // ... whereas one PCG over the whole matrix (one step length for all blocks) needs more steps
  // than its slowest block alone.
  CpuBackend backend;
  const auto a = backend.upload(batch.matrix);
  const auto b = backend.upload(batch.rhs.col(0));
  const auto x = backend.allocate(static_cast<int>(batch.rhs.rows()), 1);
  const SolveStats global = backend.pcg(*a, *b, *x, settings, {});
  ASSERT_EQ(global.status, Status::ok) << global.message;
  int slowest = 0;
  for (int k = 0; k < batch.count(); ++k)
    slowest = std::max(slowest, run.stats.system(k, 0).iterations);
  EXPECT_GT(global.iterations, slowest);
}

TEST(BlockPcg, RejectsAnEntryOutsideItsBlockNamingIt) {
  const BlockBatch batch = mixed_batch(1);
  // Couple row 5 of block 0 (rows 0..19) to column 30 of block 1, symmetrically.
  RowMajorSparse coupled = batch.matrix;
  coupled.coeffRef(5, 30) = -0.1;
  coupled.coeffRef(30, 5) = -0.1;
  coupled.makeCompressed();
  const Eigen::MatrixXd start = Eigen::MatrixXd::Constant(batch.rhs.rows(), 1, 3.0);
  BlockRun run = block_pcg(coupled, batch.rows, batch.rhs, start, {});
  EXPECT_EQ(run.stats.status, Status::invalid_input);
  EXPECT_NE(run.stats.message.find("entry (row 5, column 30) lies outside block 0 (rows 0..19)"),
            std::string::npos)
      << run.stats.message;
  EXPECT_EQ(run.x, start);  // Nothing ran.
  // Offsets that do not cover the matrix, or run backwards.
  detail::BlockRows short_rows = batch.rows;
  short_rows.offsets.back() -= 1;
  run = block_pcg(batch.matrix, short_rows, batch.rhs, start, {});
  EXPECT_EQ(run.stats.status, Status::invalid_input);
  EXPECT_NE(run.stats.message.find("offsets"), std::string::npos) << run.stats.message;
  detail::BlockRows backwards = batch.rows;
  std::swap(backwards.offsets[1], backwards.offsets[2]);
  run = block_pcg(batch.matrix, backwards, batch.rhs, start, {});
  EXPECT_EQ(run.stats.status, Status::invalid_input);
  EXPECT_NE(run.stats.message.find("decrease at block 1"), std::string::npos) << run.stats.message;
}

TEST(BlockPcg, ABlockThatIsNotPositiveDefiniteFailsAlone) {
  BlockBatch batch = mixed_batch(1);
  batch.blocks[6] = -batch.blocks[6];  // Negative definite: p^T A p < 0 at the first step.
  batch = assemble_batch(batch.blocks, batch.rhs);
  const Eigen::MatrixXd reference = direct_solutions(batch);
  IterativeSettings settings;
  settings.relative_tolerance = 1e-10;
  const BlockRun run = block_pcg(batch.matrix, batch.rows, batch.rhs,
                                 Eigen::MatrixXd::Zero(batch.rhs.rows(), 1), settings);
  EXPECT_EQ(run.stats.status, Status::numerical_failure);
  EXPECT_NE(run.stats.message.find("block 6"), std::string::npos) << run.stats.message;
  EXPECT_NE(run.stats.message.find("not positive definite"), std::string::npos)
      << run.stats.message;
  EXPECT_EQ(run.stats.system(6).status, Status::numerical_failure);
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(run.stats.system(k).status, Status::ok) << run.stats.system(k).message;
    if (batch.segment(batch.rhs, k).norm() == 0.0 || batch.rows.size(k) == 0) continue;
    const double bound = condition_bound(batch.blocks[k]) * (settings.relative_tolerance + 8 * eps);
    EXPECT_LE(relative_error(batch.segment(run.x, k), batch.segment(reference, k)), bound)
        << "block " << k;
  }
}

TEST(BlockPcg, CapAndCancellation) {
  const BlockBatch batch = mixed_batch(1);
  const Eigen::MatrixXd zeros = Eigen::MatrixXd::Zero(batch.rhs.rows(), 1);
  IterativeSettings settings;
  settings.max_iterations = 3;  // Enough for the small blocks, not for the grids.
  BlockRun run = block_pcg(batch.matrix, batch.rows, batch.rhs, zeros, settings);
  EXPECT_EQ(run.stats.status, Status::not_converged);
  EXPECT_NE(run.stats.message.find("block 0"), std::string::npos) << run.stats.message;
  EXPECT_EQ(run.stats.system(2).status, Status::ok);
  EXPECT_EQ(run.stats.system(1).status, Status::not_converged);
  EXPECT_LE(run.stats.iterations, 3);

  int calls = 0;
  run =
      block_pcg(batch.matrix, batch.rows, batch.rhs, zeros, {}, [&calls](const Progress& progress) {
        EXPECT_EQ(progress.stage, "block_pcg");
        return ++calls < 2;
      });
  EXPECT_EQ(run.stats.status, Status::cancelled);
  EXPECT_EQ(calls, 2);
}

}  // namespace
}  // namespace harmonia::testing
