#include "kernels/minres.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "kernels/device_reals.h"
#include "kernels/reduction.h"
#include "kernels/spmv.h"
#include "kernels/transfers.h"
#include "kernels/vector_ops.h"

namespace harmonia::vulkan::detail {
namespace {

// The device state of one solve: the Lanczos vectors v_{k-1}, v_k and the work vector q, the
// directions w_{k-2}, w_{k-1}, the per-column scalars and flags, and the dot scratch. New blocks
// hold zeros, which is what v_0, w_{-1} and w_0 must be.
struct MinresBuffers {
  MinresBuffers(CommandRecorder& transfers, int rows, int cols, ReductionShape shape,
                DevicePrecision precision)
      : previous_v(transfers, rows, cols, precision),
        v(transfers, rows, cols, precision),
        q(transfers, rows, cols, precision),
        older_w(transfers, rows, cols, precision),
        old_w(transfers, rows, cols, precision),
        scalars(transfers.context(),
                real_bytes(precision, std::uint64_t{field_count()} * static_cast<unsigned>(cols)),
                BufferRole::device, "minres scalars"),
        state(transfers.context(), std::uint64_t{state_count()} * cols * 4, BufferRole::device,
              "minres state"),
        partials(transfers.context(), real_bytes(precision, dot_scratch_floats(rows, cols, shape)),
                 BufferRole::device, "dot partials") {}
  static constexpr std::uint32_t field_count() {
    return static_cast<std::uint32_t>(MinresField::count);
  }
  static constexpr std::uint32_t state_count() {
    return static_cast<std::uint32_t>(MinresState::count);
  }
  VulkanVectors previous_v, v, q, older_w, old_w;
  Buffer scalars, state, partials;
};

std::uint32_t field_index(MinresField field, int cols) {
  return static_cast<std::uint32_t>(field) * static_cast<std::uint32_t>(cols);
}

void record_scalars_stage(CommandRecorder& recorder, MinresBuffers& buffers, int cols,
                          MinresStage stage) {
  recorder.dispatch(in_precision(minres_scalars_program, buffers.q.precision()),
                    {&buffers.scalars, &buffers.state},
                    MinresScalarsPush{static_cast<std::uint32_t>(cols),
                                      static_cast<std::uint32_t>(stage)},
                    recorder.groups_for(static_cast<std::uint64_t>(cols)));
}

// q = b - A x, beta_1 = |q|, phibar = beta_1, the flags, v_1 = q / beta_1.
void record_start(CommandRecorder& recorder, const VulkanMatrix& a, const VulkanVectors& b,
                  const VulkanVectors& x, MinresBuffers& buffers, int cols) {
  record_spmv(recorder, a, x, buffers.q);
  record_linear_combination(recorder, buffers.scalars, Coefficient{1.0f, {}}, b,
                            Coefficient{-1.0f, {}}, buffers.q);
  record_dot(recorder, buffers.q, buffers.q, buffers.partials, buffers.scalars,
             field_index(MinresField::qq, cols));
  record_scalars_stage(recorder, buffers, cols, MinresStage::start);
  record_linear_combination(recorder, buffers.scalars,
                            Coefficient{1.0f, field_index(MinresField::inverse_beta, cols)},
                            buffers.q, std::nullopt, buffers.v);
}

// One iteration (see kernels/minres.h). Frozen columns have every weight zero.
void record_iteration(CommandRecorder& recorder, const VulkanMatrix& a, VulkanVectors& x,
                      MinresBuffers& buffers, int cols) {
  record_spmv(recorder, a, buffers.v, buffers.q);
  record_linear_combination(recorder, buffers.scalars,
                            Coefficient{-1.0f, field_index(MinresField::beta, cols)},
                            buffers.previous_v, Coefficient{1.0f, {}}, buffers.q);
  record_dot(recorder, buffers.v, buffers.q, buffers.partials, buffers.scalars,
             field_index(MinresField::vq, cols));
  record_linear_combination(recorder, buffers.scalars,
                            Coefficient{-1.0f, field_index(MinresField::vq, cols)}, buffers.v,
                            Coefficient{1.0f, {}}, buffers.q);
  record_dot(recorder, buffers.q, buffers.q, buffers.partials, buffers.scalars,
             field_index(MinresField::qq, cols));
  record_scalars_stage(recorder, buffers, cols, MinresStage::rotate);
  recorder.dispatch(
      in_precision(minres_update_program, x.precision()),
      {&buffers.scalars, &x.buffer(), &buffers.previous_v.buffer(), &buffers.v.buffer(),
       &buffers.q.buffer(), &buffers.older_w.buffer(), &buffers.old_w.buffer()},
      MinresUpdatePush{static_cast<std::uint32_t>(x.rows()), static_cast<std::uint32_t>(cols)},
      recorder.groups_for(static_cast<std::uint64_t>(x.rows())), static_cast<std::uint32_t>(cols));
  x.written_on_device();
  buffers.previous_v.written_on_device();
  buffers.v.written_on_device();
  buffers.older_w.written_on_device();
  buffers.old_w.written_on_device();
}

struct ColumnStates {
  std::vector<std::uint32_t> values;
  int cols;
  [[nodiscard]] std::uint32_t get(MinresState field, int column) const {
    return values[static_cast<std::size_t>(field) * cols + column];
  }
};

ColumnStates read_states(CommandRecorder& transfers, const MinresBuffers& buffers, int cols) {
  ColumnStates states{std::vector<std::uint32_t>(std::size_t{MinresBuffers::state_count()} * cols),
                      cols};
  read_buffer(transfers, buffers.state, states.values.data(), states.values.size() * 4);
  return states;
}

Eigen::VectorXd read_residual_estimates(CommandRecorder& transfers, const MinresBuffers& buffers,
                                        int cols) {
  const DevicePrecision precision = buffers.q.precision();
  std::vector<std::byte> bytes(real_bytes(precision, static_cast<std::uint64_t>(cols)));
  read_buffer(transfers, buffers.scalars, bytes.data(), bytes.size(),
              real_bytes(precision, field_index(MinresField::phibar, cols)));
  Eigen::VectorXd values(cols);
  decode_reals(bytes.data(), static_cast<std::size_t>(cols), precision, values.data());
  return values.cwiseAbs();
}

}  // namespace

DeviceMinresResult run_device_minres(Context::Impl& context, const VulkanMatrix& a,
                                     const VulkanVectors& b, VulkanVectors& x,
                                     const Eigen::VectorXd& thresholds, int max_iterations,
                                     int check_every, const ProgressCallback& progress,
                                     int progress_offset, int progress_total) {
  const int rows = b.rows(), cols = b.cols();
  DeviceMinresResult result;
  CommandRecorder transfers(context);
  const DevicePrecision precision = x.precision();
  MinresBuffers buffers(transfers, rows, cols, reduction_shape(context), precision);
  const std::vector<std::byte> threshold_values = encode_reals(
      thresholds.data(), static_cast<std::size_t>(cols), precision, "minres threshold");
  write_buffer(transfers, buffers.scalars, threshold_values.data(), threshold_values.size(),
               real_bytes(precision, field_index(MinresField::threshold, cols)));

  transfers.begin();
  record_start(transfers, a, b, x, buffers, cols);
  transfers.end();
  transfers.submit_and_wait();
  ColumnStates states = read_states(transfers, buffers, cols);

  // The batch is recorded once and resubmitted; a shorter last batch is recorded when needed.
  // Converged columns are frozen on the device, so the batch length changes no bit of the result.
  const int batch = std::max(1, check_every);
  CommandRecorder iterations_recorder(context);
  int recorded_length = 0;
  int done = 0;
  const auto any_active = [&] {
    for (int c = 0; c < cols; ++c)
      if (states.get(MinresState::active, c) == 1u) return true;
    return false;
  };
  const auto find_failure = [&] {
    for (int c = 0; c < cols; ++c) {
      if (states.get(MinresState::failure, c) != static_cast<std::uint32_t>(MinresFailure::none)) {
        result.failure = static_cast<MinresFailure>(states.get(MinresState::failure, c));
        result.failed_column = c;
        return true;
      }
    }
    return false;
  };
  bool failed = find_failure();
  while (!failed && any_active() && done < max_iterations) {
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
    failed = find_failure();
    if (failed) break;
    if (progress && !progress(Progress{"minres", progress_offset + done, progress_total})) {
      result.cancelled = true;
      break;
    }
  }
  for (int c = 0; c < cols; ++c)
    result.iterations =
        std::max(result.iterations, static_cast<int>(states.get(MinresState::iterations, c)));
  result.residual_estimates = read_residual_estimates(transfers, buffers, cols);
  return result;
}

}  // namespace harmonia::vulkan::detail
