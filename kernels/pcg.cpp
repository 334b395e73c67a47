#include "kernels/pcg.h"

#include <algorithm>
#include <vector>

#include "kernels/device_reals.h"
#include "kernels/reduction.h"
#include "kernels/spmv.h"
#include "kernels/transfers.h"
#include "kernels/vector_ops.h"

namespace harmonia::vulkan::detail {
namespace {

// The device state of one solve: work vectors, the per-column scalars and flags, scratch.
struct PcgBuffers {
  PcgBuffers(CommandRecorder& transfers, int rows, int cols, ReductionShape shape,
             DevicePrecision precision)
      : r(transfers, rows, cols, precision),
        z(transfers, rows, cols, precision),
        p(transfers, rows, cols, precision),
        q(transfers, rows, cols, precision),
        scalars(transfers.context(), real_bytes(precision, std::uint64_t{field_count} * cols),
                BufferRole::device, "pcg scalars"),
        state(transfers.context(), std::uint64_t{state_count} * cols * 4, BufferRole::device,
              "pcg state"),
        partials(transfers.context(), real_bytes(precision, dot_scratch_floats(rows, cols, shape)),
                 BufferRole::device, "dot partials") {}
  VulkanVectors r, z, p, q;
  Buffer scalars, state, partials;
};

std::uint32_t field_index(PcgField field, int cols) {
  return static_cast<std::uint32_t>(field) * static_cast<std::uint32_t>(cols);
}

void record_scalars_stage(CommandRecorder& recorder, PcgBuffers& buffers, int cols,
                          PcgStage stage) {
  recorder.dispatch(
      in_precision(pcg_scalars_program, buffers.r.precision()), {&buffers.scalars, &buffers.state},
      PcgScalarsPush{static_cast<std::uint32_t>(cols), static_cast<std::uint32_t>(stage)},
      recorder.groups_for(static_cast<std::uint64_t>(cols)));
}

// r = b - A x, z = M^-1 r, p = z, rz = r.z, rr = r.r, and the flags of every column.
void record_start(CommandRecorder& recorder, const VulkanMatrix& a, const VulkanVectors& b,
                  const VulkanVectors& x, PcgBuffers& buffers, int cols) {
  record_spmv(recorder, a, x, buffers.r);
  record_linear_combination(recorder, buffers.scalars, Coefficient{1.0f, {}}, b,
                            Coefficient{-1.0f, {}}, buffers.r);
  record_jacobi(recorder, a, buffers.r, buffers.z);
  record_linear_combination(recorder, buffers.scalars, Coefficient{1.0f, {}}, buffers.z,
                            std::nullopt, buffers.p);
  record_dot(recorder, buffers.r, buffers.z, buffers.partials, buffers.scalars,
             field_index(rz, cols));
  record_dot(recorder, buffers.r, buffers.r, buffers.partials, buffers.scalars,
             field_index(rr, cols));
  record_scalars_stage(recorder, buffers, cols, PcgStage::start);
}

// One iteration: q = A p, alpha = rz / p.q, x += alpha p, r -= alpha q, z = M^-1 r,
// beta = r.z / rz, p = z + beta p. Converged or failed columns have alpha = beta = 0.
void record_iteration(CommandRecorder& recorder, const VulkanMatrix& a, VulkanVectors& x,
                      PcgBuffers& buffers, int cols) {
  record_spmv(recorder, a, buffers.p, buffers.q);
  record_dot(recorder, buffers.p, buffers.q, buffers.partials, buffers.scalars,
             field_index(pq, cols));
  record_scalars_stage(recorder, buffers, cols, PcgStage::step_length);
  recorder.dispatch(in_precision(pcg_update_program, x.precision()),
                    {&buffers.scalars, &a.inverse_diagonal(), &buffers.p.buffer(),
                     &buffers.q.buffer(), &x.buffer(), &buffers.r.buffer(), &buffers.z.buffer()},
                    PcgUpdatePush{static_cast<std::uint32_t>(x.rows()), field_index(alpha, cols)},
                    recorder.groups_for(static_cast<std::uint64_t>(x.rows())),
                    static_cast<std::uint32_t>(cols));
  x.written_on_device();
  record_dot(recorder, buffers.r, buffers.z, buffers.partials, buffers.scalars,
             field_index(rz_next, cols));
  record_dot(recorder, buffers.r, buffers.r, buffers.partials, buffers.scalars,
             field_index(rr, cols));
  record_scalars_stage(recorder, buffers, cols, PcgStage::next_direction);
  record_linear_combination(recorder, buffers.scalars, Coefficient{1.0f, {}}, buffers.z,
                            Coefficient{1.0f, field_index(beta, cols)}, buffers.p);
}

struct ColumnStates {
  std::vector<std::uint32_t> values;
  int cols;
  [[nodiscard]] std::uint32_t get(PcgState field, int column) const {
    return values[static_cast<std::size_t>(field) * cols + column];
  }
};

ColumnStates read_states(CommandRecorder& transfers, const PcgBuffers& buffers, int cols) {
  ColumnStates states{std::vector<std::uint32_t>(std::size_t{state_count} * cols), cols};
  read_buffer(transfers, buffers.state, states.values.data(), states.values.size() * 4);
  return states;
}

}  // namespace

DevicePcgResult run_device_pcg(Context::Impl& context, const VulkanMatrix& a,
                               const VulkanVectors& b, VulkanVectors& x,
                               const Eigen::VectorXd& thresholds, int max_iterations,
                               int check_every, const ProgressCallback& progress,
                               int progress_offset, int progress_total) {
  const int rows = b.rows(), cols = b.cols();
  DevicePcgResult result;
  CommandRecorder transfers(context);
  const DevicePrecision precision = x.precision();
  PcgBuffers buffers(transfers, rows, cols, reduction_shape(context), precision);
  // Thresholds are compared with r.r, so they are stored squared.
  Eigen::VectorXd squared = thresholds.array().square();
  const std::vector<std::byte> threshold_values =
      encode_reals(squared.data(), static_cast<std::size_t>(cols), precision, "pcg threshold");
  write_buffer(transfers, buffers.scalars, threshold_values.data(), threshold_values.size(),
               real_bytes(precision, field_index(threshold, cols)));

  transfers.begin();
  record_start(transfers, a, b, x, buffers, cols);
  transfers.end();
  transfers.submit_and_wait();
  ColumnStates states = read_states(transfers, buffers, cols);

  // The batch is recorded once and resubmitted; a shorter last batch is recorded when needed.
  const int batch = std::max(1, check_every);
  CommandRecorder iterations_recorder(context);
  int recorded_length = 0;
  int done = 0;
  const auto any_active = [&] {
    for (int c = 0; c < cols; ++c)
      if (states.get(active, c) == 1u) return true;
    return false;
  };
  while (any_active() && done < max_iterations) {
    const int length = std::min(batch, max_iterations - done);
    if (length != recorded_length) {
      iterations_recorder.begin();
      for (int k = 0; k < length; ++k) record_iteration(iterations_recorder, a, x, buffers, cols);
      iterations_recorder.end();
      recorded_length = length;
    }
    iterations_recorder.submit_and_wait();
    done += length;
    states = read_states(transfers, buffers, cols);
    bool failed = false;
    for (int c = 0; c < cols && !failed; ++c) {
      if (states.get(failure, c) != static_cast<std::uint32_t>(PcgFailure::none)) {
        result.failure = static_cast<PcgFailure>(states.get(failure, c));
        result.failed_column = c;
        failed = true;
      }
    }
    if (failed) break;
    if (progress && !progress(Progress{"pcg", progress_offset + done, progress_total})) {
      result.cancelled = true;
      break;
    }
  }
  for (int c = 0; c < cols; ++c)
    result.iterations = std::max(result.iterations, static_cast<int>(states.get(iterations, c)));
  return result;
}

}  // namespace harmonia::vulkan::detail
