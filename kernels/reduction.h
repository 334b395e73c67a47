#pragma once
// Internal: dot products per column, dot(a, b)[c] = sum_i a(i,c) b(i,c), as a deterministic two-
// pass tree reduction (shaders/dot_partial.comp, shaders/dot_final.comp). The grouping depends
// only on the length and the workgroup width, so the same input on the same device gives the
// same bits every run. Eigen twin: CpuBackend::dot. Norms are square roots of dot(x, x).

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "kernels/device_arrays.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

// Mirrors `Push` in shaders/dot_partial.comp.
struct DotPartialPush {
  std::uint32_t rows;
};
static_assert(sizeof(DotPartialPush) == 4);

// Mirrors `Push` in shaders/dot_final.comp.
struct DotFinalPush {
  std::uint32_t groups;
  std::uint32_t result_offset;
};
static_assert(sizeof(DotFinalPush) == 8 && offsetof(DotFinalPush, result_offset) == 4);

enum class DotPartialBinding : std::uint32_t { a, b, partials, count };
enum class DotFinalBinding : std::uint32_t { partials, results, count };

extern const KernelProgram dot_partial_program;
extern const KernelProgram dot_final_program;

// The shape of a reduction on a device: workgroup width and most first-pass workgroups
// (Context::Impl::workgroup_size, reduction_groups).
struct ReductionShape {
  std::uint32_t workgroup_size;
  std::uint32_t max_groups;
};

// Workgroups of the first pass: one item per invocation, up to shape.max_groups.
[[nodiscard]] std::uint32_t dot_groups(std::uint64_t rows, ReductionShape shape);

// Error of the result relative to sum_i |a_i b_i|: inputs rounded to float (2u), the product
// (u), each invocation's in-order sum over its strided items, the log2(W) tree levels of each
// pass and the second pass's in-order sums, with u = 2^-24, plus one u of slack.
[[nodiscard]] inline double dot_error_bound(std::uint64_t rows, ReductionShape shape) {
  const std::uint64_t workgroup_size = shape.workgroup_size;
  const std::uint64_t groups = dot_groups(rows, shape);
  const std::uint64_t per_invocation =
      (rows + groups * workgroup_size - 1) / (groups * workgroup_size);
  const double tree_levels = 2.0 * std::log2(static_cast<double>(workgroup_size));
  return (4.0 + static_cast<double>(per_invocation) + tree_levels + 1.0) * 0x1p-24;
}

// Scratch floats the reduction of a rows x cols block needs (the partials).
[[nodiscard]] std::uint64_t dot_scratch_floats(std::uint64_t rows, std::uint64_t cols,
                                               ReductionShape shape);

[[nodiscard]] ReductionShape reduction_shape(const Context::Impl& context);

// Records results[result_offset + c] = dot(a, b)[c] for every column c.
void record_dot(CommandRecorder& recorder, const VulkanVectors& a, const VulkanVectors& b,
                const Buffer& partials, const Buffer& results, std::uint32_t result_offset);

}  // namespace harmonia::vulkan::detail
