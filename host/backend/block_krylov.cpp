// The batched PCG of block-diagonal systems every backend gets for free, and the check of the
// block structure every implementation starts with. The default is the definition itself: PCG
// (krylov.cpp) on each diagonal block alone, one column at a time, so each system has its own
// step lengths and stopping test. A device backend overrides it to solve all blocks together
// (kernels/block_pcg.h); this is the reference it is tested against.

#include <algorithm>
#include <stdexcept>
#include <string>

#include "backend/backend.h"

namespace harmonia::detail {
namespace {

std::string rows_text(const BlockRows& blocks, int block) {
  return "block " + std::to_string(block) + " (rows " + std::to_string(blocks.begin(block)) + ".." +
         std::to_string(blocks.offsets[block + 1] - 1) + ")";
}

}  // namespace

// The first broken-down system names the batch's failure, else the first unconverged one.
void BlockSolveStats::summarize(const BlockRows& blocks) {
  iterations = 0;
  relative_residual = 0.0;
  for (const BlockSystemStats& system : systems) {
    iterations = std::max(iterations, system.iterations);
    relative_residual = std::max(relative_residual, system.relative_residual);
  }
  for (const Status failure : {Status::numerical_failure, Status::not_converged}) {
    const auto failed = std::find_if(systems.begin(), systems.end(),
                                     [&](const auto& system) { return system.status == failure; });
    if (failed == systems.end()) continue;
    const auto index = static_cast<int>(failed - systems.begin());
    status = failure;
    message = "block_pcg: " + rows_text(blocks, index % block_count) + ", column " +
              std::to_string(index / block_count) + ": " + failed->message;
    return;
  }
}

std::string block_structure_error(const RowMajorSparse& matrix, const BlockRows& blocks) {
  const auto rows = static_cast<int>(matrix.rows());
  if (matrix.cols() != rows)
    return "the matrix is not square (" + std::to_string(rows) + " x " +
           std::to_string(matrix.cols()) + ")";
  if (blocks.offsets.empty() || blocks.offsets.front() != 0 || blocks.offsets.back() != rows)
    return "the block offsets must run from 0 to the " + std::to_string(rows) +
           " rows of the matrix";
  for (int k = 0; k < blocks.count(); ++k)
    if (blocks.size(k) < 0)
      return "the block offsets decrease at block " + std::to_string(k) + " (" +
             std::to_string(blocks.offsets[k]) + " > " + std::to_string(blocks.offsets[k + 1]) +
             ")";
  for (int k = 0; k < blocks.count(); ++k) {
    const int first = blocks.begin(k), end = first + blocks.size(k);
    for (int row = first; row < end; ++row) {
      for (RowMajorSparse::InnerIterator entry(matrix, row); entry; ++entry) {
        const auto column = static_cast<int>(entry.col());
        if (column < first || column >= end)
          return "entry (row " + std::to_string(row) + ", column " + std::to_string(column) +
                 ") lies outside " + rows_text(blocks, k) + "; the matrix must be block diagonal";
      }
    }
  }
  return {};
}

BlockSolveStats Backend::block_pcg(const DeviceMatrix& a, const BlockRows& blocks,
                                   const DeviceVectors& b, DeviceVectors& x,
                                   const IterativeSettings& settings,
                                   const ProgressCallback& progress) {
  if (b.rows() != a.rows() || x.rows() != b.rows() || x.cols() != b.cols())
    throw std::invalid_argument("block_pcg: the shapes of A, b and x differ");
  BlockSolveStats stats;
  const RowMajorSparse& matrix = a.host();
  if (std::string error = block_structure_error(matrix, blocks); !error.empty()) {
    stats.status = Status::invalid_input;
    stats.message = "block_pcg: " + error;
    return stats;
  }
  const int block_count = blocks.count(), cols = b.cols();
  stats.block_count = block_count;
  stats.systems.resize(static_cast<std::size_t>(block_count) * cols);
  const Eigen::MatrixXd rhs = b.download();
  Eigen::MatrixXd solution = x.download();
  const int total = block_count * cols;
  int done = 0;
  for (int k = 0; k < block_count; ++k) {
    const int first = blocks.begin(k), size = blocks.size(k);
    if (size == 0) {
      done += cols;
      continue;
    }
    const auto block = upload(RowMajorSparse(matrix.block(first, first, size, size)));
    for (int c = 0; c < cols; ++c, ++done) {
      const auto block_rhs = upload(rhs.block(first, c, size, 1));
      const auto block_x = upload(solution.block(first, c, size, 1));
      // Progress counts systems; pcg's own calls are passed on as "still on system `done`".
      ProgressCallback per_system;
      if (progress)
        per_system = [&](const Progress&) { return progress(Progress{"block_pcg", done, total}); };
      const SolveStats system = pcg(*block, *block_rhs, *block_x, settings, per_system);
      solution.block(first, c, size, 1) = block_x->download();
      if (system.status == Status::cancelled) {
        x.upload(solution);
        stats.summarize(blocks);
        stats.status = Status::cancelled;
        stats.message = "cancelled during block_pcg";
        return stats;
      }
      BlockSystemStats& outcome = stats.systems[static_cast<std::size_t>(k + c * block_count)];
      outcome.iterations = system.iterations;
      outcome.relative_residual = system.relative_residual;
      outcome.status = system.status;
      outcome.message = system.message;
    }
  }
  x.upload(solution);
  stats.summarize(blocks);
  return stats;
}

}  // namespace harmonia::detail
