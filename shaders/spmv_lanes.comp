#version 450
#extension GL_GOOGLE_include_directive : require
// y = A x for a CSR matrix with long rows: `lanes_per_row` consecutive invocations (one subgroup
// on the device, specialization constant 1) share a row, each summing a strided slice, then a
// fixed tree combines the slices. C++ side: kernels/spmv.h (SpmvPush).
#include "common/real.glsl"
#include "common/grid.glsl"
#include "common/tree_sum.glsl"

layout(constant_id = 1) const uint lanes_per_row = 8;

layout(std430, binding = 0) readonly buffer RowOffsets { uint row_offsets[]; };
layout(std430, binding = 1) readonly buffer Columns { uint columns[]; };
layout(std430, binding = 2) readonly buffer Values { real values[]; };
layout(std430, binding = 3) readonly buffer X { real x[]; };
layout(std430, binding = 4) writeonly buffer Y { real y[]; };

layout(push_constant) uniform Push {
  uint rows;
  uint x_rows;
} push;

void main() {
  const uint rows_per_group = gl_WorkGroupSize.x / lanes_per_row;
  const uint lane = gl_LocalInvocationID.x % lanes_per_row;
  const uint x_base = block_column() * push.x_rows;
  const uint y_base = block_column() * push.rows;
  // The loop bound depends on the workgroup only, so every invocation reaches the barriers.
  for (uint first_row = gl_WorkGroupID.x * rows_per_group; first_row < push.rows;
       first_row += gl_NumWorkGroups.x * rows_per_group) {
    const uint row = first_row + gl_LocalInvocationID.x / lanes_per_row;
    real sum = 0.0;
    if (row < push.rows) {
      for (uint entry = row_offsets[row] + lane; entry < row_offsets[row + 1];
           entry += lanes_per_row)
        sum += values[entry] * x[x_base + columns[entry]];
    }
    tree_sum(sum, lanes_per_row);
    if (lane == 0 && row < push.rows) y[y_base + row] = partial_sums[gl_LocalInvocationID.x];
    barrier();  // partial_sums is reused by the next rows.
  }
}
