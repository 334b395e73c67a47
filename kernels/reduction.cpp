#include "kernels/reduction.h"

#include <algorithm>
#include <stdexcept>

#include "kernels/device_reals.h"

namespace harmonia::vulkan::detail {

std::uint32_t dot_groups(std::uint64_t rows, ReductionShape shape) {
  const std::uint64_t needed = (rows + shape.workgroup_size - 1) / shape.workgroup_size;
  return static_cast<std::uint32_t>(std::clamp<std::uint64_t>(needed, 1, shape.max_groups));
}

std::uint64_t dot_scratch_floats(std::uint64_t rows, std::uint64_t cols, ReductionShape shape) {
  return static_cast<std::uint64_t>(dot_groups(rows, shape)) * cols;
}

ReductionShape reduction_shape(const Context::Impl& context) {
  return ReductionShape{context.workgroup_size, context.reduction_groups};
}

void record_dot(CommandRecorder& recorder, const VulkanVectors& a, const VulkanVectors& b,
                const Buffer& partials, const Buffer& results, std::uint32_t result_offset) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    throw std::invalid_argument("vulkan backend: dot: block shapes differ");
  const ReductionShape shape = reduction_shape(recorder.context());
  const std::uint32_t groups = dot_groups(static_cast<std::uint64_t>(a.rows()), shape);
  const auto columns = static_cast<std::uint32_t>(a.cols());
  const DevicePrecision precision = a.precision();
  if (partials.bytes() < real_bytes(precision, dot_scratch_floats(a.rows(), columns, shape)) ||
      results.bytes() < real_bytes(precision, static_cast<std::uint64_t>(result_offset) + columns))
    throw std::logic_error("vulkan backend: dot: scratch buffers too small");
  recorder.dispatch(in_precision(dot_partial_program, precision),
                    {&a.buffer(), &b.buffer(), &partials},
                    DotPartialPush{static_cast<std::uint32_t>(a.rows())}, groups, columns);
  recorder.dispatch(in_precision(dot_final_program, precision), {&partials, &results},
                    DotFinalPush{groups, result_offset}, 1, columns);
}

}  // namespace harmonia::vulkan::detail
