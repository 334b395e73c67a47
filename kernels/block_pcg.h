#pragma once
// Internal: Jacobi-preconditioned conjugate gradients on a block-diagonal matrix, every diagonal
// block of every column its own system (e.g. one per texture-atlas chart), all solved together on
// the device: one SpMV over the whole matrix, segmented dot products (shaders/block_dot.comp: one
// sum per block, never one over the whole column, since a shared step length would couple the
// systems and change every iteration), per-system step lengths, direction weights, residual norms
// and convergence and breakdown flags (shaders/pcg_scalars.comp, one "column" per system), and
// per-row updates that read their own system's scalars (shaders/block_pcg_update.comp,
// block_pcg_direction.comp). Several iterations per submission; the host reads the flags back
// every `check_every` iterations, as the fused PCG of kernels/pcg.h does. A system that breaks
// down stops alone. Eigen twin: Backend::block_pcg (host/backend/block_krylov.cpp).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "backend/backend.h"
#include "kernels/device_arrays.h"
#include "kernels/pcg.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

// Mirrors `Push` in shaders/block_dot.comp.
struct BlockDotPush {
  std::uint32_t rows;
  std::uint32_t blocks;
  std::uint32_t result_offset;
};
static_assert(sizeof(BlockDotPush) == 12 && offsetof(BlockDotPush, result_offset) == 8);

// Mirrors `Push` in shaders/block_pcg_update.comp.
struct BlockPcgUpdatePush {
  std::uint32_t rows;
  std::uint32_t blocks;
  std::uint32_t alpha_index;  // Of alpha for system 0 in the scalars buffer.
};
static_assert(sizeof(BlockPcgUpdatePush) == 12 && offsetof(BlockPcgUpdatePush, alpha_index) == 8);

// Mirrors `Push` in shaders/block_pcg_direction.comp.
struct BlockPcgDirectionPush {
  std::uint32_t rows;
  std::uint32_t blocks;
  std::uint32_t beta_index;    // Of beta for system 0 in the scalars buffer.
  std::uint32_t active_index;  // Of the active flag of system 0 in the state buffer.
};
static_assert(sizeof(BlockPcgDirectionPush) == 16 &&
              offsetof(BlockPcgDirectionPush, active_index) == 12);

enum class BlockDotBinding : std::uint32_t { block_offsets, a, b, results, count };
enum class BlockPcgUpdateBinding : std::uint32_t {
  row_blocks,
  scalars,
  inverse_diagonal,
  p,
  q,
  x,
  r,
  z,
  count
};
enum class BlockPcgDirectionBinding : std::uint32_t { row_blocks, state, scalars, z, p, count };

extern const KernelProgram block_dot_program;
extern const KernelProgram block_pcg_update_program;
extern const KernelProgram block_pcg_direction_program;

// The block structure on the device: the block offsets, and the block of every row.
class DeviceBlocks {
 public:
  // `blocks` must cover `rows` rows (harmonia::detail::block_structure_error is empty).
  DeviceBlocks(CommandRecorder& transfers, const harmonia::detail::BlockRows& blocks, int rows);
  [[nodiscard]] int count() const { return count_; }
  [[nodiscard]] int rows() const { return rows_; }
  [[nodiscard]] const Buffer& offsets() const { return offsets_; }
  [[nodiscard]] const Buffer& row_blocks() const { return row_blocks_; }

 private:
  int count_, rows_;
  Buffer offsets_, row_blocks_;
};

// Records results[result_offset + c * blocks + k] = the dot product of a and b over the rows of
// block k in column c, for every block and column.
void record_block_dot(CommandRecorder& recorder, const DeviceBlocks& blocks, const VulkanVectors& a,
                      const VulkanVectors& b, const Buffer& results, std::uint32_t result_offset);

struct DeviceBlockPcgResult {
  int iterations = 0;      // Most iterations any system took (the iterations the batch ran).
  bool cancelled = false;  // The progress callback returned false.
  // Per system (block k of column c at k + c * blocks): iterations taken and how it ended.
  std::vector<int> system_iterations;
  std::vector<PcgFailure> system_failures;
};

// Solves A x = b from the warm start in x, on the device in the blocks' precision, A block
// diagonal with these blocks. System s stops when its recursive residual norm is at most
// thresholds[s] (absolute). At most max_iterations iterations; flags are read back every
// check_every iterations, which is also when `progress` is called (stage "block_pcg", steps offset
// by progress_offset, out of progress_total). One submission starts the solve and one runs each
// batch of check_every iterations (plus the staging copies of the read-backs on devices without
// unified memory).
[[nodiscard]] DeviceBlockPcgResult run_device_block_pcg(
    Context::Impl& context, const VulkanMatrix& a, const DeviceBlocks& blocks,
    const VulkanVectors& b, VulkanVectors& x, const Eigen::VectorXd& thresholds, int max_iterations,
    int check_every, const ProgressCallback& progress, int progress_offset, int progress_total);

// The whole solve of VulkanBackend::block_pcg, with the semantics of Backend::block_pcg: the block
// structure checked on the host, then iterative refinement in double per system (as
// kernels/refinement.h does per column): each round forms every system's residual in double,
// solves the corrections of the systems not yet converged together on the device (fp32: each to
// at most correction_relative_tolerance; fp64: straight to the tolerance), and adds them in
// double. A system stops being refined when it converged, broke down, or a round failed to halve
// its residual.
[[nodiscard]] harmonia::detail::BlockSolveStats solve_block_pcg(
    CommandRecorder& transfers, const VulkanMatrix& a, const harmonia::detail::BlockRows& blocks,
    const VulkanVectors& b, VulkanVectors& x, const harmonia::detail::IterativeSettings& settings,
    const ProgressCallback& progress);

}  // namespace harmonia::vulkan::detail
