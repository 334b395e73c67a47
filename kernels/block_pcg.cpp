#include "kernels/block_pcg.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "kernels/device_reals.h"
#include "kernels/refinement.h"
#include "kernels/spmv.h"
#include "kernels/transfers.h"
#include "kernels/vector_ops.h"
#include "mesh/number_text.h"

namespace harmonia::vulkan::detail {
namespace {

using harmonia::detail::BlockRows;
using harmonia::detail::BlockSolveStats;
using harmonia::detail::BlockSystemStats;

// A safety net only (as in kernels/refinement.cpp): each round at least halves a residual.
constexpr int maximum_rounds = 60;

// The device state of one solve: work vectors, the per-system scalars and flags.
struct BlockPcgBuffers {
  BlockPcgBuffers(CommandRecorder& transfers, int rows, int cols, int systems,
                  DevicePrecision precision)
      : r(transfers, rows, cols, precision),
        z(transfers, rows, cols, precision),
        p(transfers, rows, cols, precision),
        q(transfers, rows, cols, precision),
        scalars(transfers.context(), real_bytes(precision, std::uint64_t{field_count} * systems),
                BufferRole::device, "block pcg scalars"),
        state(transfers.context(), std::uint64_t{state_count} * systems * 4, BufferRole::device,
              "block pcg state") {}
  VulkanVectors r, z, p, q;
  Buffer scalars, state;
};

// Where field f (or flag f) of system 0 lives; system s follows at + s.
std::uint32_t field_index(std::uint32_t field, int systems) {
  return field * static_cast<std::uint32_t>(systems);
}

void record_scalars_stage(CommandRecorder& recorder, BlockPcgBuffers& buffers, int systems,
                          PcgStage stage) {
  recorder.dispatch(
      in_precision(pcg_scalars_program, buffers.r.precision()), {&buffers.scalars, &buffers.state},
      PcgScalarsPush{static_cast<std::uint32_t>(systems), static_cast<std::uint32_t>(stage)},
      recorder.groups_for(static_cast<std::uint64_t>(systems)));
}

// r = b - A x, z = M^-1 r, p = z, and per system rz = r.z, rr = r.r and the flags.
void record_start(CommandRecorder& recorder, const VulkanMatrix& a, const DeviceBlocks& blocks,
                  const VulkanVectors& b, const VulkanVectors& x, BlockPcgBuffers& buffers,
                  int systems) {
  record_spmv(recorder, a, x, buffers.r);
  record_linear_combination(recorder, buffers.scalars, Coefficient{1.0f, {}}, b,
                            Coefficient{-1.0f, {}}, buffers.r);
  record_jacobi(recorder, a, buffers.r, buffers.z);
  record_linear_combination(recorder, buffers.scalars, Coefficient{1.0f, {}}, buffers.z,
                            std::nullopt, buffers.p);
  record_block_dot(recorder, blocks, buffers.r, buffers.z, buffers.scalars,
                   field_index(rz, systems));
  record_block_dot(recorder, blocks, buffers.r, buffers.r, buffers.scalars,
                   field_index(rr, systems));
  record_scalars_stage(recorder, buffers, systems, PcgStage::start);
}

// One iteration of every active system: q = A p, alpha = rz / p.q, x += alpha p, r -= alpha q,
// z = M^-1 r, beta = r.z / rz, p = z + beta p, each scalar per block and column.
void record_iteration(CommandRecorder& recorder, const VulkanMatrix& a, const DeviceBlocks& blocks,
                      VulkanVectors& x, BlockPcgBuffers& buffers, int systems) {
  const auto rows = static_cast<std::uint32_t>(x.rows());
  const auto block_count = static_cast<std::uint32_t>(blocks.count());
  const auto cols = static_cast<std::uint32_t>(x.cols());
  const DevicePrecision precision = x.precision();
  record_spmv(recorder, a, buffers.p, buffers.q);
  record_block_dot(recorder, blocks, buffers.p, buffers.q, buffers.scalars,
                   field_index(pq, systems));
  record_scalars_stage(recorder, buffers, systems, PcgStage::step_length);
  recorder.dispatch(
      in_precision(block_pcg_update_program, precision),
      {&blocks.row_blocks(), &buffers.scalars, &a.inverse_diagonal(), &buffers.p.buffer(),
       &buffers.q.buffer(), &x.buffer(), &buffers.r.buffer(), &buffers.z.buffer()},
      BlockPcgUpdatePush{rows, block_count, field_index(alpha, systems)}, recorder.groups_for(rows),
      cols);
  x.written_on_device();
  record_block_dot(recorder, blocks, buffers.r, buffers.z, buffers.scalars,
                   field_index(rz_next, systems));
  record_block_dot(recorder, blocks, buffers.r, buffers.r, buffers.scalars,
                   field_index(rr, systems));
  record_scalars_stage(recorder, buffers, systems, PcgStage::next_direction);
  recorder.dispatch(in_precision(block_pcg_direction_program, precision),
                    {&blocks.row_blocks(), &buffers.state, &buffers.scalars, &buffers.z.buffer(),
                     &buffers.p.buffer()},
                    BlockPcgDirectionPush{rows, block_count, field_index(beta, systems),
                                          field_index(active, systems)},
                    recorder.groups_for(rows), cols);
}

struct SystemStates {
  std::vector<std::uint32_t> values;
  int systems;
  [[nodiscard]] std::uint32_t get(PcgState field, int system) const {
    return values[static_cast<std::size_t>(field) * systems + system];
  }
  [[nodiscard]] bool any_active() const {
    for (int s = 0; s < systems; ++s)
      if (get(active, s) == 1u) return true;
    return false;
  }
};

SystemStates read_states(CommandRecorder& transfers, const BlockPcgBuffers& buffers, int systems) {
  SystemStates states{std::vector<std::uint32_t>(std::size_t{state_count} * systems), systems};
  read_buffer(transfers, buffers.state, states.values.data(), states.values.size() * 4);
  return states;
}

// The norm of every system's segment of v (block k of column c at k + c * blocks).
Eigen::VectorXd system_norms(const Eigen::MatrixXd& v, const BlockRows& blocks) {
  const int count = blocks.count();
  Eigen::VectorXd norms(static_cast<Eigen::Index>(count) * v.cols());
  for (Eigen::Index c = 0; c < v.cols(); ++c)
    for (int k = 0; k < count; ++k)
      norms[k + c * count] = v.col(c).segment(blocks.begin(k), blocks.size(k)).norm();
  return norms;
}

// The rows of system s (block k of column c) in a rows x cols block.
template <typename Matrix>
auto segment(Matrix& v, const BlockRows& blocks, int s) {
  const int k = s % blocks.count(), c = s / blocks.count();
  return v.col(c).segment(blocks.begin(k), blocks.size(k));
}

std::string failure_text(PcgFailure failure) {
  switch (failure) {
    case PcgFailure::none:
      return "no failure";
    case PcgFailure::not_positive_definite:
      return "the block is not positive definite (p^T A p <= 0)";
    case PcgFailure::not_finite:
      return "the residual is not finite";
  }
  return "unknown failure";
}

}  // namespace

DeviceBlocks::DeviceBlocks(CommandRecorder& transfers, const BlockRows& blocks, int rows)
    : count_(blocks.count()),
      rows_(rows),
      offsets_(transfers.context(), 4 * blocks.offsets.size(), BufferRole::device, "block offsets"),
      row_blocks_(transfers.context(), 4 * static_cast<std::uint64_t>(rows), BufferRole::device,
                  "row blocks") {
  if (blocks.offsets.empty() || blocks.offsets.back() != rows)
    throw std::invalid_argument("vulkan backend: the blocks do not cover the rows");
  const std::vector<std::uint32_t> offsets(blocks.offsets.begin(), blocks.offsets.end());
  std::vector<std::uint32_t> row_blocks(static_cast<std::size_t>(rows));
  for (int k = 0; k < count_; ++k)
    std::fill_n(row_blocks.begin() + blocks.begin(k), blocks.size(k),
                static_cast<std::uint32_t>(k));
  write_buffer(transfers, offsets_, offsets.data(), 4 * offsets.size());
  write_buffer(transfers, row_blocks_, row_blocks.data(), 4 * row_blocks.size());
}

void record_block_dot(CommandRecorder& recorder, const DeviceBlocks& blocks, const VulkanVectors& a,
                      const VulkanVectors& b, const Buffer& results, std::uint32_t result_offset) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.rows() != blocks.rows())
    throw std::invalid_argument("vulkan backend: block dot: shapes differ");
  const auto block_count = static_cast<std::uint32_t>(blocks.count());
  const auto columns = static_cast<std::uint32_t>(a.cols());
  if (results.bytes() < real_bytes(a.precision(), std::uint64_t{result_offset} +
                                                      std::uint64_t{block_count} * columns))
    throw std::logic_error("vulkan backend: block dot: result buffer too small");
  // One workgroup per block, as many as the device allows; the shader strides over the rest.
  const std::uint32_t groups = std::clamp<std::uint32_t>(
      block_count, 1, recorder.context().limits.maxComputeWorkGroupCount[0]);
  recorder.dispatch(in_precision(block_dot_program, a.precision()),
                    {&blocks.offsets(), &a.buffer(), &b.buffer(), &results},
                    BlockDotPush{static_cast<std::uint32_t>(a.rows()), block_count, result_offset},
                    groups, columns);
}

DeviceBlockPcgResult run_device_block_pcg(Context::Impl& context, const VulkanMatrix& a,
                                          const DeviceBlocks& blocks, const VulkanVectors& b,
                                          VulkanVectors& x, const Eigen::VectorXd& thresholds,
                                          int max_iterations, int check_every,
                                          const ProgressCallback& progress, int progress_offset,
                                          int progress_total) {
  const int rows = b.rows(), cols = b.cols(), systems = blocks.count() * cols;
  if (thresholds.size() != systems)
    throw std::invalid_argument("vulkan backend: block pcg: one threshold per system is needed");
  DeviceBlockPcgResult result;
  CommandRecorder transfers(context);
  const DevicePrecision precision = x.precision();
  BlockPcgBuffers buffers(transfers, rows, cols, systems, precision);
  // Thresholds are compared with r.r, so they are stored squared.
  const Eigen::VectorXd squared = thresholds.array().square();
  const std::vector<std::byte> threshold_values = encode_reals(
      squared.data(), static_cast<std::size_t>(systems), precision, "block pcg threshold");
  write_buffer(transfers, buffers.scalars, threshold_values.data(), threshold_values.size(),
               real_bytes(precision, field_index(threshold, systems)));

  transfers.begin();
  record_start(transfers, a, blocks, b, x, buffers, systems);
  transfers.end();
  transfers.submit_and_wait();
  SystemStates states = read_states(transfers, buffers, systems);

  // The batch is recorded once and resubmitted; a shorter last batch is recorded when needed.
  // Systems that converged or broke down are frozen on the device, so the others go on.
  const int batch = std::max(1, check_every);
  CommandRecorder iterations_recorder(context);
  int recorded_length = 0;
  int done = 0;
  while (states.any_active() && done < max_iterations) {
    const int length = std::min(batch, max_iterations - done);
    if (length != recorded_length) {
      iterations_recorder.begin();
      for (int k = 0; k < length; ++k)
        record_iteration(iterations_recorder, a, blocks, x, buffers, systems);
      iterations_recorder.end();
      recorded_length = length;
    }
    iterations_recorder.submit_and_wait();
    done += length;
    states = read_states(transfers, buffers, systems);
    if (progress && !progress(Progress{"block_pcg", progress_offset + done, progress_total})) {
      result.cancelled = true;
      break;
    }
  }
  result.system_iterations.resize(static_cast<std::size_t>(systems));
  result.system_failures.resize(static_cast<std::size_t>(systems));
  for (int s = 0; s < systems; ++s) {
    result.system_iterations[s] = static_cast<int>(states.get(iterations, s));
    result.system_failures[s] = static_cast<PcgFailure>(states.get(failure, s));
    result.iterations = std::max(result.iterations, result.system_iterations[s]);
  }
  return result;
}

BlockSolveStats solve_block_pcg(CommandRecorder& transfers, const VulkanMatrix& a,
                                const BlockRows& blocks, const VulkanVectors& b, VulkanVectors& x,
                                const harmonia::detail::IterativeSettings& settings,
                                const ProgressCallback& progress) {
  if (b.rows() != a.rows() || x.rows() != b.rows() || x.cols() != b.cols())
    throw std::invalid_argument("block_pcg: the shapes of A, b and x differ");
  BlockSolveStats stats;
  if (std::string error = harmonia::detail::block_structure_error(a.host(), blocks);
      !error.empty()) {
    stats.status = Status::invalid_input;
    stats.message = "block_pcg: " + error;
    return stats;
  }
  const int rows = b.rows(), cols = b.cols(), systems = blocks.count() * cols;
  stats.block_count = blocks.count();
  stats.systems.resize(static_cast<std::size_t>(systems));
  const Eigen::MatrixXd rhs = b.download();
  Eigen::MatrixXd solution = x.download();
  const Eigen::VectorXd b_norms = system_norms(rhs, blocks);
  for (int s = 0; s < systems; ++s)
    if (b_norms[s] == 0.0) segment(solution, blocks, s).setZero();  // Exactly its solution.
  const double tolerance = settings.relative_tolerance;
  // fp64 kernels reach the final tolerance themselves: one round, its residual checked in double.
  const double correction_floor =
      a.precision() == DevicePrecision::float64 ? 0.0 : correction_relative_tolerance;

  std::vector<bool> broken(static_cast<std::size_t>(systems), false);
  Eigen::VectorXd previous =
      Eigen::VectorXd::Constant(systems, std::numeric_limits<double>::infinity());
  int iterations = 0;  // Device iterations so far: each round adds the most any system took.
  bool cancelled = false;
  std::unique_ptr<DeviceBlocks> device_blocks;
  std::unique_ptr<VulkanVectors> residual, correction;
  for (int round = 0; rows > 0; ++round) {
    const Eigen::MatrixXd r = rhs - a.host() * solution;
    const Eigen::VectorXd r_norms = system_norms(r, blocks);
    // The systems this round refines: not converged, not broken down, still gaining.
    std::vector<bool> refined(static_cast<std::size_t>(systems), false);
    Eigen::VectorXd thresholds = Eigen::VectorXd::Zero(systems);
    bool any = false;
    for (int s = 0; s < systems; ++s) {
      const double relative = b_norms[s] > 0.0 ? r_norms[s] / b_norms[s] : r_norms[s];
      stats.systems[s].relative_residual =
          std::isfinite(relative) ? relative : std::numeric_limits<double>::infinity();
      if (broken[s] || !std::isfinite(relative) || relative <= tolerance) continue;
      if (round > 0 && relative > refinement_minimum_gain * previous[s]) continue;
      previous[s] = relative;
      thresholds[s] = std::max(tolerance * b_norms[s] / r_norms[s], correction_floor);
      refined[s] = any = true;
    }
    if (!any || iterations >= settings.max_iterations || round == maximum_rounds) break;

    // Each refined system's residual scaled to unit norm (fp32 would underflow the squares of a
    // residual of 1e-20; the relative tolerance is unchanged); the others get zero and start
    // converged.
    Eigen::MatrixXd scaled = Eigen::MatrixXd::Zero(rows, cols);
    for (int s = 0; s < systems; ++s)
      if (refined[s]) segment(scaled, blocks, s) = segment(r, blocks, s) / r_norms[s];
    if (!device_blocks) {
      device_blocks = std::make_unique<DeviceBlocks>(transfers, blocks, rows);
      residual = std::make_unique<VulkanVectors>(transfers, rows, cols, a.precision());
      correction = std::make_unique<VulkanVectors>(transfers, rows, cols, a.precision());
    }
    residual->upload(scaled);
    correction->upload(Eigen::MatrixXd::Zero(rows, cols));
    const DeviceBlockPcgResult device =
        run_device_block_pcg(transfers.context(), a, *device_blocks, *residual, *correction,
                             thresholds, settings.max_iterations - iterations, settings.check_every,
                             progress, iterations, settings.max_iterations);
    iterations += device.iterations;
    const Eigen::MatrixXd d = correction->download();
    for (int s = 0; s < systems; ++s) {
      if (!refined[s]) continue;
      stats.systems[s].iterations += device.system_iterations[s];
      segment(solution, blocks, s) += r_norms[s] * segment(d, blocks, s);
      if (device.system_failures[s] != PcgFailure::none) {
        broken[s] = true;  // Keeps its last iterate, as the CPU's PCG does.
        stats.systems[s].status = Status::numerical_failure;
        stats.systems[s].message = failure_text(device.system_failures[s]);
      }
    }
    if (device.cancelled) {
      cancelled = true;
      break;
    }
  }
  x.set_refined(solution);

  const std::string name = a.precision() == DevicePrecision::float64
                               ? " (fp64 on the device)"
                               : " (fp32 on the device, refined in double)";
  for (int s = 0; s < systems; ++s) {
    BlockSystemStats& system = stats.systems[s];
    if (broken[s]) continue;
    if (!std::isfinite(system.relative_residual)) {
      system.status = Status::numerical_failure;
      system.message = "the residual is not finite";
    } else if (system.relative_residual > tolerance) {
      system.status = Status::not_converged;
      system.message = "pcg" + name + " stopped after " + std::to_string(system.iterations) +
                       " iterations at relative residual " +
                       harmonia::detail::scientific_text(system.relative_residual) + " (tolerance " +
                       harmonia::detail::scientific_text(tolerance) + ")";
    }
  }
  stats.summarize(blocks);
  if (cancelled) {
    stats.status = Status::cancelled;
    stats.message = "cancelled during block_pcg";
  }
  return stats;
}

}  // namespace harmonia::vulkan::detail
