#include "kernels/reduction.h"

#include <algorithm>
#include <stdexcept>

namespace harmonia::vulkan::detail {

std::uint32_t dot_groups(std::uint64_t rows, std::uint32_t workgroup_size) {
  const std::uint64_t needed = (rows + workgroup_size - 1) / workgroup_size;
  return static_cast<std::uint32_t>(std::clamp<std::uint64_t>(needed, 1, workgroup_size));
}

std::uint64_t dot_scratch_floats(std::uint64_t rows, std::uint64_t cols,
                                 std::uint32_t workgroup_size) {
  return static_cast<std::uint64_t>(dot_groups(rows, workgroup_size)) * cols;
}

void record_dot(CommandRecorder& recorder, const VulkanVectors& a, const VulkanVectors& b,
                const Buffer& partials, const Buffer& results, std::uint32_t result_offset) {
  if (a.rows() != b.rows() || a.cols() != b.cols())
    throw std::invalid_argument("vulkan backend: dot: block shapes differ");
  const std::uint32_t width = recorder.context().workgroup_size;
  const std::uint32_t groups = dot_groups(static_cast<std::uint64_t>(a.rows()), width);
  const auto columns = static_cast<std::uint32_t>(a.cols());
  if (partials.bytes() < dot_scratch_floats(a.rows(), columns, width) * 4 ||
      results.bytes() < (static_cast<std::uint64_t>(result_offset) + columns) * 4)
    throw std::logic_error("vulkan backend: dot: scratch buffers too small");
  recorder.dispatch(dot_partial_program, {&a.buffer(), &b.buffer(), &partials},
                    DotPartialPush{static_cast<std::uint32_t>(a.rows())}, groups, columns);
  recorder.dispatch(dot_final_program, {&partials, &results}, DotFinalPush{groups, result_offset},
                    1, columns);
}

}  // namespace harmonia::vulkan::detail
