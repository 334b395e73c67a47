#pragma once
// Internal: CSR sparse matrix times a block of vectors, y = A x column by column
// (shaders/spmv_rows.comp, shaders/spmv_lanes.comp). Eigen twin: CpuBackend::spmv.

#include <cstddef>
#include <cstdint>

#include "kernels/device_arrays.h"
#include "kernels/pipelines.h"
#include "kernels/recorder.h"

namespace harmonia::vulkan::detail {

// Mirrors `Push` in shaders/spmv_rows.comp and shaders/spmv_lanes.comp.
struct SpmvPush {
  std::uint32_t rows;    // Rows of A and of y.
  std::uint32_t x_rows;  // Columns of A: the stride between the columns of the x block.
};
static_assert(sizeof(SpmvPush) == 8 && offsetof(SpmvPush, x_rows) == 4);

enum class SpmvBinding : std::uint32_t { row_offsets, columns, values, x, y, count };

extern const KernelProgram spmv_rows_program;   // One invocation per row.
extern const KernelProgram spmv_lanes_program;  // One subgroup (lanes_per_row) per row.

// Rows at least this long on average go to the subgroup-per-row variant: below it most lanes of
// a subgroup would idle, above it one invocation per row serializes too much work.
constexpr double spmv_lanes_min_mean_row_length = 16.0;

// Error of one entry of y relative to sum_j |a_ij x_j|: a and x are rounded to float (u each),
// each product rounds (u), and the row's sum of L terms rounds L - 1 times, with u = 2^-24;
// first order, plus one u of slack. Used by tests/kernels/test_vulkan_kernels.cpp.
constexpr double spmv_error_bound(int longest_row) { return (longest_row + 4) * 0x1p-24; }

// Records y = A x (both blocks with the same column count; y must not alias x).
void record_spmv(CommandRecorder& recorder, const VulkanMatrix& a, const VulkanVectors& x,
                 VulkanVectors& y);

}  // namespace harmonia::vulkan::detail
